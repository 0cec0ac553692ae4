// `welkin demo heritage` (apps/welkin/demo_heritage.cpp, heritage.cpp): the equinox, the Sun's
// day and the alignment day against published times and closed-form facts; the models turned to
// the demo's azimuths; the noon frame lit on the Sun's side; the command writing every image it
// announces, and refusing bad options with one line.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"
#include "gl_test_context.hpp"
#include "heritage.hpp"

#include <welkin/astro/bodies.hpp>
#include <welkin/astro/events.hpp>
#include <welkin/image.hpp>

#include <welkin_host/host_app.hpp>

#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <regex>
#include <sstream>

using namespace welkin;
using namespace welkin::heritage;

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

double secondsBetween(const UtcInstant& a, const UtcInstant& b) { return daysBetween(a.julianDate(), b.julianDate()) * 86400.0; }

const std::string kAssets = WELKIN_SOURCE_DIR "/apps/demos/heritage";
}  // namespace

TEST_CASE("Heritage demo: the next equinox matches the published instants", "[cpu][heritage]") {
    // Published equinoxes (USNO / IMCCE almanacs, to the minute): 2026 September 23 00:05 UTC,
    // 2027 March 20 20:25 UTC. 150 s: the minute's rounding (30 s) plus the Fast path's solar
    // longitude (~1", i.e. ~25 s of time) with margin.
    const UtcInstant sep = nextEquinox(UtcInstant::parse("2026-07-01T00:00:00Z"));
    CHECK(std::abs(secondsBetween(sep, UtcInstant::parse("2026-09-23T00:05:00Z"))) < 150.0);
    const UtcInstant mar = nextEquinox(UtcInstant::parse("2026-11-26T00:00:00Z"));
    CHECK(std::abs(secondsBetween(mar, UtcInstant::parse("2027-03-20T20:25:00Z"))) < 150.0);
    CHECK(dateOf(mar) == Date{2027, 3, 20});
    // At the instant found the longitude is 0 (mod 180 deg) to better than its hourly motion
    // (2.5'); 1e-4 rad = 21" is the bisection's half second of motion with a wide margin.
    CHECK(std::abs(std::sin(sunEclipticLongitudeRad(mar))) < 1e-4);
}

TEST_CASE("Heritage demo: the Sun's day at Kalabsha on the equinox", "[cpu][heritage]") {
    const SiteInfo& k = site("kalabsha");
    const SunDay day = sunDay(k, {2027, 3, 20});
    // Day length from the hour angle of sunrise, cos H0 = (sin h0 - sin phi sin delta) /
    // (cos phi cos delta) with h0 = -0.8333 deg and delta ~ 0: H0 = 90.91 deg, 12 h 07.3 min.
    // 90 s: delta moves ~0.4 deg a day (up to +-0.2 deg over the day, ~45 s of day length).
    const double phi = k.latitudeDeg * kDeg, h0 = -0.8333 * kDeg;
    const double expected = 2.0 * std::acos(std::sin(h0) / std::cos(phi)) / kDeg / 15.0 * 3600.0;
    CHECK(std::abs(secondsBetween(day.sunrise, day.sunset) - expected) < 90.0);
    // The culmination is on the meridian: the Sun due south (the Sun 66 deg up, moving ~0.6 deg
    // of azimuth a minute there; 0.2 deg is ~20 s of time, the search stops at 1 s).
    const SunPosition noon = sunPosition(k, day.noon);
    CHECK(std::abs(noon.azimuthDeg - 180.0) < 0.2);
    // ... at 90 - phi + delta: 66.04 deg plus ~0.01 deg of refraction; 0.3 deg for delta.
    CHECK(std::abs(noon.altitudeDeg - (90.0 - k.latitudeDeg)) < 0.3);
    // Night: 2 h after astronomical dusk, the Sun far below the horizon.
    CHECK(sunPosition(k, day.night).altitudeDeg < -30.0);
}

TEST_CASE("Heritage demo: the day the rising Sun lines up with an axis", "[cpu][heritage]") {
    const SiteInfo& k = site("kalabsha");
    const astro::Site where = astroSite(k);

    SECTION("Kalabsha's axis: twice a year, the nearest day by the events search") {
        const Alignment al = alignmentDays(where, 2027, k.axisAzimuthDeg);
        REQUIRE(al.exact);
        REQUIRE(al.days.size() == 2);
        // The solstices' rising azimuths at 24 N: cos Az = sin(23.44) / cos(23.96) -> 64.2 and
        // 115.8 deg (+ ~0.4 deg for the Sun's -0.83 deg altitude). 1 deg: that approximation.
        CHECK(std::abs(al.minAzimuthDeg - 64.2) < 1.0);
        CHECK(std::abs(al.maxAzimuthDeg - 115.8) < 1.0);
        for (const Sunrise& d : al.days) {
            // Independent check: the sunrise of that day from findDayEvents (the almanac
            // search), the Sun's apparent azimuth then from computeBody.
            auto azimuthOn = [&](const Date& date) {
                const UtcInstant start = UtcInstant::fromDateTime({date.year, date.month, date.day}).plusSeconds(-k.longitudeDeg / 15.0 * 3600.0);
                const astro::DayEvents ev = astro::findDayEvents(where, start, astro::Path::Fast);
                REQUIRE(ev.sunrise);
                const astro::BodyState s = astro::computeBody(astro::Body::Sun, astro::observerFrame(where, astro::timeScales(*ev.sunrise), astro::Path::Fast));
                return s.topo.azimuthRad / kDeg;
            };
            const double az = azimuthOn(d.date), before = azimuthOn(addDays(d.date, -1)), after = azimuthOn(addDays(d.date, 1));
            INFO(d.date.iso() << ": sunrise azimuth " << az << " (day before " << before << ", after " << after << ")");
            CHECK(std::abs(az - d.azimuthDeg) < 1e-6);  // the same instant by two searches
            // The nearest day: within half a day's swing of the axis (the swing is ~0.4 deg a
            // day near the equinoxes), and nearer than its neighbours.
            CHECK(std::abs(az - k.axisAzimuthDeg) <= 0.5 * std::abs(after - before) / 2.0 + 1e-3);
            CHECK(std::abs(az - k.axisAzimuthDeg) <= std::abs(before - k.axisAzimuthDeg));
            CHECK(std::abs(az - k.axisAzimuthDeg) <= std::abs(after - k.axisAzimuthDeg));
        }
        // 100 deg is south of east: the Sun's declination about -9.6 deg, in late February and
        // mid October.
        CHECK(al.days[0].date.month == 2);
        CHECK(al.days[1].date.month == 10);
    }

    SECTION("a due-east axis lines up at the equinoxes") {
        // On the equator the Sun rises due east when its declination is 0: the equinox day
        // (2027-03-20, 2027-09-23), within a day (the daily step).
        const astro::Site equator{.latitudeRad = 0.0, .longitudeRad = k.longitudeDeg * kDeg, .heightMeters = 0.0};
        const Alignment eq = alignmentDays(equator, 2027, 90.0);
        REQUIRE(eq.days.size() == 2);
        auto daysFrom = [](const Date& a, const Date& b) {  // a - b, days
            return daysBetween(toJulianDate({b.year, b.month, b.day}), toJulianDate({a.year, a.month, a.day}));
        };
        CHECK(std::abs(daysFrom(eq.days[0].date, {2027, 3, 20})) <= 1.0);
        CHECK(std::abs(daysFrom(eq.days[1].date, {2027, 9, 23})) <= 1.0);
        // At Kalabsha the -0.83 deg of sunrise moves it: sin delta = sin(h0) sin(phi), delta =
        // -0.34 deg, ~0.9 day before the March equinox and after the September one.
        const Alignment k90 = alignmentDays(where, 2027, 90.0);
        REQUIRE(k90.days.size() == 2);
        INFO("due east at Kalabsha: " << k90.days[0].date.iso() << ", " << k90.days[1].date.iso());
        CHECK(daysFrom(k90.days[0].date, {2027, 3, 20}) <= 0.0);
        CHECK(daysFrom(k90.days[0].date, {2027, 3, 20}) >= -2.0);
        CHECK(daysFrom(k90.days[1].date, {2027, 9, 23}) >= 0.0);
        CHECK(daysFrom(k90.days[1].date, {2027, 9, 23}) <= 2.0);
    }

    SECTION("an axis outside the year's range: the closest day, the winter solstice") {
        const Alignment far = alignmentDays(where, 2027, 130.0);
        CHECK_FALSE(far.exact);
        REQUIRE(far.days.size() == 1);
        // The southernmost sunrise: around 2027-12-22 (the solstice); +-4 days, where the
        // azimuth changes by < 0.02 deg a day.
        CHECK(far.days[0].date.month == 12);
        CHECK(std::abs(far.days[0].date.day - 22) <= 4);
    }
}

TEST_CASE("Heritage demo: the models are turned to the demo's azimuths", "[gl][heritage]") {
    test::glContext();
    for (const SiteInfo& s : sites()) {
        host::Scene scene;
        scene.load(kAssets + "/" + s.modelFile);
        const host::SceneNode* node = scene.findNode(s.buildingNode);
        REQUIRE(node);
        // The building's local +x (its axis) in the world: azimuth atan2(east, north).
        const glm::dvec3 axis = glm::dvec3(node->world[0]);
        const double az = std::fmod(std::atan2(axis.x, -axis.z) / kDeg + 360.0, 360.0);
        INFO(s.id << ": model axis " << az << " deg, demo " << s.axisAzimuthDeg << " deg");
        CHECK(std::abs(az - s.axisAzimuthDeg) < 1e-3);  // float quaternion: ~1e-5 deg
        // toWorld() agrees with the node's transform (1 mm over 100 m).
        const glm::dvec3 p = glm::dvec3(node->world * glm::vec4(-60.0f, 3.0f, 7.0f, 1.0f));
        CHECK(glm::length(p - toWorld(s, -60.0, 3.0, 7.0)) < 1e-3);
    }
}

TEST_CASE("Heritage demo: the noon frame has the building lit on the Sun's side", "[gl][heritage]") {
    test::glContext();
    const SiteInfo& k = site("kalabsha");
    host::AppOptions options;
    options.sceneFiles = {kAssets + "/" + k.modelFile};
    options.site = {k.latitudeDeg, k.longitudeDeg, k.heightM};
    options.shadows.halfExtentM = 150.0f;  // as the demo
    host::HostApp app(options, test::testLogger());
    app.sky().setAnimationTime(0.0);
    const UtcInstant noon = sunDay(k, {2027, 3, 20}).noon;
    // The demo's outside view (south-east of the pylon): it sees the south end of the pylon's
    // southern tower (facing azimuth ~190 deg, tilted up by the batter) and its front (facing the
    // axis, 100 deg).
    app.render(noon, camera(k, k.outside), 192, 108);
    const Image hdr = app.readHdr();
    auto luminanceAt = [&](const glm::dvec3& world) {
        const glm::dvec4 clip = app.viewProjection() * glm::dvec4(world, 1.0);
        REQUIRE(clip.w > 0.0);
        const int px = int(std::floor((clip.x / clip.w + 1.0) * 0.5 * hdr.width));
        const int py = int(std::floor((1.0 - clip.y / clip.w) * 0.5 * hdr.height));
        REQUIRE(px >= 1);
        REQUIRE(px + 1 < hdr.width);
        REQUIRE(py >= 1);
        REQUIRE(py + 1 < hdr.height);
        double sum = 0.0;  // a 3 x 3 box: the faces are 6-10 px across at this size
        for (int y = py - 1; y <= py + 1; ++y)
            for (int x = px - 1; x <= px + 1; ++x) sum += 0.2126 * hdr.at(x, y, 0) + 0.7152 * hdr.at(x, y, 1) + 0.0722 * hdr.at(x, y, 2);
        return sum / 9.0;
    };
    // Points on the faces (building frame, metres; the batter puts the south end at z = 16.53 at
    // y = 5 and the front at x = -0.2), 2 cm inside so that they lie on the face.
    const double sunny = luminanceAt(toWorld(k, -2.5, 5.0, 16.51));
    const double front = luminanceAt(toWorld(k, -0.22, 5.0, 9.5));
    INFO("south end " << sunny << " cd/m^2, front " << front << " cd/m^2, Sun " << sunPosition(k, noon).altitudeDeg << " deg up");
    // The Sun due south, 66 deg up: the south end gets E (cos 66 cos 10 + sin 66 sin 5) ~ 0.48 E
    // of sunlight, the front E cos 66 cos 80 ~ 0.07 E; both about 0.1 E of skylight. ~3x; 2x
    // leaves room for the sky's anisotropy and the forecourt's bounce, which the SH irradiance
    // does not know.
    CHECK(sunny > 2.0 * front);
    CHECK(std::isfinite(sunny));
}

TEST_CASE("Heritage demo: the command writes every image it announces", "[gl][heritage]") {
    const std::string dir = test::scratchDir("demo-heritage");
    const test::CliResult r =
        test::runCli("demo heritage --site kalabsha --date 2027-03-20 --size 96x64 --out '" + dir + "'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    // Every announced image exists and is a PNG of the asked size's bytes (non-empty).
    std::vector<std::string> announced;
    std::istringstream lines(r.output);
    for (std::string line; std::getline(lines, line);)
        if (line.rfind(dir + "/", 0) == 0) announced.push_back(line.substr(0, line.find("  ")));
    CHECK(announced.size() == 6);  // sunrise, noon, sunset, night, inside, alignment
    for (const auto& f : announced) {
        INFO(f);
        CHECK(std::filesystem::is_regular_file(f));
        CHECK(std::filesystem::file_size(f) > 100);
    }
    // Nothing else in the folder: no temporary files left behind.
    size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        INFO(e.path());
        CHECK(e.path().filename().string()[0] != '.');
        ++files;
    }
    CHECK(files == announced.size());
    // The noon image as written: the pylon's south end (sunlit) brighter than its front (the
    // same points as the noon test above, projected with the demo's camera at 96x64).
    {
        const SiteInfo& k = site("kalabsha");
        const Image img = readImage(dir + "/kalabsha-noon.png");
        REQUIRE(img.width == 96);
        const host::FlyCamera cam = camera(k, k.outside);
        const glm::dmat4 vp = cam.projection(96.0 / 64.0) * cam.view();
        auto linearLuminanceAt = [&](const glm::dvec3& world) {
            const glm::dvec4 clip = vp * glm::dvec4(world, 1.0);
            const int px = int(std::floor((clip.x / clip.w + 1.0) * 0.5 * img.width));
            const int py = int(std::floor((1.0 - clip.y / clip.w) * 0.5 * img.height));
            REQUIRE(px >= 0);
            REQUIRE(px < img.width);
            REQUIRE(py >= 0);
            REQUIRE(py < img.height);
            auto lin = [](double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
            return 0.2126 * lin(img.at(px, py, 0)) + 0.7152 * lin(img.at(px, py, 1)) + 0.0722 * lin(img.at(px, py, 2));
        };
        const double sunny = linearLuminanceAt(toWorld(k, -2.5, 5.0, 16.51)), front = linearLuminanceAt(toWorld(k, -0.22, 5.0, 9.5));
        INFO("noon image (display-linear): south end " << sunny << ", front " << front);
        // ~2.8x in radiance (the noon test); the tone curve is monotonic (its toe steepens the
        // darker face's fall: ~5x here), and one pixel of a 4-6 px face may mix in an edge:
        // 2x still separates sunlit from grazed.
        CHECK(sunny > 2.0 * front);
    }
    // The alignment days it states are those of alignmentDays().
    const Alignment al = alignmentDays(astroSite(site("kalabsha")), 2027, site("kalabsha").axisAzimuthDeg);
    for (const auto& d : al.days)
        CHECK(r.output.find("the Sun rises along Kalabsha's axis (azimuth 100.0 deg) on " + d.date.iso()) != std::string::npos);
}

TEST_CASE("Heritage demo: the default date is the next equinox", "[gl][heritage]") {
    // Kiti has no alignment image: this run renders nothing and states the date it chose.
    const std::string dir = test::scratchDir("demo-heritage-default-date");
    const test::CliResult r = test::runCli("demo heritage --site kiti --views alignment --out '" + dir + "'");
    INFO(r.output);
    REQUIRE(r.status == 0);
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    const UtcInstant today = UtcInstant::fromDateTime({tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min, 0.0});
    const Date expected = dateOf(nextEquinox(today));
    CHECK(r.output.find("date: " + expected.iso() + ", the ") != std::string::npos);
}

TEST_CASE("Heritage demo: bad options give one line and status 1", "[cpu][heritage]") {
    // Six cases: each run of the command costs ~2 s of start-up on the CI's 2 cores.
    const auto failures = test::badOptionFailures(
        "demo heritage", {
                             {"--date 2027-13-01", "--date '2027-13-01' must be a date YYYY-MM-DD with the year in [1000, 3000]"},
                             {"--date 2027-02-29", "--date '2027-02-29' must be a date"},
                             {"--site mars", "--site 'mars' is not one of kalabsha, kiti, all"},
                             {"--size 10x10", "--size '10x10' must be WxH with W and H in [16, 4096]"},
                             {"--views dawn", "--views 'dawn': 'dawn' is not one of"},
                             {"--clouds thick", "--clouds 'thick' is not one of none, fair, overcast"},
                         });
    std::string all;
    for (const auto& f : failures) all += f + "\n";
    INFO(all);
    CHECK(failures.empty());
}
