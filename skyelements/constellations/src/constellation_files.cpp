// Constellations element, its text files: clines.dat / cnames.dat parsing and the resolution of
// the figures' HD numbers against a star list (CPU only, no GL: the fuzz targets in tests/fuzz
// build this file alone). The model is described in include/welkin/elements/constellations.hpp.
#include <welkin/elements/constellations.hpp>
#include <welkin/error.hpp>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>
#include <unordered_map>

namespace welkin::elements {

namespace {
std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}
std::string trim(const std::string& s) {
    const size_t a = s.find_first_not_of(" \t\r\n");
    if (a == std::string::npos) return {};
    return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}
std::string titleCase(const std::string& s) {
    std::string out = s;
    bool start = true;
    for (char& c : out) {
        const unsigned char u = static_cast<unsigned char>(c);
        c = char(start ? std::toupper(u) : std::tolower(u));
        start = !std::isalpha(u) && c != '\'';
    }
    return out;
}
std::string readFile(const std::string& path, const char* what) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(std::string(what) + ": cannot read '" + path + "' (install kstars-data or set the file key)");
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Calls f(lineNumber, line) for the lines of `culture` ("C <name>" headers), and lists the
// cultures seen; throws if the culture is absent.
template <class F>
void forCulture(const std::string& text, const std::string& source, const std::string& culture, F&& f) {
    std::istringstream in(text);
    std::string line, current, seen;
    bool found = false;
    for (int n = 1; std::getline(in, line); ++n) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.size() >= 2 && line[0] == 'C' && line[1] == ' ') {
            current = trim(line.substr(2));
            seen += (seen.empty() ? "" : ", ") + current;
            found = found || lower(current) == lower(culture);
            continue;
        }
        if (lower(current) == lower(culture)) f(n, line);
    }
    if (!found) throw Error(source + ": no sky culture '" + culture + "' (the file has: " + seen + ")");
}
}  // namespace

std::vector<ConstellationFigure> parseConstellationLines(const std::string& text, const std::string& source, const std::string& culture) {
    std::vector<ConstellationFigure> figures;
    forCulture(text, source, culture, [&](int n, const std::string& line) {
        const std::string t = trim(line);
        if (t.empty()) return;
        if (t[0] == '#') {
            const std::string name = trim(t.substr(1));
            if (!name.empty()) figures.push_back({name, {}});
            return;
        }
        const char mode = t[0];
        if (mode != 'M' && mode != 'D' && mode != 'd')
            throw Error(source + ":" + std::to_string(n) + ": expected 'M <HD>' or 'D <HD>', got '" + t + "'");
        char* end = nullptr;
        const std::string num = trim(t.substr(1));
        const long hd = std::strtol(num.c_str(), &end, 10);
        if (num.empty() || *end != '\0' || hd <= 0 || hd > INT_MAX) throw Error(source + ":" + std::to_string(n) + ": bad HD number '" + num + "'");
        if (figures.empty()) figures.push_back({"", {}});
        auto& polys = figures.back().polylines;
        if (mode == 'M' || polys.empty()) polys.emplace_back();
        polys.back().push_back(int(hd));
    });
    // Figures without lines (a comment only) are dropped.
    std::erase_if(figures, [](const ConstellationFigure& f) { return f.polylines.empty(); });
    return figures;
}

std::vector<ConstellationLabel> parseConstellationNames(const std::string& text, const std::string& source, const std::string& culture) {
    std::vector<ConstellationLabel> labels;
    forCulture(text, source, culture, [&](int n, const std::string& line) {
        if (trim(line).empty() || line[0] == '#') return;
        auto bad = [&](const char* what) { return Error(source + ":" + std::to_string(n) + ": " + what + " in '" + line + "'"); };
        if (line.size() < 14) throw bad("line too short (HHMMSS+DDMMSS, then the name)");
        auto field = [&](size_t at, size_t len) {
            int v = 0;
            for (size_t i = at; i < at + len; ++i) {
                if (!std::isdigit(static_cast<unsigned char>(line[i]))) throw bad("expected digits");
                v = 10 * v + (line[i] - '0');
            }
            return v;
        };
        const double ra = (field(0, 2) + field(2, 2) / 60.0 + field(4, 2) / 3600.0) * 15.0;
        if (line[6] != '+' && line[6] != '-') throw bad("expected the declination's sign");
        const double dec = (line[6] == '-' ? -1.0 : 1.0) * (field(7, 2) + field(9, 2) / 60.0 + field(11, 2) / 3600.0);
        if (ra >= 360.0 || std::abs(dec) > 90.0) throw bad("position out of range");
        ConstellationLabel l;
        l.raJ2000Rad = ra * std::numbers::pi / 180.0;
        l.decJ2000Rad = dec * std::numbers::pi / 180.0;
        const std::string rest = line.substr(13);
        const size_t sp = rest.find(' ');
        l.abbreviation = trim(rest.substr(0, sp));
        l.name = titleCase(trim(sp == std::string::npos ? std::string() : rest.substr(sp)));
        if (l.name.empty()) throw bad("no name");
        labels.push_back(std::move(l));
    });
    return labels;
}

std::vector<ConstellationFigure> loadConstellationLines(const std::string& path, const std::string& culture) {
    return parseConstellationLines(readFile(path, "loadConstellationLines()"), path, culture);
}
std::vector<ConstellationLabel> loadConstellationNames(const std::string& path, const std::string& culture) {
    return parseConstellationNames(readFile(path, "loadConstellationNames()"), path, culture);
}

std::vector<ConstellationSegment> resolveConstellationSegments(const std::vector<ConstellationFigure>& figures,
                                                               const std::vector<astro::Star>& stars, int* unresolved) {
    std::unordered_map<int, glm::dvec3> byHd;
    for (const astro::Star& s : stars)
        if (s.hd > 0) byHd.emplace(s.hd, astro::starDirectionJ2000(s));
    std::vector<ConstellationSegment> out;
    int missing = 0;
    for (const ConstellationFigure& f : figures)
        for (const auto& poly : f.polylines) {
            const glm::dvec3* prev = nullptr;
            int prevHd = 0;
            for (int hd : poly) {
                auto it = byHd.find(hd);
                if (it == byHd.end()) {
                    ++missing;
                    prev = nullptr;  // the polyline is broken at an unknown star
                    continue;
                }
                if (prev) out.push_back({*prev, it->second, prevHd, hd});
                prev = &it->second;
                prevHd = hd;
            }
        }
    if (unresolved) *unresolved = missing;
    return out;
}

}  // namespace welkin::elements
