// `welkin bench sky-measured`: the reference integrator against a real sky (issue 4 item 12).
//
//   welkin bench sky-measured [--data DIR] [--quick] [--rgb] [--threads 2] [--csv out.csv] [--json]
//                             [--sensitivity] [--no-realtime] [--realtime-width 720]
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
// chromaticity difference Delta u'v' (CIE 1976), and the relative RMS left after dividing the
// model by that ratio (the shape alone). No calibration factor is applied.
// A third row set, "realtime-medium-welkin", is the real-time Sky element at quality medium with
// the "welkin" atmosphere (one equirect render per scan through the OfflineRenderer, sampled
// bilinearly at the sample directions), also scored against the "welkin" reference rows. It is the
// only part that needs an OpenGL context: --no-realtime skips it, and without a context it is
// skipped with a warning.

#include <CLI/CLI.hpp>
#include <welkin/bench.hpp>
#include <welkin/camera.hpp>
#include <welkin/color.hpp>
#include <welkin/csv.hpp>
#include <welkin/elements/sky.hpp>
#include <welkin/elements/sky_offline.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/reference_sky.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/log.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace {

using namespace welkin;
using namespace welkin::atmosphere;

constexpr double kDeg = std::numbers::pi / 180.0;

struct Options {
    // The measurements kept in the repository (skyelements/sky/tests/data/kider2013/SOURCE.md).
    std::string data = std::string(WELKIN_SOURCE_DIR) + "/skyelements/sky/tests/data/kider2013";
    bool quick = false;
    bool rgb = false;
    int threads = 2;
    int spectralSamples = 16;
    std::string csv;
    bool json = false;
    bool sensitivity = false;
    bool realtime = true;     // also the real-time Sky element at medium quality (needs OpenGL)
    int realtimeWidth = 720;  // equirect width of the real-time renders (height = width / 2)
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

std::vector<Scan> loadScans(const std::string& dir) {
    if (!std::filesystem::exists(dir + "/kider2013_scans.csv"))
        throw Error("bench sky-measured: no kider2013_scans.csv in " + dir + " (use --data DIR)");
    std::vector<Scan> scans;
    for (const CsvRow& row : CsvTable::load(dir + "/kider2013_scans.csv")) {
        Scan s;
        s.local = row.text("timestamp_local");
        s.file = row.text("csv");
        s.sunAlt = row.number("sun_alt_deg");
        s.sunAzSymmetry = row.number("sun_az_sky_symmetry_deg");
        s.sunAzAstro = row.number("sun_az_deg");
        const CsvTable samples = CsvTable::load(dir + "/" + s.file);
        const std::size_t az = samples.column("sample_az_deg"), alt = samples.column("sample_alt_deg"),
                          x = samples.column("X"), y = samples.column("Y"), z = samples.column("Z");
        int index = 0;
        for (const CsvRow& r : samples) {
            Sample m;
            m.index = index++;
            m.az = r.number(az);
            m.alt = r.number(alt);
            m.xyz = {r.number(x), r.number(y), r.number(z)};
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
    double rmsShape = 0;  // relative RMS after dividing the model by meanRatio (shape only)
    double rmsVsReference = NAN;  // relative RMS luminance against the reference "welkin" model
    double modelZenith = 0, measuredZenith = 0;
};

/// Model XYZ (cd/m^2) at every sample of every scan: [scan][sample].
using Predictions = std::vector<std::vector<glm::dvec3>>;

glm::dvec3 sunOf(const Scan& scan) { return welkin::directionFromAzAlt(scan.sunAzSymmetry * kDeg, scan.sunAlt * kDeg); }

Predictions predictReference(const ReferenceSky& sky, const std::vector<Scan>& scans) {
    Predictions p;
    for (const Scan& scan : scans) {
        std::vector<glm::dvec3> v;
        for (const Sample& m : scan.samples)
            v.push_back(color::linearSrgbToXyz(sky.radiance(0.0, welkin::directionFromAzAlt(m.az * kDeg, m.alt * kDeg), sunOf(scan))));
        p.push_back(std::move(v));
    }
    return p;
}

/// Bilinear sample of an equirect HDR image (Camera conventions: u = az / 2pi with north at the
/// left edge, v = (pi/2 - alt) / pi), wrapping in azimuth and clamping in altitude.
glm::dvec3 sampleEquirect(const Image& img, const Camera& cam, const glm::dvec3& dir) {
    const glm::dvec2 p = *cam.pixelOf(dir) - 0.5;  // texel centres at integer positions
    const double fx = std::floor(p.x), fy = std::floor(p.y);
    const double tx = p.x - fx, ty = p.y - fy;
    auto texel = [&](int x, int y) {
        x = ((x % img.width) + img.width) % img.width;
        y = std::clamp(y, 0, img.height - 1);
        return glm::dvec3(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2));
    };
    const int x0 = int(fx), y0 = int(fy);
    return glm::mix(glm::mix(texel(x0, y0), texel(x0 + 1, y0), tx), glm::mix(texel(x0, y0 + 1), texel(x0 + 1, y0 + 1), tx), ty);
}

/// The real-time Sky element (OfflineRenderer, the path of the sky tests and `welkin bench sky`)
/// at quality `quality`, one equirect render per scan (sun.direction at the scan's Sun, observer
/// at sea level, no Moon), sampled bilinearly at the 81 directions. The only part of this bench
/// that needs an OpenGL context.
Predictions predictRealtime(const Atmosphere& atmosphere, const std::vector<Scan>& scans, int quality, int width,
                            int wavelengths, double* renderSeconds) {
    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    SkyVars vars = SkyVars::earth();
    vars.set(keys::observerHeight, 0.0);
    vars.set(keys::moonDirection, glm::dvec3(0, 0, -1));
    vars.set(kAtmosphere, std::make_shared<const Atmosphere>(atmosphere));
    elements::OfflineRenderer r(vars, log);
    elements::Sky sky(elements::SkyOptions{.quality = quality, .moon = false, .wavelengths = wavelengths});
    Camera cam;
    cam.projection = Projection::Equirect;
    cam.width = width;
    cam.height = width / 2;
    const auto t0 = std::chrono::steady_clock::now();
    Predictions p;
    for (const Scan& scan : scans) {
        vars.set(keys::sunDirection, sunOf(scan));
        const Image img = r.render(sky, cam);
        std::vector<glm::dvec3> v;
        for (const Sample& m : scan.samples) {
            const glm::dvec3 rgb = sampleEquirect(img, cam, welkin::directionFromAzAlt(m.az * kDeg, m.alt * kDeg));
            v.push_back(color::linearSrgbToXyz(rgb));
        }
        p.push_back(std::move(v));
    }
    *renderSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    sky.release();
    r.release();
    return p;
}

ScanScore score(const std::vector<glm::dvec3>& model, const std::vector<glm::dvec3>* reference, const Scan& scan,
                std::vector<std::vector<std::string>>* csvRows, const std::string& name) {
    const glm::dvec3 sun = sunOf(scan);
    ScanScore s;
    double sum2 = 0, sumRatio = 0, sumDuv = 0, sumRef2 = 0;
    std::vector<std::pair<double, double>> used;  // (model, measured) luminance of the scored samples
    for (std::size_t i = 0; i < scan.samples.size(); ++i) {
        const Sample& m = scan.samples[i];
        const glm::dvec3 xyz = model[i];
        const glm::dvec3 v = welkin::directionFromAzAlt(m.az * kDeg, m.alt * kDeg);
        if (m.alt > 89.0) s.modelZenith = xyz.y, s.measuredZenith = m.xyz.y;
        const double sep = std::acos(std::clamp(glm::dot(v, sun), -1.0, 1.0)) / kDeg;
        const bool scored = m.index != 0 && sep > 10.0;
        if (csvRows) {
            auto f = [](auto v) { return CsvWriter::format(v); };
            csvRows->push_back({name, scan.local, f(m.index), f(m.az), f(m.alt), f(sep), f(scored ? 1 : 0), f(m.xyz.y), f(xyz.y),
                                f(color::chromaticity(m.xyz).x), f(color::chromaticity(m.xyz).y), f(color::chromaticity(xyz).x),
                                f(color::chromaticity(xyz).y)});
        }
        if (!scored) continue;
        const double rel = (xyz.y - m.xyz.y) / m.xyz.y;
        sum2 += rel * rel;
        sumRatio += xyz.y / m.xyz.y;
        sumDuv += color::chromaticityDistanceUv(xyz, m.xyz);
        if (reference) {
            const double r = (xyz.y - (*reference)[i].y) / (*reference)[i].y;
            sumRef2 += r * r;
        }
        used.emplace_back(xyz.y, m.xyz.y);
        ++s.n;
    }
    if (s.n > 0) {
        s.rmsRel = std::sqrt(sum2 / s.n);
        s.meanRatio = sumRatio / s.n;
        s.meanDuv = sumDuv / s.n;
        double shape2 = 0;
        for (const auto& [modelY, measuredY] : used) {
            const double rel = (modelY / s.meanRatio - measuredY) / measuredY;
            shape2 += rel * rel;
        }
        s.rmsShape = std::sqrt(shape2 / s.n);
        if (reference) s.rmsVsReference = std::sqrt(sumRef2 / s.n);
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
        bool realtime = false;  // the real-time Sky element instead of the reference integrator
        int wavelengths = 3;    // real-time: 3 = RGB, else spectral
    };
    const Atmosphere welkinDay = Atmosphere::earthClear().withAerosolOpticalDepth(tau550, alpha).withAerosolAsymmetry(0.64);
    std::vector<Model> models = {
        {"welkin", welkinDay},
        {"bruneton2017", Atmosphere::earthBruneton2017Evaluation()},
    };
    if (o.realtime) {
        models.push_back({"realtime-medium-welkin", welkinDay, true, 3});
        models.push_back({"realtime-medium-spectral15-welkin", welkinDay, true, 15});
    }
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

    std::vector<std::vector<std::string>> csvRows;
    nlohmann::json out;
    out["reference_options"] = {{"mode", o.rgb ? "rgb" : "spectral"}, {"quick", o.quick}, {"spectral_samples", ro.spectralSamples}};
    Predictions welkinReference;  // the "welkin" reference rows, for the real-time row's comparison
    for (const Model& model : models) {
        Predictions pred;
        std::string how;
        nlohmann::json meta;
        if (model.realtime) {
            double seconds = 0;
            try {
                pred = predictRealtime(model.atmosphere, scans, 1, o.realtimeWidth, model.wavelengths, &seconds);
            } catch (const std::exception& e) {
                // No OpenGL 4.5 context here: the reference rows stand on their own.
                std::fprintf(stderr, "WARN bench sky-measured: real-time rows skipped (%s); --no-realtime silences this\n", e.what());
                continue;
            }
            std::fprintf(stderr, "%s: %d equirect renders %dx%d in %.1f s\n", model.name.c_str(), int(scans.size()), o.realtimeWidth,
                         o.realtimeWidth / 2, seconds);
            char buf[160];
            std::snprintf(buf, sizeof buf, "real-time Sky element, quality medium, %s, %dx%d equirect sampled bilinearly, %.1f s",
                          model.wavelengths == 3 ? "RGB" : (std::to_string(model.wavelengths) + " wavelengths").c_str(), o.realtimeWidth,
                          o.realtimeWidth / 2, seconds);
            how = buf;
            meta = {{"renderer", "realtime"}, {"quality", "medium"}, {"wavelengths", model.wavelengths},
                    {"equirect_width", o.realtimeWidth}, {"render_s", seconds}};
        } else {
            const ReferenceSky sky(model.atmosphere, ro);
            std::fprintf(stderr, "%s: precomputed %d orders in %.1f s\n", model.name.c_str(), sky.orders(), sky.precomputeSeconds());
            pred = predictReference(sky, scans);
            char buf[160];
            std::snprintf(buf, sizeof buf, "reference integrator, precompute %.1f s, %d orders", sky.precomputeSeconds(), sky.orders());
            how = buf;
            meta = {{"renderer", "reference"}, {"precompute_s", sky.precomputeSeconds()}, {"orders", sky.orders()}};
            if (model.name == "welkin") welkinReference = pred;
        }
        const bool vsRef = model.realtime && !welkinReference.empty();
        if (!o.json) {
            std::printf("\nmodel %s (%s, AOD550 %.4f, %s)\n", model.name.c_str(), model.atmosphere.name.c_str(),
                        model.atmosphere.aerosolOpticalDepth(550.0), how.c_str());
            std::printf("| scan (EDT) | sun alt | n | rel. RMS lum. | mean model/measured | RMS after level | mean du'v' | "
                        "zenith model / measured cd/m2 |%s\n",
                        vsRef ? " rel. RMS vs reference welkin |" : "");
            std::printf("|---|---|---|---|---|---|---|---|%s\n", vsRef ? "---|" : "");
        }
        double sumRms = 0, sumRatio = 0, sumDuv = 0, sumShape = 0, sumVsRef = 0;
        nlohmann::json js = nlohmann::json::array();
        for (std::size_t k = 0; k < scans.size(); ++k) {
            const Scan& scan = scans[k];
            const ScanScore s =
                score(pred[k], vsRef ? &welkinReference[k] : nullptr, scan, o.csv.empty() ? nullptr : &csvRows, model.name);
            sumRms += s.rmsRel;
            sumRatio += s.meanRatio;
            sumDuv += s.meanDuv;
            sumShape += s.rmsShape;
            sumVsRef += s.rmsVsReference;
            nlohmann::json j = {{"scan", scan.local},
                                {"sun_alt_deg", scan.sunAlt},
                                {"n", s.n},
                                {"rel_rms_luminance", s.rmsRel},
                                {"mean_ratio", s.meanRatio},
                                {"rel_rms_after_level", s.rmsShape},
                                {"mean_duv", s.meanDuv},
                                {"zenith_model_cd_m2", s.modelZenith},
                                {"zenith_measured_cd_m2", s.measuredZenith}};
            if (vsRef) j["rel_rms_vs_reference_welkin"] = s.rmsVsReference;
            js.push_back(j);
            if (!o.json) {
                std::printf("| %s | %.1f | %d | %.1f%% | %.3f | %.1f%% | %.4f | %.0f / %.0f |", scan.local.substr(11, 5).c_str(),
                            scan.sunAlt, s.n, 100.0 * s.rmsRel, s.meanRatio, 100.0 * s.rmsShape, s.meanDuv, s.modelZenith,
                            s.measuredZenith);
                if (vsRef) std::printf(" %.2f%% |", 100.0 * s.rmsVsReference);
                std::printf("\n");
            }
        }
        const double n = double(scans.size());
        if (!o.json) {
            std::printf("| mean | | | %.1f%% | %.3f | %.1f%% | %.4f | |", 100.0 * sumRms / n, sumRatio / n, 100.0 * sumShape / n,
                        sumDuv / n);
            if (vsRef) std::printf(" %.2f%% |", 100.0 * sumVsRef / n);
            std::printf("\n");
        }
        meta["atmosphere"] = model.atmosphere.name;
        meta["aod550"] = model.atmosphere.aerosolOpticalDepth(550.0);
        meta["scans"] = js;
        meta["mean_rel_rms_luminance"] = sumRms / n;
        meta["mean_ratio"] = sumRatio / n;
        meta["mean_rel_rms_after_level"] = sumShape / n;
        meta["mean_duv"] = sumDuv / n;
        if (vsRef) meta["mean_rel_rms_vs_reference_welkin"] = sumVsRef / n;
        out["models"][model.name] = meta;
    }
    if (!o.csv.empty()) {
        CsvWriter f(o.csv, {"model", "scan", "sample", "az_deg", "alt_deg", "sun_sep_deg", "scored", "measured_cd_m2", "model_cd_m2",
                            "measured_x", "measured_y", "model_x", "model_y"});
        for (const auto& r : csvRows) f.writeFields(r);
        f.close();
    }
    if (o.json) std::cout << out.dump(2) << '\n';
    return 0;
}

welkin::bench::CommandBenchRegistrar reg({"sky-measured",
                                  "reference integrator against the Kider 2013 measured clear sky (luminance RMS, colour)",
                                  [](CLI::App& sub) -> std::function<int()> {
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
                                      sub.add_flag("!--no-realtime", o.realtime,
                                                   "skip the real-time Sky element rows (no OpenGL context needed)");
                                      sub.add_option("--realtime-width", o.realtimeWidth,
                                                     "equirect width of the real-time renders, default 720 (0.5 deg/pixel)")
                                          ->check(CLI::Range(64, 4096));
                                      return [] { return run(o); };
                                  }});

}  // namespace
