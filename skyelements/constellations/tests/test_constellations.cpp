// Constellations and the engine's text: the files parsed as they are written, lines through the
// stars' apparent places, labels at their figures, glyph metrics against the drawn pixels, finite
// output everywhere (with the equatorial grid over them where skyelements/grid is present; the
// grid's own pole and hour circles are tested in skyelements/grid/tests/test_grid_equatorial.cpp).
#include <catch2/catch.hpp>

#include "elements_present.hpp"
#include "gl_test_context.hpp"
#include "malta_night.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/astro/earth.hpp>
#include <welkin/astro/frames.hpp>
#include <welkin/astro/stars.hpp>
#include <welkin/astro/timescales.hpp>
#include <welkin/elements/constellations.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/gl/text.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>

using namespace welkin;
using namespace welkin::elements;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

bool haveKStars() {
    return std::filesystem::exists(kConstellationLinesFile) && std::filesystem::exists(kConstellationNamesFile) &&
           std::filesystem::exists(astro::kKStarsCatalogue);
}
bool haveFont() { return std::filesystem::exists(gl::kDefaultFontPath); }

using test::atMalta;
using test::fisheye;
using test::lum;
using Sky = test::MaltaSky;
const UtcInstant kWhen = test::kMaltaNight;
const double kLat = test::kMaltaLatRad, kLon = test::kMaltaLonRad;
Sky maltaSky() { return test::maltaSky(); }

// Draws one string with the engine's text API, as an element would.
class TextProbe final : public SkyElement {
public:
    TextProbe(std::string text, gl::TextStyle style) : SkyElement("text_probe"), text_(std::move(text)), style_(style) {}
    gl::Font font;
    std::optional<glm::vec3> direction;  // anchor on the GPU (addAt) instead of the image centre

private:
    void doInit(InitContext&) override { font = gl::Font::load(); }
    void doRender(const FrameContext& ctx) override {
        if (direction) batch_.addAt(font, *direction, text_, style_);
        else batch_.add(font, glm::vec4(0, 0, 1, 1), text_, style_);  // the image centre
        batch_.draw(font);
        if (ctx.emptyVao) ctx.emptyVao->bind();
    }
    void doRelease() override {
        font = gl::Font();
        batch_ = gl::TextBatch();
    }
    std::string text_;
    gl::TextStyle style_;
    gl::TextBatch batch_;
};

// One string drawn by a TextProbe alone at the centre of a w x h perspective frame (no
// astronomy): the processor (which owns the probe and its font), the camera and the HDR image
// (cd/m^2). `anchorOnGpu`: anchored by the camera's forward direction, projected on the GPU.
struct TextFrame {
    std::unique_ptr<SkyProcessor> processor;
    TextProbe* probe = nullptr;
    Camera camera;
    Image image;
};
TextFrame drawText(const std::string& text, const gl::TextStyle& style, int w, int h, bool anchorOnGpu = false) {
    TextFrame f;
    f.processor = std::make_unique<SkyProcessor>(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false});
    f.camera.projection = Projection::Perspective;
    f.camera.width = w;
    f.camera.height = h;
    f.processor->setCamera(f.camera);
    auto probe = std::make_unique<TextProbe>(text, style);
    if (anchorOnGpu) probe->direction = glm::vec3(f.camera.basis()[2]);
    f.probe = probe.get();
    f.processor->add(std::move(probe));
    f.processor->renderFrame();
    f.image = f.processor->readHdr();
    return f;
}
}  // namespace

TEST_CASE("Constellations: clines.dat and cnames.dat parse as the files are written", "[cpu][constellations]") {
    if (!haveKStars()) FAIL("kstars-data is not installed (/usr/share/kstars/clines.dat, cnames.dat, stars.dat)" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    const auto figures = loadConstellationLines(kConstellationLinesFile, "Western");
    // The Western culture of kstars-data: 89 "# Name" figures with lines (Serpens in two) and 659
    // "D" records, each one segment (both counted independently with grep/awk on the file).
    size_t segments = 0;
    for (const auto& f : figures)
        for (const auto& poly : f.polylines) segments += poly.size() - 1;
    CHECK(segments == 659);
    CHECK(figures.size() == 89);
    auto figure = [&](const std::vector<ConstellationFigure>& fs, const std::string& name) -> const ConstellationFigure& {
        auto it = std::find_if(fs.begin(), fs.end(), [&](const ConstellationFigure& f) { return f.name == name; });
        REQUIRE(it != fs.end());
        return *it;
    };
    auto connected = [](const ConstellationFigure& f, int a, int b) {
        for (const auto& poly : f.polylines)
            for (size_t i = 1; i < poly.size(); ++i)
                if ((poly[i - 1] == a && poly[i] == b) || (poly[i - 1] == b && poly[i] == a)) return true;
        return false;
    };
    // Orion's belt: Alnitak (HD 37742) - Alnilam (HD 37128) - Mintaka (HD 36486), in the
    // Asterisms culture; the Western figure joins Mintaka to Rigel (HD 34085) and Alnitak to
    // Betelgeuse (HD 39801) instead (the IAU figure's outline).
    const auto asterisms = loadConstellationLines(kConstellationLinesFile, "asterisms");
    const auto& belt = figure(asterisms, "Orion's Belt");
    CHECK(connected(belt, 37742, 37128));
    CHECK(connected(belt, 37128, 36486));
    CHECK_FALSE(connected(belt, 37742, 36486));
    const auto& orion = figure(figures, "Orion");
    CHECK(connected(orion, 36486, 34085));
    CHECK(connected(orion, 37742, 39801));

    const auto names = loadConstellationNames(kConstellationNamesFile, "Western");
    CHECK(names.size() == 89);  // the 88 IAU constellations, Serpens in two parts
    auto ori = std::find_if(names.begin(), names.end(), [](const ConstellationLabel& l) { return l.abbreviation == "Ori"; });
    REQUIRE(ori != names.end());
    CHECK(ori->name == "Orion");
    CHECK(ori->raJ2000Rad == Approx(5.6667 * 15 * kDeg).margin(1e-4));  // "054000+030000"
    CHECK(ori->decJ2000Rad == Approx(3.0 * kDeg).margin(1e-9));
    auto cvn = std::find_if(names.begin(), names.end(), [](const ConstellationLabel& l) { return l.abbreviation == "CVn"; });
    REQUIRE(cvn != names.end());
    CHECK(cvn->name == "Canes Venatici");
    CHECK(cvn->decJ2000Rad == Approx((42 + 30 / 60.0) * kDeg).margin(1e-9));  // "+423000"

    // Errors name the source, the line and the problem.
    CHECK_THROWS_WITH(parseConstellationLines("C Western\nM 12\nX 7\n", "t.dat", "Western"), Catch::Contains("t.dat:3: expected 'M <HD>'"));
    CHECK_THROWS_WITH(parseConstellationLines("C Western\nD abc\n", "t.dat", "Western"), Catch::Contains("t.dat:2: bad HD number"));
    CHECK_THROWS_WITH(parseConstellationLines("C Western\nM 1\n", "t.dat", "Klingon"), Catch::Contains("no sky culture 'Klingon' (the file has: Western)"));
    CHECK_THROWS_WITH(parseConstellationNames("C Western\n05x000+030000Ori ORION\n", "n.dat", "Western"), Catch::Contains("n.dat:2: expected digits"));
    CHECK_THROWS_WITH(loadConstellationLines("/nonexistent/clines.dat", "Western"), Catch::Contains("cannot read '/nonexistent/clines.dat'"));
}

TEST_CASE("Constellations: every sky culture of the files parses", "[cpu][constellations]") {
    if (!haveKStars()) FAIL("kstars-data is not installed" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    // The cultures listed by the files' own "C <name>" lines; each has figures and names.
    std::ifstream in(kConstellationLinesFile);
    std::string line;
    std::vector<std::string> cultures;
    while (std::getline(in, line))
        if (line.rfind("C ", 0) == 0) cultures.push_back(line.substr(2));
    REQUIRE(cultures.size() >= 10);
    for (const std::string& c : cultures) {
        INFO(c);
        const auto figures = loadConstellationLines(kConstellationLinesFile, c);
        CHECK(!figures.empty());
        CHECK(!loadConstellationNames(kConstellationNamesFile, c).empty());
    }
}

TEST_CASE("Constellations: the figures' stars resolve against the catalogue", "[cpu][constellations]") {
    if (!haveKStars()) FAIL("kstars-data is not installed" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    const std::vector<astro::Star> stars = loadConstellationStars();
    int unresolved = -1;
    const auto segs = resolveConstellationSegments(loadConstellationLines(kConstellationLinesFile, "Western"), stars, &unresolved);
    // The HD numbers of the Western figures are found in stars.dat through namedstars.dat and
    // unnamedstars.dat or, for 7 close doubles, in the binary files' own records; all but two
    // (kstars-data 3.6: HD 20794 = e Eri and HD 98230 = xi UMa are in none of its HD-bearing
    // files), which take out 3 of the 659 segments.
    CHECK(unresolved == 2);
    CHECK(segs.size() == 656);
    // Izar (eps Boo, HD 129988), a double that stars.dat and namedstars.dat place > 6" apart, is
    // one of them: its Boötes segments are drawn.
    CHECK(std::count_if(segs.begin(), segs.end(), [](const ConstellationSegment& s) { return s.hdA == 129988 || s.hdB == 129988; }) == 2);
    // The binary records stand in at their own J2000 places: Sirius (HD 48915) in namedstars.dat
    // lies within 1" of its J2000 position (Hipparcos 2007: RA 101.287155 deg, Dec -16.716116 deg;
    // the file's J1991.25 position carried by its -546/-1223 mas/yr proper motion).
    const auto named = astro::loadKStarsBinaryStars("/usr/share/kstars/namedstars.dat");
    auto sirius = std::find_if(named.begin(), named.end(), [](const astro::Star& s) { return s.hd == 48915; });
    REQUIRE(sirius != named.end());
    const glm::dvec3 siriusRef = astro::directionFromRaDec(101.287155 * kDeg, -16.716116 * kDeg);
    CHECK(std::acos(std::min(1.0, glm::dot(astro::starDirectionJ2000(*sirius), siriusRef))) < 1.0 / 3600 * kDeg);
    CHECK(sirius->magnitudeV == Approx(-1.44).margin(0.1));
    // Betelgeuse (HD 39801) to Alnitak (HD 37742): 9.2 deg apart on the sky (their J2000
    // positions, 05h55m10s +07d24' and 05h40m46s -01d56', by the spherical law of cosines).
    auto it = std::find_if(segs.begin(), segs.end(), [](const ConstellationSegment& s) {
        return (s.hdA == 39801 && s.hdB == 37742) || (s.hdA == 37742 && s.hdB == 39801);
    });
    REQUIRE(it != segs.end());
    const double ra1 = (5 + 55 / 60.0 + 10.3 / 3600) * 15 * kDeg, de1 = (7 + 24 / 60.0 + 25 / 3600.0) * kDeg;
    const double ra2 = (5 + 40 / 60.0 + 45.5 / 3600) * 15 * kDeg, de2 = -(1 + 56 / 60.0 + 34 / 3600.0) * kDeg;
    const double expected = std::acos(std::sin(de1) * std::sin(de2) + std::cos(de1) * std::cos(de2) * std::cos(ra1 - ra2));
    CHECK(std::acos(glm::dot(it->a, it->b)) == Approx(expected).margin(10.0 / 3600 * kDeg));  // 10": the catalogue's rounding
}

TEST_CASE("Text: glyph metrics, and a drawn string's box matches its layout", "[gl][constellations][text]") {
    if (!haveFont()) FAIL("DejaVu Sans is not installed (fonts-dejavu-core)" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    test::glContext();
    CHECK_THROWS_WITH(gl::Font::load({.path = "/nonexistent.ttf"}), Catch::Contains("cannot open font '/nonexistent.ttf'"));
    CHECK_THROWS_WITH(gl::Font::load({.rasterPx = 4}), Catch::Contains("rasterPx 4 not in [8, 256]"));
    const gl::Font font = gl::Font::load();
    const float em = float(font.rasterPx());
    // DejaVu Sans: cap height 0.729 em, x-height 0.547 em, 'M' advance 0.863 em, 'i' 0.278 em,
    // ascender 0.928 em (its hhea table); rasterised sizes within a pixel (hinting rounds to whole pixels).
    CHECK(std::abs(font.glyph(U'H').size.y - 0.729f * em) <= 1.0f);
    CHECK(std::abs(font.glyph(U'x').size.y - 0.547f * em) <= 1.0f);
    CHECK(std::abs(font.glyph(U'M').advance - 0.863f * em) <= 1.0f);
    CHECK(std::abs(font.glyph(U'i').advance - 0.278f * em) <= 1.0f);
    CHECK(std::abs(font.ascender() - 0.928f * em) <= 1.0f);
    CHECK(font.descender() < 0.0f);
    CHECK(font.glyph(U' ').size == glm::ivec2(0));
    CHECK(font.glyph(U' ').advance > 0.0f);
    CHECK(font.glyph(U'g').bearing.y < font.glyph(U'g').size.y);  // a descender below the baseline
    CHECK(font.has(U'\u00f6'));                                     // Latin-1: o umlaut
    CHECK(font.glyph(U'\u4e2d').advance == font.glyph(U'?').advance);  // outside the atlas: '?'
    // measure(): the advance is the sum of the glyphs' advances at the scale.
    const gl::TextExtent e = font.measure("Cygnus", 24);
    float sum = 0;
    for (char32_t c : std::u32string(U"Cygnus")) sum += font.glyph(c).advance * 24 / em;
    CHECK(e.advance == Approx(sum).epsilon(1e-6));
    CHECK(e.inkMax.x <= e.advance + 1.0f);
    CHECK_THROWS_WITH(font.measure("x", 0), Catch::Contains("pixelSize 0.000000 not in (0, 1024]"));
    {
        gl::TextBatch b;
        CHECK_THROWS_WITH(b.add(font, glm::vec4(0, 0, 1, 1), "x", {.pixelSize = 2000}), Catch::Contains("TextBatch::add(): pixelSize 2000"));
        CHECK_THROWS_WITH(b.addAt(font, glm::vec3(0), "x"), Catch::Contains("TextBatch::addAt(): direction is zero or not finite"));
        b.add(font, glm::vec4(0, 0, 1, -1), "behind");  // w < 0: not visible, nothing queued
        CHECK(b.quads() == 0);
        b.add(font, glm::vec4(0, 0, 1, 1), "a b");  // a space has no quad
        CHECK(b.quads() == 2);
    }

    for (float size : {48.0f, 20.0f}) {  // the atlas' own size, and scaled down through the mipmaps
        const std::string text = "Hyades Wg";
        gl::TextStyle style;
        style.pixelSize = size;
        style.luminanceCdM2 = 100;
        const TextFrame frame = drawText(text, style, 320, 96);
        const Image& img = frame.image;
        const TextProbe* probePtr = frame.probe;
        // The ink box drawn: pixels at more than 10 % coverage.
        int x0 = 1 << 20, y0 = 1 << 20, x1 = -1, y1 = -1;
        double peak = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                const double L = lum(img, x, y);
                peak = std::max(peak, L);
                if (L > 10.0) {
                    x0 = std::min(x0, x);
                    y0 = std::min(y0, y);
                    x1 = std::max(x1, x + 1);
                    y1 = std::max(y1, y + 1);
                }
            }
        REQUIRE(x1 > x0);
        // Full coverage inside the strokes emits the style's luminance (white: luminance 1): at the
        // atlas' own size exactly, to the R8 atlas' 1/255 step; scaled down, a mip texel averages
        // a stroke with its edge, so the peak may fall a little short (never above).
        if (size == 48.0f) CHECK(peak == Approx(100.0).epsilon(0.005));
        CHECK(peak <= 100.0 * 1.0001);
        CHECK(peak > 85.0);
        // The predicted box: anchor (160, 48), centred on the advance x ascender..descender box.
        const gl::TextExtent m = probePtr->font.measure(text, size);
        // The pen's origin is put on a whole pixel (TextBatch::add()).
        const glm::vec2 pen = glm::vec2(160.0f, 48.0f) + glm::round(glm::vec2(-0.5f * m.advance, m.ascender - 0.5f * (m.ascender - m.descender)));
        const glm::vec2 lo = pen + m.inkMin, hi = pen + m.inkMax;
        INFO("size " << size << ": drawn [" << x0 << ", " << x1 << "] x [" << y0 << ", " << y1 << "], layout [" << lo.x << ", " << hi.x
                     << "] x [" << lo.y << ", " << hi.y << "]");
        // Within a pixel: the glyph bitmaps' edge texels are partly covered (FreeType's
        // antialiasing), so a 10 % threshold can land a pixel inside or outside the bitmap's box.
        CHECK(std::abs(x0 - lo.x) <= 1.0f);
        CHECK(std::abs(x1 - hi.x) <= 1.0f);
        CHECK(std::abs(y0 - lo.y) <= 1.0f);
        CHECK(std::abs(y1 - hi.y) <= 1.0f);
        // The same string anchored by a direction projected on the GPU (addAt): the camera's
        // forward direction lands on the image centre, so the same pixels to float rounding.
        {
            const Image img2 = drawText(text, style, 320, 96, true).image;
            double maxDiff = 0;
            for (size_t i = 0; i < img.pixels.size(); ++i) maxDiff = std::max(maxDiff, double(std::abs(img.pixels[i] - img2.pixels[i])));
            CHECK(maxDiff < 1e-3);  // 1e-5 of the luminance: identical coverage
        }
        // And the string's drawn width against its advance: advance minus the first glyph's left
        // bearing and the last one's right side bearing.
        const float s = size / em;
        const gl::Glyph& H = probePtr->font.glyph(U'H');
        const gl::Glyph& g = probePtr->font.glyph(U'g');
        const float inkFromAdvance = m.advance - H.bearing.x * s - (g.advance - g.bearing.x - g.size.x) * s;
        CHECK(std::abs(float(x1 - x0) - inkFromAdvance) <= 1.0f);
    }
}

TEST_CASE("Text: a glyph thinner than a pixel (the minus sign at 11 px) is still drawn", "[gl][constellations][text]") {
    if (!haveFont()) FAIL("DejaVu Sans is not installed (fonts-dejavu-core)" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    test::glContext();
    // A hyphen at 11 px is a bar about 0.9 px high: drawn as laid out, its quad can miss every
    // pixel centre and the label "Mars -2.2" loses its sign. At every size from 9 to 14 px in
    // quarter pixels (the pen is on a whole pixel, so the size sets where the bar falls between
    // pixel centres), its ink must reach the image, carrying about the bar's area: the sum of its
    // pixels' coverage within 50 % of the glyph's area on screen (the filtered footprint spreads
    // it, it does not create or lose much of it).
    for (int q = 0; q <= 20; ++q) {
            const float size = 9.0f + 0.25f * float(q);
            gl::TextStyle style;
            style.pixelSize = size;
            style.luminanceCdM2 = 100;
            const TextFrame frame = drawText("-", style, 64, 32);
            const Image& img = frame.image;
            const TextProbe* probePtr = frame.probe;
            double coverage = 0;  // in pixels: luminance / 100 cd/m^2 summed
            for (int y = 0; y < img.height; ++y)
                for (int x = 0; x < img.width; ++x) coverage += (0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2)) / 100.0;
            const gl::Glyph& g = probePtr->font.glyph(U'-');
            const double s = size / float(probePtr->font.rasterPx());
            const double area = double(g.size.x) * s * double(g.size.y) * s;
            INFO("size " << size << " px: coverage " << coverage << " px, the glyph's area " << area << " px");
            CHECK(coverage > 0.5 * area);
            CHECK(coverage < 1.5 * area);
        }
}

TEST_CASE("Constellations: lines pass within 1 px of their stars (Malta, 1024 fisheye and perspective)", "[gl][constellations]") {
    if (!haveKStars() || !haveFont()) FAIL("kstars-data or DejaVu Sans is not installed" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    test::glContext();
    // The 1024-px fisheye, and a 50-deg perspective view centred on Cygnus (pinhole: the
    // arcs are straight lines, drawn through the near-plane clipping path).
    Camera persp;
    persp.projection = Projection::Perspective;
    persp.width = 1024;
    persp.height = 768;
    persp.verticalFovRad = 50 * kDeg;
    {
        const glm::dvec2 azAlt = azAltFromDirection(maltaSky().apparent(astro::directionFromRaDec(305.557 * kDeg, 40.257 * kDeg)));  // gamma Cyg
        persp.azimuthRad = azAlt.x;
        persp.altitudeRad = azAlt.y;
    }
    for (const Camera& cam : {fisheye(1024), persp}) {
    INFO(toString(cam.projection));
    SkyProcessor p;
    atMalta(p, cam);
    p.add(makeElement("constellations"));
    p.vars().set(constellationkeys::labels, std::string("none"));
    p.vars().set(constellationkeys::lineLuminance, 1.0);
    p.vars().set(constellationkeys::lineColour, glm::dvec3(1.0));
    p.renderFrame();
    Image img = p.readHdr();
    // Cygnus stands near the zenith at local midnight in August.
    const std::vector<astro::Star> stars = loadConstellationStars();
    auto figures = loadConstellationLines(kConstellationLinesFile, "Western");
    std::erase_if(figures, [](const ConstellationFigure& f) { return f.name != "Cygnus"; });
    const auto segs = resolveConstellationSegments(figures, stars);
    REQUIRE(segs.size() == 7);  // clines.dat's Western Cygnus: two polylines of 3 and 4 segments
    const Sky sky = maltaSky();
    int checked = 0;
    for (const ConstellationSegment& s : segs)
        for (int end = 0; end < 2; ++end) {
            const glm::dvec3 star = end == 0 ? s.a : s.b, other = end == 0 ? s.b : s.a;
            const glm::dvec3 d = sky.apparent(star);
            REQUIRE(d.z > std::sin(20 * kDeg));
            const glm::dvec2 ps = *cam.pixelOf(d), po = *cam.pixelOf(sky.apparent(other));
            const glm::dvec2 u = glm::normalize(po - ps), n(-u.y, u.x);
            // Skip an end where another line leaves the same star within 45 deg of this one (its
            // pixels would share the window).
            bool crowded = false;
            for (const ConstellationSegment& t : segs) {
                if (&t == &s) continue;
                const glm::dvec3 o = glm::length(t.a - star) < 1e-9 ? t.b : glm::length(t.b - star) < 1e-9 ? t.a : glm::dvec3(0.0);
                if (o == glm::dvec3(0.0)) continue;
                const glm::dvec2 v = glm::normalize(*cam.pixelOf(sky.apparent(o)) - ps);
                if (glm::dot(u, v) > std::cos(45 * kDeg)) crowded = true;
            }
            if (crowded) continue;
            // The line's cross-section 6 px from the star (the arc is straight over 6 px: its
            // curvature on this fisheye is < 0.01 px there): luminance-weighted offset across it.
            const glm::dvec2 q = ps + 6.0 * u;
            double w = 0, off = 0;
            for (int y = int(q.y) - 5; y <= int(q.y) + 5; ++y)
                for (int x = int(q.x) - 5; x <= int(q.x) + 5; ++x) {
                    const glm::dvec2 c = glm::dvec2(x + 0.5, y + 0.5) - q;
                    if (std::abs(glm::dot(c, u)) > 1.5 || std::abs(glm::dot(c, n)) > 4.0) continue;
                    const double L = lum(img, x, y);
                    w += L;
                    off += L * glm::dot(c, n);
                }
            INFO("segment HD " << s.hdA << " - HD " << s.hdB << " end " << end << " at " << ps.x << ", " << ps.y);
            // A 1.5-px line of luminance 1 over a 3-px stretch: ~4.5 (half of it guards against a gap).
            REQUIRE(w > 2.0);
            CHECK(std::abs(off / w) < 1.0);  // the 1 px
            // And it reaches the star: the pixel under the star is lit (the line runs 0.75 px past it).
            CHECK(lum(img, int(ps.x), int(ps.y)) > 0.3);
            ++checked;
        }
    CHECK(checked >= 6);
    nlohmann::json j = p.stats();
    CHECK(j["constellations"]["segments"].get<int>() == 656);  // as the [cpu] resolution test
    CHECK(j["constellations"]["unresolved_stars"].get<int>() == 2);
    }
}

TEST_CASE("Constellations: a label is drawn centred on its figure's position", "[gl][constellations]") {
    if (!haveKStars() || !haveFont()) FAIL("kstars-data or DejaVu Sans is not installed" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    test::glContext();
    const Camera cam = fisheye(1024);
    SkyProcessor p;
    atMalta(p, cam);
    p.add(makeElement("constellations"));
    p.vars().set(constellationkeys::lines, false);
    p.vars().set(constellationkeys::labels, std::string("abbreviation"));
    p.vars().set(constellationkeys::labelLuminance, 1.0);
    p.vars().set(constellationkeys::labelSize, 20.0);
    p.renderFrame();
    Image img = p.readHdr();
    const Sky sky = maltaSky();
    const auto names = loadConstellationNames(kConstellationNamesFile, "Western");
    int checked = 0;
    for (const char* abbr : {"Cyg", "Lyr", "Aql", "Her"}) {
        auto it = std::find_if(names.begin(), names.end(), [&](const ConstellationLabel& l) { return l.abbreviation == abbr; });
        REQUIRE(it != names.end());
        const glm::dvec3 icrs = astro::directionFromRaDec(it->raJ2000Rad, it->decJ2000Rad);
        const glm::dvec2 c = *cam.pixelOf(sky.apparent(icrs));
        // Ink centroid within 40 px of the anchor (labels of neighbouring figures are further away).
        double w = 0;
        glm::dvec2 m(0.0);
        for (int y = int(c.y) - 40; y <= int(c.y) + 40; ++y)
            for (int x = int(c.x) - 40; x <= int(c.x) + 40; ++x) {
                const double L = lum(img, x, y);
                w += L;
                m += L * glm::dvec2(x + 0.5, y + 0.5);
            }
        INFO(abbr << " anchor " << c.x << ", " << c.y);
        REQUIRE(w > 5.0);  // a 3-letter label at 20 px covers ~100 px
        m /= w;
        // The string is centred on its advance box (not its ink): its ink centroid differs by the
        // glyphs' shapes, a fraction of the em (20 px): within 0.3 em horizontally and vertically.
        CHECK(std::abs(m.x - c.x) < 6.0);
        CHECK(std::abs(m.y - c.y) < 6.0);
        ++checked;
    }
    CHECK(checked == 4);
}

// The grid (by name, where its folder is present) draws over the same frames: the two overlays'
// GL state together.
TEST_CASE("Constellations and the equatorial grid: every pixel finite at FOV 0.5 and 180 deg, 1x1 to 2048x2048",
          "[gl][constellations]") {
    if (!haveKStars() || !haveFont()) FAIL("kstars-data or DejaVu Sans is not installed" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    test::glContext();
    // 2048 rather than 4096: a 4096^2 float read-back is 256 MB on llvmpipe; nothing in the
    // shaders depends on the size beyond the viewport.
    struct Case { Projection proj; double fov; int size; };
    for (Case k : {Case{Projection::Perspective, 0.5 * kDeg, 1}, Case{Projection::Perspective, 0.5 * kDeg, 2048},
                   Case{Projection::Perspective, 179 * kDeg, 512}, Case{Projection::Fisheye, 0, 1}, Case{Projection::Fisheye, 0, 2048},
                   Case{Projection::Equirect, 0, 1}, Case{Projection::Equirect, 0, 1024}}) {
        SkyProcessor p;
        Camera cam;
        cam.projection = k.proj;
        cam.altitudeRad = 1.2;
        cam.azimuthRad = 0.3;
        if (k.fov > 0) cam.verticalFovRad = k.fov;
        cam.width = cam.height = k.size;
        atMalta(p, cam);
        p.add(makeElement("constellations"));
#ifdef WELKIN_HAS_ELEMENT_grid
        p.add(makeElement("grid"));
        p.vars().setFromString("grid.frame", "both");
#endif
        p.renderFrame();
        Image img = p.readHdr();
        size_t bad = 0;
        double total = 0;
        for (float v : img.pixels) {
            bad += !std::isfinite(v) || v < 0;
            total += v;
        }
        INFO(toString(k.proj) << " " << k.size);
        CHECK(bad == 0);
        if (k.size >= 512 && (k.fov == 0 || k.fov > 90 * kDeg)) CHECK(total > 0);  // wide views show lines (a 0.5-deg one may not)
    }
}

TEST_CASE("Constellations: the equirect seam and options", "[gl][constellations]") {
    if (!haveKStars() || !haveFont()) FAIL("kstars-data or DejaVu Sans is not installed" << ": install it (scripts/setup.sh installs it; a missing file fails, never skips)");
    test::glContext();
    Camera cam;
    cam.projection = Projection::Equirect;
    cam.width = 720;
    cam.height = 360;
    SkyProcessor p;
    atMalta(p, cam);
    p.add(makeElement("constellations"));
    p.vars().set(constellationkeys::labels, std::string("none"));
    p.vars().set(constellationkeys::lineLuminance, 1.0);
    p.renderFrame();
    Image img = p.readHdr();
    // No line crosses the whole image: a piece that straddles the seam is drawn as two short
    // pieces at the edges, not one across. The middle rows' total in any column stays below a
    // horizontal line's (a wrapped piece would light ~every column of its row).
    int longest = 0;
    for (int y = 0; y < img.height; ++y) {
        int run = 0;
        for (int x = 0; x < img.width; ++x) {
            run = lum(img, x, y) > 0.05 ? run + 1 : 0;
            longest = std::max(longest, run);
        }
    }
    CHECK(longest < 200);  // the longest near-horizontal arc of a figure spans < 100 deg (< 200 px)
    // Below the horizon nothing by default (but a line's width and end caps, 1.75 px = 0.9 deg
    // here: rows from 184, altitude < -2 deg, are checked); with constellations.below_horizon the
    // southern figures appear there.
    auto below = [](const Image& im) {
        double sum = 0;
        for (int y = im.height / 2 + 4; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x) sum += lum(im, x, y);
        return sum;
    };
    CHECK(below(img) == 0.0);
    p.vars().set(constellationkeys::belowHorizon, true);
    p.renderFrame();
    CHECK(below(p.readHdr()) > 100.0);  // hundreds of lit pixels (luminance 1 each)
    CHECK_THROWS_WITH(p.vars().set(constellationkeys::labels, std::string("both")),
                      "key 'constellations.labels': 'both' is not one of name, abbreviation, none");
}
