// `welkin bench sky-measured`: the reference integrator against a real sky (issue 4 item 12).
//
//   welkin bench sky-measured [--data DIR] [--quick] [--rgb] [--threads 2] [--csv out.csv] [--json]
//                             [--sensitivity]
//
// Reads the Kider et al. 2013 clear-sky scans (15 scans x 81 directions, Cornell, 2013-05-27;
// see DIR/README.md) and, for each scan, evaluates the reference integrator (reference_sky.hpp)
// at the sample directions for two atmospheres:
//  * "welkin": Atmosphere::earthClear() with the day's aerosols from the AERONET retrievals
//    summarised in the README (AOD 0.11 at 500 nm, Angstrom exponent 0.9, asymmetry 0.64);
//  * "bruneton2017": the parameters of Bruneton's 2017 evaluation of clear-sky models
//    (Atmosphere::earthBruneton2017Evaluation()).
// Following the README's caveats: the model Sun is put at (sun_az_sky_symmetry_deg,
// sun_alt_deg), sample 0 of every scan is excluded, and only samples more than 10 deg from the
// Sun are scored. Per scan it reports the relative RMS luminance error, the mean signed
// luminance ratio (model / measured, to separate the overall level from the shape), and the mean
// chromaticity difference Delta u'v' (CIE 1976). No calibration factor is applied.
#include "command.hpp"

#include <welkin/color.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/reference_sky.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace {

using namespace welkin;
using namespace welkin::atmosphere;

constexpr double kDeg = std::numbers::pi / 180.0;

struct Options {
    // The project's shared reference data sits beside the source tree (../shared/reference).
    std::string data = std::string(WELKIN_SOURCE_DIR) + "/../shared/reference/kider2013";
    bool quick = false;
    bool rgb = false;
    int threads = 2;
    int spectralSamples = 16;
    std::string csv;
    bool json = false;
    bool sensitivity = false;
};

struct Sample {
    int index = 0;
    double az = 0, alt = 0;  // degrees
    glm::dvec3 xyz{0.0};
};

struct Scan {
    std::string local, file;
    double sunAlt = 0, sunAzSymmetry = 0, sunAzAstro = 0;
    std::vector<Sample> samples;
};

/// Splits one CSV line (no quoted commas in the columns we read).
std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> out;
    std::string cur;
    bool quoted = false;
    for (char c : line) {
        if (c == '"') quoted = !quoted;
        else if (c == ',' && !quoted) out.push_back(cur), cur.clear();
        else cur += c;
    }
    out.push_back(cur);
    return out;
}

/// Reads a CSV with a header row into maps column -> value.
std::vector<std::map<std::string, std::string>> readCsv(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw Error("bench sky-measured: cannot open " + path + " (use --data DIR)");
    std::string line;
    std::vector<std::string> header;
    std::vector<std::map<std::string, std::string>> rows;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto cells = splitCsv(line);
        if (header.empty()) {
            header = cells;
            continue;
        }
        std::map<std::string, std::string> row;
        for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) row[header[i]] = cells[i];
        rows.push_back(std::move(row));
    }
    return rows;
}

double num(const std::map<std::string, std::string>& row, const std::string& key) {
    auto it = row.find(key);
    if (it == row.end()) throw Error("bench sky-measured: missing column '" + key + "'");
    return std::stod(it->second);
}

std::vector<Scan> loadScans(const std::string& dir) {
    std::vector<Scan> scans;
    for (const auto& row : readCsv(dir + "/kider2013_scans.csv")) {
        Scan s;
        s.local = row.at("timestamp_local");
        s.file = row.at("csv");
        s.sunAlt = num(row, "sun_alt_deg");
        s.sunAzSymmetry = num(row, "sun_az_sky_symmetry_deg");
        s.sunAzAstro = num(row, "sun_az_deg");
        int index = 0;
        for (const auto& r : readCsv(dir + "/" + s.file)) {
            Sample m;
            m.index = index++;
            m.az = num(r, "sample_az_deg");
            m.alt = num(r, "sample_alt_deg");
            m.xyz = {num(r, "X"), num(r, "Y"), num(r, "Z")};
            s.samples.push_back(m);
        }
        scans.push_back(std::move(s));
    }
    if (scans.empty()) throw Error("bench sky-measured: no scans in " + dir);
    return scans;
}

struct ScanScore {
    int n = 0;
    double rmsRel = 0, meanRatio = 0, meanDuv = 0;
    double modelZenith = 0, measuredZenith = 0;
};

ScanScore score(const ReferenceSky& sky, const Scan& scan, std::vector<std::string>* csvRows, const std::string& model) {
    const glm::dvec3 sun = directionFromAzAlt(scan.sunAzSymmetry * kDeg, scan.sunAlt * kDeg);
    ScanScore s;
    double sum2 = 0, sumRatio = 0, sumDuv = 0;
    for (const Sample& m : scan.samples) {
        const glm::dvec3 v = directionFromAzAlt(m.az * kDeg, m.alt * kDeg);
        const glm::dvec3 xyz = color::linearSrgbToXyz(sky.radiance(0.0, v, sun));
        if (m.alt > 89.0) s.modelZenith = xyz.y, s.measuredZenith = m.xyz.y;
        const double sep = std::acos(std::clamp(glm::dot(v, sun), -1.0, 1.0)) / kDeg;
        const bool used = m.index != 0 && sep > 10.0;
        if (csvRows) {
            std::ostringstream o;
            o << model << ',' << scan.local << ',' << m.index << ',' << m.az << ',' << m.alt << ',' << sep << ','
              << (used ? 1 : 0) << ',' << m.xyz.y << ',' << xyz.y << ',' << color::chromaticity(m.xyz).x << ','
              << color::chromaticity(m.xyz).y << ',' << color::chromaticity(xyz).x << ',' << color::chromaticity(xyz).y;
            csvRows->push_back(o.str());
        }
        if (!used) continue;
        const double rel = (xyz.y - m.xyz.y) / m.xyz.y;
        sum2 += rel * rel;
        sumRatio += xyz.y / m.xyz.y;
        sumDuv += color::chromaticityDistanceUv(xyz, m.xyz);
        ++s.n;
    }
    if (s.n > 0) {
        s.rmsRel = std::sqrt(sum2 / s.n);
        s.meanRatio = sumRatio / s.n;
        s.meanDuv = sumDuv / s.n;
    }
    return s;
}

int run(const Options& o) {
    const std::vector<Scan> scans = loadScans(o.data);
    ReferenceOptions ro = o.quick ? ReferenceOptions::fast() : ReferenceOptions{};
    ro.mode = o.rgb ? SpectralMode::Rgb : SpectralMode::Spectral;
    ro.spectralSamples = o.spectralSamples;
    ro.threads = o.threads;

    // AERONET (README): AOD 0.11 at 500 nm with alpha 0.9 -> tau(550) = 0.11 (550/500)^-0.9.
    const double alpha = 0.9, tau550 = 0.11 * std::pow(550.0 / 500.0, -alpha);
    struct Model {
        std::string name;
        Atmosphere atmosphere;
    };
    const Atmosphere welkinDay = Atmosphere::earthClear().withAerosolOpticalDepth(tau550, alpha).withAerosolAsymmetry(0.64);
    std::vector<Model> models = {
        {"welkin", welkinDay},
        {"bruneton2017", Atmosphere::earthBruneton2017Evaluation()},
    };
    if (o.sensitivity) {
        // One change at a time from "welkin" towards Bruneton's parameters, to see what sets the level.
        auto withSsa = [](Atmosphere a, double ssa) {
            for (std::size_t i = 0; i < a.size(); ++i) a.mieScattering[i] = a.mieExtinction[i] * ssa;
            return a;
        };
        Atmosphere grass = welkinDay;
        grass.groundAlbedo = Atmosphere::earthBruneton2017Evaluation().groundAlbedo;
        models.push_back({"welkin-ssa0.8", withSsa(welkinDay, 0.8)});
        models.push_back({"welkin-grass", grass});
        models.push_back({"welkin-aod0.0645", welkinDay.withAerosolOpticalDepth(0.0645, 0.8)});
        models.push_back({"welkin-no-ozone", welkinDay.withOzoneColumn(0.0)});
        models.push_back({"welkin-ssa0.8-grass", withSsa(grass, 0.8)});
    }

    std::vector<std::string> csvRows;
    nlohmann::json out;
    out["reference_options"] = {{"mode", o.rgb ? "rgb" : "spectral"}, {"quick", o.quick}, {"spectral_samples", ro.spectralSamples}};
    for (const Model& model : models) {
        const ReferenceSky sky(model.atmosphere, ro);
        std::fprintf(stderr, "%s: precomputed %d orders in %.1f s\n", model.name.c_str(), sky.orders(), sky.precomputeSeconds());
        if (!o.json) {
            std::printf("\nmodel %s (%s, AOD550 %.4f, precompute %.1f s, %d orders)\n", model.name.c_str(),
                        model.atmosphere.name.c_str(), model.atmosphere.aerosolOpticalDepth(550.0), sky.precomputeSeconds(),
                        sky.orders());
            std::printf("| scan (EDT) | sun alt | n | rel. RMS lum. | mean model/measured | mean du'v' | zenith model / measured cd/m2 |\n");
            std::printf("|---|---|---|---|---|---|---|\n");
        }
        double sumRms = 0, sumRatio = 0, sumDuv = 0;
        nlohmann::json js = nlohmann::json::array();
        for (const Scan& scan : scans) {
            const ScanScore s = score(sky, scan, o.csv.empty() ? nullptr : &csvRows, model.name);
            sumRms += s.rmsRel;
            sumRatio += s.meanRatio;
            sumDuv += s.meanDuv;
            js.push_back({{"scan", scan.local},
                          {"sun_alt_deg", scan.sunAlt},
                          {"n", s.n},
                          {"rel_rms_luminance", s.rmsRel},
                          {"mean_ratio", s.meanRatio},
                          {"mean_duv", s.meanDuv},
                          {"zenith_model_cd_m2", s.modelZenith},
                          {"zenith_measured_cd_m2", s.measuredZenith}});
            if (!o.json)
                std::printf("| %s | %.1f | %d | %.1f%% | %.3f | %.4f | %.0f / %.0f |\n", scan.local.substr(11, 5).c_str(), scan.sunAlt,
                            s.n, 100.0 * s.rmsRel, s.meanRatio, s.meanDuv, s.modelZenith, s.measuredZenith);
        }
        const double n = double(scans.size());
        if (!o.json)
            std::printf("| mean | | | %.1f%% | %.3f | %.4f | |\n", 100.0 * sumRms / n, sumRatio / n, sumDuv / n);
        out["models"][model.name] = {{"atmosphere", model.atmosphere.name},
                                     {"aod550", model.atmosphere.aerosolOpticalDepth(550.0)},
                                     {"precompute_s", sky.precomputeSeconds()},
                                     {"orders", sky.orders()},
                                     {"scans", js},
                                     {"mean_rel_rms_luminance", sumRms / n},
                                     {"mean_ratio", sumRatio / n},
                                     {"mean_duv", sumDuv / n}};
    }
    if (!o.csv.empty()) {
        std::ofstream f(o.csv);
        if (!f) throw Error("bench sky-measured: cannot write " + o.csv);
        f << "model,scan,sample,az_deg,alt_deg,sun_sep_deg,scored,measured_cd_m2,model_cd_m2,measured_x,measured_y,model_x,model_y\n";
        for (const auto& r : csvRows) f << r << '\n';
    }
    if (o.json) std::cout << out.dump(2) << '\n';
    return 0;
}

welkin::cli::BenchRegistrar bench("sky-measured",
                                  "reference integrator against the Kider 2013 measured clear sky (luminance RMS, colour)",
                                  [](CLI::App& sub) -> welkin::cli::Action {
                                      static Options o;
                                      sub.add_option("--data", o.data, "directory of the Kider 2013 reference tables");
                                      sub.add_flag("--quick", o.quick, "coarse integrator settings (ReferenceOptions::fast())");
                                      sub.add_flag("--rgb", o.rgb, "RGB mode instead of spectral");
                                      sub.add_option("--spectral-samples", o.spectralSamples, "wavelengths of the spectral mode (default 16)");
                                      sub.add_option("--threads", o.threads, "precomputation threads (default 2)");
                                      sub.add_option("--csv", o.csv, "write every sample's measured and modelled values");
                                      sub.add_flag("--json", o.json, "print one JSON object");
                                      sub.add_flag("--sensitivity", o.sensitivity,
                                                   "also run variants of the welkin atmosphere (SSA, ground, AOD, ozone)");
                                      return [] { return run(o); };
                                  });

}  // namespace
