// welkin bench sky-twin: the real-time sky model's CPU twin (generators/atmosphere sky_model.hpp:
// the transmittance table, the multiple-scattering field and the view-ray march the GPU passes
// mirror) against the brute-force reference integrator (welkin::atmosphere::ReferenceSky, RGB
// mode), luminance direction by direction, at the ground in the clear Earth atmosphere. Two
// Markdown tables (skyelements/sky/README.md):
//   twin:      orders 1 (the twin's multiple scattering zeroed, the reference single scattering
//              only) and 60 (both complete), Sun at 60, 20, 5, -4, -10, -18 deg, six directions,
//              quality high (preset 2), 512 march steps;
//   departure: all orders, quality medium (preset 1), Sun at 20 and 5 deg, view altitude 3, 10,
//              30, 60 deg by 15 deg of azimuth from the Sun's (within 2 deg of the Sun skipped),
//              256 march steps: where the real-time model departs from the reference.
// Each row: Y (cd/m^2) of each and their ratio twin / reference. CPU only (no GL); the reference's
// multiple-scattering tables take the time (--threads).

#include "bench_util.hpp"

#include <CLI/CLI.hpp>
#include <welkin/bench.hpp>
#include <welkin/camera.hpp>
#include <welkin/error.hpp>
#include <welkin/generators/atmosphere.hpp>
#include <welkin/generators/reference_sky.hpp>
#include <welkin/generators/sky_luts.hpp>
#include <welkin/keys.hpp>

#include <cmath>
#include <functional>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace welkin::cli {
namespace {

using namespace welkin::generators;
constexpr double kDeg = M_PI / 180;

struct SkyTwinOptions {
    std::string tables = "twin,departure";  // which tables to print
    std::string orders = "1,60";            // the twin table's scattering orders, each in [1, 500]
    int threads = 2;                        // reference precomputation threads, [1, 64]
};

double luminance(const glm::dvec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

SkyModel clearModel(const atmosphere::Atmosphere& atm) {
    SkyVars vars = SkyVars::earth();
    vars.set(atmosphere::kAtmosphere, std::make_shared<const atmosphere::Atmosphere>(atm));
    return SkyModel::fromVars(vars);
}

void twinTable(const std::vector<int>& orderList, int threads) {
    const auto atm = atmosphere::Atmosphere::earthClear();
    std::printf("\nCPU twin (quality high, 512 steps) against the reference (RGB), at the ground\n\n"
                "| orders | Sun alt deg | view az deg | view alt deg | reference Y cd/m^2 | twin Y cd/m^2 | twin / reference |\n"
                "|---|---|---|---|---|---|---|\n");
    for (int orders : orderList) {
        atmosphere::ReferenceOptions ro;
        ro.mode = atmosphere::SpectralMode::Rgb;
        ro.threads = threads;
        ro.maxOrders = orders;
        atmosphere::ReferenceSky ref(atm, ro);
        const SkyModel m = clearModel(atm);
        const SkyQuality q = SkyQuality::preset(2);
        const Lut2D T = cpu::transmittanceLut(m, q);
        cpu::MsField MS = cpu::msField(m, q, T);
        if (orders == 1) {  // single scattering: no multiple-scattering field
            for (auto& t : MS.psi.texels) t = glm::dvec3(0.0);
            for (auto& l : MS.sh)
                for (auto& t : l.texels) t = glm::dvec3(0.0);
        }
        for (double sunAlt : {60.0, 20.0, 5.0, -4.0, -10.0, -18.0}) {
            const glm::dvec3 sun = welkin::directionFromAzAlt(0.0, sunAlt * kDeg);
            for (auto [az, alt] : {std::pair{180.0, 45.0}, {90.0, 10.0}, {0.0, 90.0}, {0.0, 5.0}, {180.0, 5.0}, {30.0, 20.0}}) {
                const glm::dvec3 d = welkin::directionFromAzAlt(az * kDeg, alt * kDeg);
                const double r = luminance(ref.radiance(0.0, d, sun));
                const double c = luminance(cpu::skyRadiance(m, T, MS, 0.0, d, sun, m.solarIlluminance, 512, m.sunAngularRadius));
                char ratio[32] = "-";  // no light reaches the direction (in the Earth's shadow): no ratio
                if (r > 0.0) std::snprintf(ratio, sizeof ratio, "%.4f", c / r);
                std::printf("| %d | %.1f | %.1f | %.1f | %.4g | %.4g | %s |\n", orders, sunAlt, az, alt, r, c, ratio);
            }
        }
    }
}

void departureTable(int threads) {
    const auto atm = atmosphere::Atmosphere::earthClear();
    atmosphere::ReferenceOptions ro;
    ro.mode = atmosphere::SpectralMode::Rgb;
    ro.threads = threads;
    atmosphere::ReferenceSky ref(atm, ro);
    const SkyModel m = clearModel(atm);
    const SkyQuality q = SkyQuality::preset(1);
    const Lut2D T = cpu::transmittanceLut(m, q);
    const cpu::MsField MS = cpu::msField(m, q, T);
    std::printf("\nWhere the real-time model (CPU twin, quality medium, 256 steps) departs from the reference (RGB, all "
                "orders): twin / reference luminance, by view altitude (rows) and azimuth from the Sun (columns)\n");
    for (double sunAlt : {20.0, 5.0}) {
        const glm::dvec3 sun = welkin::directionFromAzAlt(0.0, sunAlt * kDeg);
        std::printf("\nSun at %.0f deg\n\n| view alt deg |", sunAlt);
        for (double az = 0; az <= 180; az += 15) std::printf(" az %.0f |", az);
        std::printf("\n|---|");
        for (double az = 0; az <= 180; az += 15) std::printf("---|");
        std::printf("\n");
        for (double alt : {3.0, 10.0, 30.0, 60.0}) {
            std::printf("| %.0f |", alt);
            for (double az = 0; az <= 180; az += 15) {
                const glm::dvec3 d = welkin::directionFromAzAlt(az * kDeg, alt * kDeg);
                if (glm::dot(d, sun) > std::cos(2 * kDeg)) {  // the Sun's disk and its edge: not compared
                    std::printf(" - |");
                    continue;
                }
                const double r = luminance(ref.radiance(0.0, d, sun));
                const double c = luminance(cpu::skyRadiance(m, T, MS, 0.0, d, sun, m.solarIlluminance, 256, m.sunAngularRadius));
                if (r > 0.0) std::printf(" %.3f |", c / r);
                else std::printf(" - |");
            }
            std::printf("\n");
        }
    }
}

int run(const SkyTwinOptions& o) {
    if (o.threads < 1 || o.threads > 64) throw Error("--threads " + std::to_string(o.threads) + " not in [1, 64]");
    std::vector<int> orderList;
    for (const std::string& s : splitList(o.orders)) {
        int n = 0;
        try {
            size_t used = 0;
            n = std::stoi(s, &used);
            if (used != s.size()) n = 0;
        } catch (const std::exception&) {
            n = 0;
        }
        if (n < 1 || n > 500) throw Error("--orders '" + o.orders + "': each entry an integer in [1, 500]");
        orderList.push_back(n);
    }
    bool twin = false, departure = false;
    for (const std::string& t : splitList(o.tables)) {
        if (t == "twin") twin = true;
        else if (t == "departure") departure = true;
        else throw Error("--tables '" + o.tables + "': a list of twin, departure");
    }
    if (!twin && !departure) throw Error("--tables '" + o.tables + "': a list of twin, departure");
    std::printf("welkin bench sky-twin: the clear Earth atmosphere, observer at the ground, Sun at azimuth 0\n");
    if (twin) twinTable(orderList, o.threads);
    if (departure) departureTable(o.threads);
    return 0;
}

bench::CommandBenchRegistrar reg({"sky-twin", "the sky model's CPU twin against the reference integrator (Markdown tables)", [](CLI::App& sub) {
    auto o = std::make_shared<SkyTwinOptions>();  // the action below owns it
    sub.add_option("--tables", o->tables, "which tables: twin (orders 1 and 60), departure (a map of the ratio)")->capture_default_str();
    sub.add_option("--orders", o->orders, "the twin table's scattering orders, comma-separated, each in [1, 500]")->capture_default_str();
    sub.add_option("--threads", o->threads, "reference precomputation threads, [1, 64]")->capture_default_str();
    return [o]() { return run(*o); };
}});

}  // namespace
}  // namespace welkin::cli
