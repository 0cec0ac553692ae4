// `welkin astro` end to end: JSON fields, values against the library, events, bad input.
#include <catch2/catch.hpp>

#include "cli_runner.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>

using welkin::test::runCli;

TEST_CASE("welkin astro --json: every documented field, sensible values", "[cpu][astro][cli]") {
    auto r = runCli("astro --time 1992-04-12T00:00:00Z --lat 0 --lon 0 --json");
    INFO(r.output);
    REQUIRE(r.status == 0);
    nlohmann::json j = nlohmann::json::parse(r.output);
    for (const char* k : {"jd_ut", "jd_tt", "delta_t_s", "gmst_deg", "last_deg", "bodies"}) CHECK(j.contains(k));
    // 1992: TT - UTC = 26 + 32.184 s (leap-second table); UT1 = UTC.
    CHECK(j["delta_t_s"].get<double>() == Approx(58.184).margin(1e-3));
    CHECK(j["jd_ut"].get<double>() == Approx(2448724.5).margin(1e-9));
    CHECK((j["jd_tt"].get<double>() - j["jd_ut"].get<double>()) * 86400 == Approx(58.184).margin(1e-3));
    const char* names[] = {"sun", "moon", "mercury", "venus", "mars", "jupiter", "saturn", "uranus", "neptune"};
    for (const char* n : names) {
        INFO(n);
        REQUIRE(j["bodies"].contains(n));
        const auto& b = j["bodies"][n];
        for (const char* k : {"ra_deg", "dec_deg", "az_deg", "alt_deg", "alt_geometric_deg", "distance_km", "angular_diameter_deg",
                              "magnitude", "phase_angle_deg", "illuminated_fraction", "bright_limb_angle_deg"}) {
            INFO(k);
            REQUIRE(b.contains(k));
            CHECK(b[k].is_number());
        }
        CHECK(b["az_deg"].get<double>() >= 0.0);
        CHECK(b["az_deg"].get<double>() < 360.0);
        // Refraction only lifts: alt_deg >= alt_geometric_deg.
        CHECK(b["alt_deg"].get<double>() >= b["alt_geometric_deg"].get<double>());
    }
    const auto& moon = j["bodies"]["moon"];
    for (const char* k : {"libration_lon_deg", "libration_lat_deg", "axis_angle_deg"}) CHECK(moon.contains(k));
    // Meeus 47.a / 53.a at 0h TD; the CLI's 0h UTC is 58 s earlier (Moon: 0.55"/s): 0.02 deg.
    CHECK(moon["ra_deg"].get<double>() == Approx(134.688470).margin(0.02));
    CHECK(moon["libration_lon_deg"].get<double>() == Approx(-1.23).margin(0.01));
    CHECK(moon["axis_angle_deg"].get<double>() == Approx(15.08).margin(0.02));
    CHECK_FALSE(j.contains("events"));
}

TEST_CASE("welkin astro: --bodies, --refraction off, --precise, --events", "[cpu][astro][cli]") {
    auto r = runCli("astro --time 2026-06-21T00:00:00Z --lat 69.65 --lon 18.96 --bodies sun,MOON --refraction off --precise --events --json");
    INFO(r.output);
    REQUIRE(r.status == 0);
    nlohmann::json j = nlohmann::json::parse(r.output);
    CHECK(j["bodies"].size() == 2);
    CHECK(j["bodies"]["sun"]["alt_deg"].get<double>() == j["bodies"]["sun"]["alt_geometric_deg"].get<double>());
    const auto& ev = j["events"];
    for (const char* k : {"sunrise", "sunset", "civil_dawn", "civil_dusk", "nautical_dawn", "nautical_dusk", "astronomical_dawn",
                          "astronomical_dusk", "moonrise", "moonset", "polar"})
        CHECK(ev.contains(k));
    // Tromso at midsummer: midnight Sun.
    CHECK(ev["polar"] == "day");
    CHECK(ev["sunrise"].is_null());
    CHECK(ev["sunset"].is_null());
    // Berlin: ISO strings for the sunrise.
    auto b = runCli("astro --time 2026-06-21T00:00:00Z --lat 52.52 --lon 13.405 --events --json");
    REQUIRE(b.status == 0);
    nlohmann::json jb = nlohmann::json::parse(b.output);
    REQUIRE(jb["events"]["sunrise"].is_string());
    CHECK(jb["events"]["sunrise"].get<std::string>().rfind("2026-06-21T02:4", 0) == 0);
    CHECK(jb["events"]["polar"].is_null());
    // Without --json: a readable table naming every body.
    auto t = runCli("astro --time 2026-06-21T00:00:00Z --lat 52.52 --lon 13.405");
    REQUIRE(t.status == 0);
    for (const char* n : {"sun", "moon", "mercury", "neptune", "libration"}) CHECK(t.output.find(n) != std::string::npos);
}

TEST_CASE("welkin astro: bad input is a one-line error and exit status 1", "[cpu][astro][cli]") {
    const char* bad[] = {
        "astro --time 2026-06-21T00:00:00Z --lat 91 --lon 0",
        "astro --time 2026-06-21T00:00:00Z --lat 0 --lon 180.5",
        "astro --time 2026-02-30T00:00:00Z --lat 0 --lon 0",
        "astro --time 2026-06-21T25:00:00Z --lat 0 --lon 0",
        "astro --time yesterday --lat 0 --lon 0",
        "astro --time 2026-06-21T00:00:00Z --lat 0 --lon 0 --bodies sun,pluto",
        "astro --time 2026-06-21T00:00:00Z --lat north --lon 0",
        "astro --time 2026-06-21T00:00:00Z --lat 0 --lon 0 --refraction maybe",
        "astro --time -2100-06-21T00:00:00Z --lat 0 --lon 0",
        "astro --lat 0 --lon 0",
    };
    for (const char* args : bad) {
        auto r = runCli(args);
        INFO(args << "\n" << r.output);
        CHECK(r.status == 1);
        CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
        CHECK(r.output.rfind("welkin astro: ", 0) == 0);
    }
}
