// Star catalogue loaders: kstars-data stars.dat, Yale Bright Star Catalogue (BSC5), HYG CSV
// (through the shared CSV reader, csv.hpp).
// Every parse error names the source and the 1-based line: "file:line: message".
#include <welkin/astro/stars.hpp>
#include <welkin/csv.hpp>
#include <welkin/error.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string_view>

namespace welkin::astro {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct LineError {
    const std::string& source;
    size_t line;
    [[noreturn]] void operator()(const std::string& what) const {
        throw Error(source + ":" + std::to_string(line) + ": " + what);
    }
};

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

// Parses a whole (trimmed) field as a double; a leading '+' is allowed.
bool parseDouble(std::string_view s, double& out) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    if (s.empty()) return false;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && p == s.data() + s.size() && std::isfinite(out);
}

double field(std::string_view line, size_t begin, size_t length, const char* name, const LineError& fail) {
    if (line.size() < begin + length) fail(std::string("line too short for ") + name);
    double v;
    if (!parseDouble(line.substr(begin, length), v))
        fail(std::string("bad ") + name + " '" + std::string(line.substr(begin, length)) + "'");
    return v;
}

// Optional numeric field: blank -> fallback.
double optionalField(std::string_view line, size_t begin, size_t length, double fallback, const char* name, const LineError& fail) {
    if (line.size() <= begin) return fallback;
    std::string_view s = trim(line.substr(begin, std::min(length, line.size() - begin)));
    if (s.empty()) return fallback;
    double v;
    if (!parseDouble(s, v)) fail(std::string("bad ") + name + " '" + std::string(s) + "'");
    return v;
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("astro: cannot read star catalogue '" + path + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

template <class F>
void forEachLine(const std::string& text, F&& f) {
    size_t pos = 0, line = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        std::string_view l(text.data() + pos, end - pos);
        if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
        f(l, ++line);
        pos = end + 1;
    }
}

// A catalogue quantity stored as float: finite there too (|v| <= 1e30 is far beyond any star's
// magnitude, colour or proper motion; a larger value would become inf, or undefined as an int).
float asFloat(double v, const char* name, const LineError& fail) {
    char buf[32];
    std::snprintf(buf, sizeof buf, " %g", v);
    if (!(std::abs(v) <= 1e30)) fail(std::string(name) + buf + " out of range (|value| <= 1e30)");
    return float(v);
}
// A HIP or HD number: a whole number in [0, 2^31 - 1] (0: unknown).
int asCatalogueNumber(double v, const char* name, const LineError& fail) {
    char buf[32];
    std::snprintf(buf, sizeof buf, " %g", v);
    if (!(v >= 0.0 && v <= 2147483647.0 && v == std::floor(v)))
        fail(std::string(name) + buf + " is not a catalogue number (a whole number in [0, 2147483647])");
    return int(v);
}

void checkRaDec(double ra, double dec, const LineError& fail) {
    if (!(ra >= 0 && ra < 2 * std::numbers::pi + 1e-9)) fail("right ascension out of [0, 24h)");
    if (!(dec >= -std::numbers::pi / 2 - 1e-9 && dec <= std::numbers::pi / 2 + 1e-9)) fail("declination out of [-90, 90] deg");
}

}  // namespace

// kstars stars.dat columns (0-based): RA hhmmss.ss [0,9), Dec sddmmss.s [10,19), pmRA* [20,29) and
// pmDec [29,38) in mas/yr, parallax mas [38,45), magnitude [45,51), B-V [51,56), spectral type
// [56,58), ...; optional ", genetive name, long name" from the first comma.
std::vector<Star> parseKStarsCatalogue(const std::string& text, const std::string& source, double maxMagnitude) {
    std::vector<Star> stars;
    forEachLine(text, [&](std::string_view l, size_t lineNo) {
        if (trim(l).empty() || l.front() == '#') return;
        LineError fail{source, lineNo};
        if (l.size() < 56) fail("line too short (" + std::to_string(l.size()) + " characters, expected at least 56)");
        Star s;
        const double ra = field(l, 0, 9, "RA hhmmss.ss", fail);
        const double dec = field(l, 10, 9, "Dec sddmmss.s", fail);
        const double raH = std::floor(ra / 10000.0), raM = std::floor((ra - raH * 10000.0) / 100.0), raS = ra - raH * 10000.0 - raM * 100.0;
        const double ad = std::abs(dec);
        const double dD = std::floor(ad / 10000.0), dM = std::floor((ad - dD * 10000.0) / 100.0), dS = ad - dD * 10000.0 - dM * 100.0;
        // stars.dat has a dozen rounded "60.00" seconds: accepted (they carry), more is an error.
        if (raM >= 60 || raS > 60 || dM >= 60 || dS > 60) fail("minutes >= 60 or seconds > 60 in RA/Dec");
        s.raJ2000Rad = (raH + raM / 60.0 + raS / 3600.0) * 15.0 * kDeg;
        s.decJ2000Rad = (dD + dM / 60.0 + dS / 3600.0) * kDeg * (l[10] == '-' ? -1.0 : 1.0);
        checkRaDec(s.raJ2000Rad, s.decJ2000Rad, fail);
        s.pmRaMasPerYear = asFloat(field(l, 20, 9, "pmRA", fail), "pmRA", fail);
        s.pmDecMasPerYear = asFloat(field(l, 29, 9, "pmDec", fail), "pmDec", fail);
        s.magnitudeV = asFloat(field(l, 45, 6, "magnitude", fail), "magnitude", fail);
        s.colorBV = asFloat(field(l, 51, 5, "B-V", fail), "B-V", fail);
        if (s.magnitudeV > maxMagnitude) return;
        const size_t comma = l.find(',');
        if (comma != std::string_view::npos) {
            std::string_view rest = l.substr(comma + 1);
            const size_t c2 = rest.find(',');
            std::string_view genetive = trim(rest.substr(0, c2));
            std::string_view longName = c2 == std::string_view::npos ? std::string_view{} : trim(rest.substr(c2 + 1));
            s.name = std::string(longName.empty() ? genetive : longName);
        }
        stars.push_back(std::move(s));
    });
    return stars;
}

// BSC5 (CDS V/50, file "catalog"): 1-based byte ranges from its ReadMe.
std::vector<Star> parseYaleBrightStarCatalogue(const std::string& text, const std::string& source, double maxMagnitude) {
    std::vector<Star> stars;
    forEachLine(text, [&](std::string_view l, size_t lineNo) {
        if (trim(l).empty()) return;
        LineError fail{source, lineNo};
        auto cols = [&](size_t from1, size_t to1) {  // 1-based inclusive byte range, blank-padded
            if (l.size() < from1) return std::string_view{};
            return l.substr(from1 - 1, std::min(to1 - from1 + 1, l.size() - (from1 - 1)));
        };
        double hr;
        if (!parseDouble(cols(1, 4), hr)) fail("bad HR number '" + std::string(cols(1, 4)) + "'");
        // Records without a J2000 position (non-stellar entries) are skipped.
        if (trim(cols(76, 90)).empty()) return;
        if (l.size() < 107) fail("line too short (" + std::to_string(l.size()) + " characters, expected at least 107)");
        const double raH = field(l, 75, 2, "RAh", fail), raM = field(l, 77, 2, "RAm", fail), raS = field(l, 79, 4, "RAs", fail);
        const char sign = l[83];
        if (sign != '+' && sign != '-') fail(std::string("bad Dec sign '") + sign + "'");
        const double dD = field(l, 84, 2, "DEd", fail), dM = field(l, 86, 2, "DEm", fail), dS = field(l, 88, 2, "DEs", fail);
        if (raH >= 24 || raM >= 60 || raS >= 60 || dD > 90 || dM >= 60 || dS >= 60) fail("RA/Dec field out of range");
        Star s;
        s.raJ2000Rad = (raH + raM / 60.0 + raS / 3600.0) * 15.0 * kDeg;
        s.decJ2000Rad = (dD + dM / 60.0 + dS / 3600.0) * kDeg * (sign == '-' ? -1.0 : 1.0);
        checkRaDec(s.raJ2000Rad, s.decJ2000Rad, fail);
        s.magnitudeV = asFloat(field(l, 102, 5, "Vmag", fail), "Vmag", fail);
        s.colorBV = asFloat(optionalField(l, 109, 5, 0.0, "B-V", fail), "B-V", fail);
        s.pmRaMasPerYear = asFloat(optionalField(l, 148, 6, 0.0, "pmRA", fail) * 1000.0, "pmRA", fail);  // arcsec/yr -> mas/yr
        s.pmDecMasPerYear = asFloat(optionalField(l, 154, 6, 0.0, "pmDE", fail) * 1000.0, "pmDE", fail);
        s.hd = asCatalogueNumber(optionalField(l, 25, 6, 0.0, "HD", fail), "HD", fail);
        s.name = std::string(trim(cols(5, 14)));
        if (s.magnitudeV > maxMagnitude) return;
        stars.push_back(std::move(s));
    });
    return stars;
}

std::vector<Star> parseHygCsv(const std::string& text, const std::string& source, double maxMagnitude) {
    const CsvTable table = CsvTable::parse(text, source, {.caseInsensitiveColumns = true});
    if (table.header().empty()) throw Error(source + ": empty HYG file (no header)");
    if (!table.findColumn("ra") || !table.findColumn("dec"))
        throw Error(source + ":" + std::to_string(table.headerLine()) + ": header has no 'ra' and 'dec' columns");
    const std::size_t ra = table.column("ra"), dec = table.column("dec");
    auto optional = [&](const char* name) { return table.findColumn(name); };
    const auto proper = optional("proper"), dist = optional("dist"), pmra = optional("pmra"), pmdec = optional("pmdec"),
               mag = optional("mag"), ci = optional("ci"), hip = optional("hip"), hd = optional("hd"), bf = optional("bf");
    std::vector<Star> stars;
    for (const CsvRow& row : table) {
        LineError fail{source, row.line()};
        auto number = [&](const std::optional<std::size_t>& column, double fallback) {
            return column ? row.numberOr(*column, fallback) : fallback;
        };
        const std::string_view properName = proper ? row.text(*proper) : std::string_view();
        if (properName == "Sol" || number(dist, 1.0) == 0.0) continue;  // the Sun
        Star s;
        const double raHours = row.number(ra);
        if (!(raHours >= 0.0 && raHours <= 24.0)) fail("ra " + std::to_string(raHours) + " h not in [0, 24]");
        s.raJ2000Rad = std::fmod(raHours * 15.0 * kDeg, 2 * std::numbers::pi);
        s.decJ2000Rad = row.number(dec) * kDeg;
        checkRaDec(s.raJ2000Rad, s.decJ2000Rad, fail);
        s.pmRaMasPerYear = asFloat(number(pmra, 0), "pmra", fail);
        s.pmDecMasPerYear = asFloat(number(pmdec, 0), "pmdec", fail);
        s.magnitudeV = asFloat(number(mag, 99), "mag", fail);
        s.colorBV = asFloat(number(ci, 0), "ci", fail);
        s.hip = asCatalogueNumber(number(hip, 0), "hip", fail);
        s.hd = asCatalogueNumber(number(hd, 0), "hd", fail);
        s.name = std::string(!properName.empty() ? properName : (bf ? row.text(*bf) : std::string_view()));
        if (s.magnitudeV > maxMagnitude) continue;
        stars.push_back(std::move(s));
    }
    return stars;
}

std::vector<Star> loadKStarsBinaryStars(const std::string& path) { return parseKStarsBinaryStars(readFile(path), path); }

std::vector<Star> parseKStarsBinaryStars(const std::string& bin, const std::string& source) {
    auto fail = [&](const std::string& what) -> void { throw Error(source + ": " + what); };
    auto u8 = [&](size_t off) -> unsigned {
        if (off >= bin.size()) fail("truncated at byte " + std::to_string(off));
        return (unsigned char)bin[off];
    };
    auto u16 = [&](size_t off) { return u8(off) | (u8(off + 1) << 8); };
    auto u32 = [&](size_t off) { return std::uint32_t(u16(off)) | (std::uint32_t(u16(off + 2)) << 16); };
    auto i32 = [&](size_t off) { return std::int32_t(u32(off)); };
    auto i16 = [&](size_t off) { return std::int16_t(u16(off)); };
    // 124-byte description, "SK" (little-endian writer), version 1, field count, 16-byte field
    // descriptors, trixel count, 12-byte index entries (id, offset, count).
    if (bin.size() < 129 || bin.compare(124, 2, "SK") != 0) fail("not a little-endian kstars binary star file");
    if (u8(126) != 1) fail("unsupported version " + std::to_string(u8(126)));
    const size_t nFields = u16(127);
    size_t recordSize = 0, hdOffset = size_t(-1);
    for (size_t i = 0; i < nFields; ++i) {
        const size_t o = 129 + 16 * i;
        if (o + 16 > bin.size()) fail("truncated in the field table (" + std::to_string(nFields) + " fields)");
        std::string name(bin.data() + o, bin.data() + std::min(o + 10, bin.size()));
        name = name.substr(0, name.find('\0'));
        if (name == "HD") hdOffset = recordSize;
        recordSize += u8(o + 10);
    }
    if (recordSize != 32 || hdOffset != 20) fail("unexpected record layout (expected the 32-byte starData)");
    size_t o = 129 + 16 * nFields;
    const size_t nTrixels = u32(o);
    o += 4;
    std::vector<Star> out;
    for (size_t t = 0; t < nTrixels; ++t) {
        const size_t e = o + 12 * t;
        const size_t offset = u32(e + 4), count = u32(e + 8);
        for (size_t r = 0; r < count; ++r) {
            const size_t rec = offset + 32 * r;
            // Positions are at the Hipparcos epoch J1991.25: carried to J2000.0 with their own
            // proper motion (mu_alpha*, mu_delta in 0.1 mas/yr).
            Star h;
            h.raJ2000Rad = i32(rec) / 1e6 * 15.0 * kDeg;
            h.decJ2000Rad = i32(rec + 4) / 1e5 * kDeg;
            h.pmRaMasPerYear = float(i32(rec + 8) / 10.0);
            h.pmDecMasPerYear = float(i32(rec + 12) / 10.0);
            h.hd = std::max(0, int(i32(rec + 20)));
            h.magnitudeV = float(i16(rec + 24) / 100.0);
            h.colorBV = float(i16(rec + 26) / 100.0);
            const glm::dvec3 p = glm::normalize(starDirectionJ2000(h) + 8.75 * starProperMotion(h));
            raDecFromDirection(p, h.raJ2000Rad, h.decJ2000Rad);
            out.push_back(std::move(h));
        }
    }
    return out;
}

int attachKStarsHdNumbers(std::vector<Star>& stars, const std::string& path) {
    const std::vector<Star> records = loadKStarsBinaryStars(path);
    // Candidates sorted by declination for a window search.
    std::vector<size_t> order(stars.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return stars[a].decJ2000Rad < stars[b].decJ2000Rad; });
    const double tol = 6.0 / 3600.0 * kDeg;  // the two reductions differ by up to ~5"
    int attached = 0;
    for (const Star& h : records) {
        if (h.hd <= 0) continue;
        const glm::dvec3 p = starDirectionJ2000(h);
        const double dec = h.decJ2000Rad;
        auto lo = std::lower_bound(order.begin(), order.end(), dec - tol,
                                   [&](size_t i, double d) { return stars[i].decJ2000Rad < d; });
        // The nearest star within the radius whose magnitude agrees (variables such as Mira
        // and the two reductions differ by up to ~0.7 mag).
        Star* best = nullptr;
        double bestSep = tol;
        for (auto it = lo; it != order.end() && stars[*it].decJ2000Rad <= dec + tol; ++it) {
            Star& s = stars[*it];
            if (std::abs(s.magnitudeV - h.magnitudeV) > 1.0) continue;
            const glm::dvec3 q = starDirectionJ2000(s);
            const double sep = std::atan2(glm::length(glm::cross(p, q)), glm::dot(p, q));
            if (sep <= bestSep) {
                bestSep = sep;
                best = &s;
            }
        }
        if (best) {
            if (best->hd == 0) ++attached;
            best->hd = h.hd;
        }
    }
    return attached;
}

std::vector<Star> loadKStarsCatalogue(const std::string& path, double m) {
    std::vector<Star> stars = parseKStarsCatalogue(readFile(path), path, m);
    const std::filesystem::path named = std::filesystem::path(path).parent_path() / "namedstars.dat";
    if (std::filesystem::exists(named)) attachKStarsHdNumbers(stars, named.string());
    return stars;
}
std::vector<Star> loadYaleBrightStarCatalogue(const std::string& path, double m) {
    return parseYaleBrightStarCatalogue(readFile(path), path, m);
}
std::vector<Star> loadHygCsv(const std::string& path, double m) { return parseHygCsv(readFile(path), path, m); }

}  // namespace welkin::astro
