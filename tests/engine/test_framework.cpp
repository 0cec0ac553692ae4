// Framework v2: keys with units and declarers, text values, generators ordered by their data,
// change tolerances, republished textures, the element registry, release and re-init.
#include <catch2/catch.hpp>

#include "../../engine/src/generator_graph.hpp"
#include "cli_runner.hpp"
#include "elements_present.hpp"
#include "gl_test_context.hpp"

#include <welkin/astro/astro_keys.hpp>
#include <welkin/element.hpp>
#include <welkin/elements/registry.hpp>
#include <welkin/generators/lights.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <epoxy/gl.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace welkin;

namespace {
const Key<double> kA{"test.a_m", Range{0, 10}, "input written by the host"};
const Key<double> kB{"test.b_m", Range{0, 100}, "written by gen B from A"};
const Key<double> kC{"test.c_m", Range{0, 1000}, "written by gen C from B"};
const Key<double> kUndeclared{"test.nobody_declares"};

// A generator writing out = 2 * in (and logging the order it ran in).
class Doubler final : public Generator {
public:
    Doubler(std::string name, const Key<double>& in, const Key<double>& out, std::vector<std::string>* log, InputOptions opt = {})
        : Generator(std::move(name)), in_(in), out_(out), log_(log) {
        input(in, opt);
        output(out);
    }

private:
    void doRun(SkyVars& v, const Logger&) override {
        if (log_) log_->push_back(name());
        v.set(out_, 2.0 * v.getOr(in_, 0.0));
    }
    Key<double> in_, out_;
    std::vector<std::string>* log_;
};

// An element that only owns generators (no drawing) and declares keys in init.
class GenElement final : public SkyElement {
public:
    GenElement(std::string name, std::vector<std::shared_ptr<Generator>> gens, std::function<void(SkyVars&)> declare = {})
        : SkyElement(std::move(name)), gens_(std::move(gens)), declare_(std::move(declare)) {}

private:
    void doInit(InitContext& ctx) override {
        if (declare_) declare_(ctx.vars);
        for (auto& g : gens_) addGenerator(g);
    }
    void doRender(const FrameContext&) override {}
    void doRelease() override {}
    std::vector<std::shared_ptr<Generator>> gens_;
    std::function<void(SkyVars&)> declare_;
};

SkyProcessor cpuProcessor() { return SkyProcessor(SkyVars::earth(), Logger(), ProcessorOptions{.astronomy = false}); }
}  // namespace

TEST_CASE("Keys: units from names, declarations must agree and name both declarers", "[cpu][vars]") {
    CHECK(unitFromKeyName("observer.height_m") == "m");
    CHECK(unitFromKeyName("sun.angular_radius_rad") == "rad");
    CHECK(unitFromKeyName("grid.luminance_cd_m2") == "cd/m^2");
    CHECK(unitFromKeyName("sun.direction") == "");
    SkyVars v;
    {
        SkyVars::DeclarerScope s(v, "astronomy");
        v.declare(Key<double>{"moon.distance_m", Range{1e7, 1e9}}, 3.8e8);
    }
    SkyVars::DeclarerScope s(v, "sky");
    // The same definition again: shared, no error.
    v.declare(Key<double>{"moon.distance_m", Range{1e7, 1e9}}, 3.9e8);
    CHECK(v.get(Key<double>{"moon.distance_m"}) == 3.8e8);
    // A different range (the old sky.cpp re-declaration): an error naming both declarers.
    CHECK_THROWS_WITH(v.declare(Key<double>{"moon.distance_m", Range{3.4e8, 4.1e8}}, 3.8e8),
                      Catch::Contains("'moon.distance_m' declared by 'astronomy' as double in [1e+07, 1e+09] m") &&
                          Catch::Contains("by 'sky' as double in [3.4e+08, 4.1e+08] m"));
    // A different unit, or type: the same.
    CHECK_THROWS_WITH(v.declare(Key<double>{"moon.distance_m", Range{1e7, 1e9}, "", "km"}, 3.8e5), Catch::Contains("km"));
    CHECK_THROWS_WITH(v.declare(Key<int>{"moon.distance_m"}, 1), Catch::Contains("as int"));
    // set() through a key object with a conflicting definition is refused too.
    CHECK_THROWS_WITH(v.set(Key<double>{"moon.distance_m", Range{0, 1}}, 0.5), Catch::Contains("declared by 'astronomy'"));
}

TEST_CASE("Keys: values from text by type, with ranges and degrees", "[cpu][vars]") {
    SkyVars v;
    const Key<bool> b{"t.flag"};
    const Key<int> i{"t.count", Range{0, 5}};
    const Key<double> ang{"t.step_rad", Range{0, 1}};
    const Key<glm::dvec3> vec{"t.colour", Range{0, 2}};
    const Key<std::string> str{"t.name"};
    v.declare(b, false);
    v.declare(i, 1);
    v.declare(ang, 0.1);
    v.declare(vec, glm::dvec3(0));
    v.declare(str, std::string("x"));
    v.setFromString("t.flag", "on");
    CHECK(v.get(b));
    v.setFromString("t.count", " 4 ");
    CHECK(v.get(i) == 4);
    v.setFromString("t.step_rad", "30deg");
    CHECK(v.get(ang) == Approx(M_PI / 6).epsilon(1e-15));
    v.setFromString("t.colour", "0.5,1,1.5");
    CHECK(v.get(vec) == glm::dvec3(0.5, 1, 1.5));
    v.setFromString("t.name", "hello");
    CHECK(v.get(str) == "hello");
    CHECK(v.valueString("t.colour") == "0.5,1,1.5");
    CHECK(v.valueString("t.flag") == "true");
    const uint64_t ver = v.version(i);
    CHECK_THROWS_WITH(v.setFromString("t.count", "9"), "key 't.count' (int in [0, 5]): '9' not in [0, 5]");
    CHECK_THROWS_WITH(v.setFromString("t.count", "2.5"), Catch::Contains("is not an integer"));
    CHECK_THROWS_WITH(v.setFromString("t.flag", "maybe"), Catch::Contains("is not a bool"));
    CHECK_THROWS_WITH(v.setFromString("t.colour", "1,2"), Catch::Contains("needs 3 comma-separated numbers"));
    CHECK_THROWS_WITH(v.setFromString("t.step_rad", "90deg"), Catch::Contains("not in [0, 1]"));
    CHECK_THROWS_WITH(v.setFromString("t.unknown", "1"), "unknown key 't.unknown' (`welkin vars` lists the keys)");
    CHECK(v.version(i) == ver);  // refused values change nothing
}

TEST_CASE("SkyVars::publish and touch bump the version of an unchanged value", "[cpu][vars]") {
    SkyVars v;
    const Key<TextureRef> tex{"t.lut"};
    v.set(tex, TextureRef{7, 0, 4, 4, 0});
    const uint64_t a = v.version(tex);
    v.set(tex, TextureRef{7, 0, 4, 4, 0});
    CHECK(v.version(tex) == a);  // same texture name: set() sees no change
    v.publish(tex, TextureRef{7, 0, 4, 4, 0});
    CHECK(v.version(tex) == a + 1);  // rewritten in place: readers must run
    v.touch(tex);
    CHECK(v.version(tex) == a + 2);
    CHECK_THROWS_WITH(v.touch("t.missing"), Catch::Contains("not declared"));
}

TEST_CASE("Generators run in data order whatever the registration order", "[gl][generator][processor]") {
    std::vector<std::string> ran;
    auto c = std::make_shared<Doubler>("C", kB, kC, &ran);  // reads B's output
    auto b = std::make_shared<Doubler>("B", kA, kB, &ran);
    // Registered with C (which reads B's output) first.
    SkyProcessor q = cpuProcessor();
    q.vars().set(kA, 1.5);
    q.addGenerator(c);
    q.addGenerator(b);
    test::glContext();
    q.init();
    REQUIRE(q.generatorOrder().size() == 2);
    CHECK(q.generatorOrder()[0]->name() == "B");
    CHECK(q.generatorOrder()[1]->name() == "C");
    Camera cam;
    cam.width = cam.height = 2;
    q.setCamera(cam);
    q.update();
    CHECK(ran == std::vector<std::string>{"B", "C"});
    CHECK(q.vars().get(kC) == 6.0);  // 1.5 * 2 * 2 in one frame: C saw B's fresh output
    q.update();                      // nothing changed: nothing runs
    CHECK(ran.size() == 2);
    q.vars().set(kA, 2.0);
    q.update();
    CHECK(q.vars().get(kC) == 8.0);
}

TEST_CASE("Generator graph errors at init: two writers, undeclared reads, cycles", "[gl][generator][processor]") {
    test::glContext();
    Camera cam;
    cam.width = cam.height = 2;
    {
        SkyProcessor p = cpuProcessor();
        p.setCamera(cam);
        p.vars().set(kA, 1.0);
        p.addGenerator(std::make_shared<Doubler>("one", kA, kB, nullptr));
        p.addGenerator(std::make_shared<Doubler>("two", kA, kB, nullptr));
        CHECK_THROWS_WITH(p.init(), "SkyProcessor::init(): key 'test.b_m' is written by two generators, 'one' and 'two'");
    }
    {
        SkyProcessor p = cpuProcessor();
        p.setCamera(cam);
        p.addGenerator(std::make_shared<Doubler>("reader", kUndeclared, kB, nullptr));
        CHECK_THROWS_WITH(p.init(), "SkyProcessor::init(): generator 'reader' reads key 'test.nobody_declares', which no element, "
                                    "generator or host declares");
    }
    {
        // Optional inputs may be undeclared.
        SkyProcessor p = cpuProcessor();
        p.setCamera(cam);
        p.addGenerator(std::make_shared<Doubler>("reader", kUndeclared, kB, nullptr, InputOptions{.optional = true}));
        CHECK_NOTHROW(p.init());
    }
    {
        SkyProcessor p = cpuProcessor();
        p.setCamera(cam);
        p.addGenerator(std::make_shared<Doubler>("ab", kA, kB, nullptr));
        p.addGenerator(std::make_shared<Doubler>("ba", kB, kA, nullptr));
        CHECK_THROWS_WITH(p.init(), Catch::Contains("cycle") && Catch::Contains("ab") && Catch::Contains("ba"));
    }
}

TEST_CASE("GeneratorGraph without GL: stable data order, due runs, options that are outputs", "[cpu][generator]") {
    const Key<double> kD{"test.d_m", Range{0, 100}, "written by gen D from A"};
    SkyVars v;
    v.set(kA, 1.5);
    std::vector<std::string> ran;
    GeneratorGraph graph;
    auto c = std::make_shared<Doubler>("C", kB, kC, &ran);  // reads B's output
    graph.add(c, v);
    graph.add(std::make_shared<Doubler>("D", kA, kD, &ran), v);  // independent of B and C
    graph.add(std::make_shared<Doubler>("B", kA, kB, &ran), v);
    graph.add(c, v);  // the same instance again: ignored
    CHECK_FALSE(graph.valid());
    graph.order(v, {}, {});
    REQUIRE(graph.ordered().size() == 3);
    // Kahn's algorithm taking the earliest-registered ready generator: D (registered before B)
    // first, then B, then C, which waits for B.
    CHECK(graph.ordered()[0]->name() == "D");
    CHECK(graph.ordered()[1]->name() == "B");
    CHECK(graph.ordered()[2]->name() == "C");
    graph.run(v, Logger(), false, false);
    CHECK(ran == std::vector<std::string>{"D", "B", "C"});
    CHECK(v.get(kC) == 6.0);  // 1.5 * 2 * 2 in one run: C saw B's fresh output
    graph.run(v, Logger(), false, false);  // nothing changed: nothing runs
    CHECK(ran.size() == 3);
    // A key the host set as an option must not be a generator's output.
    CHECK_THROWS_WITH(graph.order(v, {}, {kB.name()}), generatorOutputMessage(kB.name(), *graph.ordered()[1]));
    CHECK_THROWS_WITH(graph.checkNotAnOutput(kC.name(), {}), Catch::StartsWith("test.c_m is an output of the generator 'C'"));
    CHECK_NOTHROW(graph.checkNotAnOutput(kA.name(), {}));
    graph.release();  // forgets the order; the next run needs order() again
    CHECK_FALSE(graph.valid());
    CHECK(graph.ordered().empty());
}

TEST_CASE("Generator inputs: a change within the tolerance does not rebuild", "[cpu][generator]") {
    SkyVars v;
    v.set(kA, 1.0);
    std::vector<std::string> ran;
    Doubler g("tol", kA, kB, &ran, InputOptions{.tolerance = 0.01});
    Logger log;
    CHECK(g.runIfDue(v, log));
    v.set(kA, 1.004);
    CHECK_FALSE(g.runIfDue(v, log));  // 0.004 since the last run
    v.set(kA, 1.008);
    CHECK_FALSE(g.runIfDue(v, log));  // 0.008: drift is measured from the last run, not the last frame
    v.set(kA, 1.012);
    CHECK(g.runIfDue(v, log));  // 0.012 > 0.01
    CHECK(ran.size() == 2);
    g.invalidate();
    CHECK(g.runIfDue(v, log));  // invalidated: runs though nothing changed
}

TEST_CASE("Element registry: generated from the folders, ordered by layer", "[cpu][registry]") {
    const auto& d = elements::descriptors();
    // At least the Sky (the tree without every other element folder is tested in CI: the order
    // check below then has one entry; it is exercised whenever another element is present).
    REQUIRE(!d.empty());
    for (size_t i = 1; i < d.size(); ++i) CHECK(d[i - 1]->layer <= d[i]->layer);
    const ElementDescriptor* sky = elements::findDescriptor("sky");
    REQUIRE(sky);
    CHECK(sky->layer == Layer::Atmosphere);
    CHECK(sky->inDefaultSet);
    auto defaults = elements::defaultElements();
    CHECK(std::find(defaults.begin(), defaults.end(), "sky") != defaults.end());
    CHECK(elements::makeElement("sky")->name() == "sky");
    CHECK_THROWS_WITH(elements::makeElement("nope"), Catch::StartsWith("unknown element 'nope' (known: "));
    CHECK_THROWS_WITH(elements::expandElementList("sky,default"), "element list 'sky,default' names 'sky' twice");
    CHECK_THROWS_WITH(elements::expandElementList("default,nope"), Catch::StartsWith("unknown element 'nope' (known: "));
#ifdef WELKIN_HAS_ELEMENT_grid  // an element outside the default set, and its options
    const ElementDescriptor* grid = elements::findDescriptor("grid");
    REQUIRE(grid);
    CHECK(grid->layer == Layer::Overlay);
    CHECK_FALSE(grid->inDefaultSet);
    CHECK(std::find(defaults.begin(), defaults.end(), "grid") == defaults.end());
    CHECK(elements::makeElement("grid")->name() == "grid");
    // A scene's list: 'default' expands in place to the default set.
    std::vector<std::string> expanded = elements::expandElementList("default, grid");
    std::vector<std::string> expected = defaults;
    expected.push_back("grid");
    CHECK(expanded == expected);
    CHECK(elements::expandElementList("grid,default").front() == "grid");
    // Options are keys declared when the element is added.
    SkyProcessor p = cpuProcessor();
    p.add(elements::makeElement("grid"));
    REQUIRE(p.vars().numeric("grid.altitude_step_rad").size() == 1);
    CHECK(p.vars().numeric("grid.altitude_step_rad")[0] == Approx(10 * M_PI / 180));
    p.vars().setFromString("grid.altitude_step_rad", "30deg");
    REQUIRE(p.vars().numeric("grid.altitude_step_rad").size() == 1);
    CHECK(p.vars().numeric("grid.altitude_step_rad")[0] == Approx(M_PI / 6));
#endif
    // The tests' guards (elements_present.hpp: WELKIN_HAS_ELEMENT_<name> around the cases that
    // need another element) see the same folders as the registry: a stale header would compile
    // such a case in where its element is gone, or leave it out where it is there.
    std::vector<std::string> known = elements::knownElements();
    std::sort(known.begin(), known.end());
    std::string joined;
    for (const auto& n : known) joined += (joined.empty() ? "" : ",") + n;
    CHECK(joined == WELKIN_ELEMENTS_PRESENT);
}

TEST_CASE("release() then init() renders the same frame again", "[gl][processor]") {
    test::glContext();
    SkyProcessor p;
    Camera cam;
    cam.projection = Projection::Fisheye;
    cam.width = cam.height = 24;
    p.setCamera(cam);
    p.setObserver({.latitudeRad = 0.6, .longitudeRad = 0.25, .heightMeters = 10});
    p.setTime(UtcInstant::parse("2026-06-21T18:00:00Z"));
    p.setExposure({.ev100 = 12});
    p.setAnimationTime(0.0);
    p.add(elements::makeElement("sky"));
#ifdef WELKIN_HAS_ELEMENT_grid  // a second element, drawn over the Sky (the Sky alone is the case without it)
    p.add(elements::makeElement("grid"));
#endif
    p.renderFrame();
    Image a = p.readHdr();
    p.release();
    p.init();
    p.renderFrame();
    Image b = p.readHdr();
    REQUIRE(a.pixels.size() == b.pixels.size());
    double worst = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i)
        worst = std::max(worst, double(std::abs(a.pixels[i] - b.pixels[i]) / std::max(1e-6f, std::abs(a.pixels[i]))));
    INFO("largest relative difference " << worst);
    // The same LUTs rebuilt from scratch by the same code: identical up to float rounding.
    CHECK(worst < 1e-5);
    // Every generator ran again after the release (its LUTs were freed).
    for (Generator* g : p.generatorOrder()) CHECK(g->runCount() >= 2);
}

TEST_CASE("Astronomy and lights as generators: world state for elements without a Sky", "[gl][processor]") {
    test::glContext();
    SkyProcessor p;
    Camera cam;
    cam.width = cam.height = 4;
    p.setCamera(cam);
    p.setObserver({.latitudeRad = 0.6266, .longitudeRad = 0.2531, .heightMeters = 0});
    p.setTime(UtcInstant::parse("2026-08-12T22:00:00Z"));
#ifdef WELKIN_HAS_ELEMENT_grid  // a library element without a Sky (the user's element below is the case without it)
    p.add(elements::makeElement("grid"));
#endif
    // A Grid-only scene: an element that wants the lights adds the shared generator itself.
    p.add(std::make_unique<GenElement>("user", std::vector<std::shared_ptr<Generator>>{}, [](SkyVars&) {}));
    auto lights = generators::AtmosphereLights::obtain(p.vars());
    p.addGenerator(lights);
    p.renderFrame();
    // The astronomy ran before the lights (the lights read sun.direction): order by data.
    const auto& order = p.generatorOrder();
    auto pos = [&](const std::string& n) {
        for (size_t i = 0; i < order.size(); ++i)
            if (order[i]->name() == n) return int(i);
        return -1;
    };
    REQUIRE(pos("astronomy") >= 0);
    REQUIRE(pos("atmosphere.lights") >= 0);
    CHECK(pos("astronomy") < pos("atmosphere.lights"));
    // Malta, 22:00 UTC on 12 August 2026: the Sun is far below the horizon.
    CHECK(p.vars().get(keys::sunDirection).z < -0.3);
    CHECK(p.vars().get(generators::lightkeys::sunTransmittance) == glm::dvec3(0.0));
    // The star frame is published: a rotation (orthonormal, det +1).
    const glm::dmat3 m = p.vars().get(astro::keys::starFrameRotation);
    CHECK(glm::determinant(m) == Approx(1.0).epsilon(1e-12));
    const glm::dvec3 pole = m * glm::dvec3(0, 0, 1);  // the ICRS pole (~ the celestial pole) from Malta
    CHECK(std::asin(pole.z) == Approx(0.6266).margin(0.01));  // altitude of the pole = latitude (precession since J2000 < 0.2 deg)
    nlohmann::json st = p.stats();
    CHECK(st["moon"].contains("illuminated_fraction"));
    CHECK(st["generators"].size() == order.size());
}

TEST_CASE("welkin render --var and welkin vars", "[gl][cli]") {
    const std::string dir = test::scratchDir("cli_var");
#ifdef WELKIN_HAS_ELEMENT_grid  // an element's options set from the command line, rendered
    auto ok = test::runCli("render --time 2026-06-21T12:00:00Z --lat 0 --lon 0 --elements grid --projection equirect --size 36x18 "
                           "--exposure 0 --var grid.altitude_step_rad=45deg --var grid.markers=off --out " + dir + "/g.exr");
    INFO(ok.output);
    CHECK(ok.status == 0);
#endif
    // Refused while the options are checked, before any GL: the Sky renders nothing here.
    auto unknown = test::runCli("render --time 2026-06-21T12:00:00Z --lat 0 --lon 0 --elements sky --size 8x8 --out " + dir +
                                "/x.png --var sky.nope=1");
    CHECK(unknown.status == 1);
    CHECK(unknown.output == "welkin render: --var sky.nope=1: unknown key 'sky.nope' (`welkin vars` lists the keys)\n");
    auto syntax = test::runCli("render --time 2026-06-21T12:00:00Z --lat 0 --lon 0 --elements sky --size 8x8 --out " + dir +
                               "/x.png --var sky.quality");
    CHECK(syntax.status == 1);
    CHECK(syntax.output == "welkin render: --var 'sky.quality' is not KEY=VALUE\n");
    CHECK_FALSE(std::filesystem::exists(dir + "/x.png"));
    auto vars = test::runCli("vars --json");
    REQUIRE(vars.status == 0);
    nlohmann::json j = nlohmann::json::parse(vars.output);
    bool sawQuality = false, sawLights = false;
    for (auto& k : j) {
        if (k["name"] == "sky.quality") {
            sawQuality = true;
            CHECK(k["option_of"] == nlohmann::json::array({"sky"}));
            CHECK(k["type"] == "enum");
            CHECK(k["range"] == nullptr);
            CHECK(k["choices"] == nlohmann::json::array({"auto", "low", "medium", "high", "reference"}));
        }
        if (k["name"] == "lights.sun_illuminance") {
            sawLights = true;
            CHECK(k["unit"] == "lx");
            CHECK(k["written_by"] == nlohmann::json::array({"atmosphere.lights"}));
        }
    }
    CHECK(sawQuality);
    CHECK(sawLights);
}

TEST_CASE("Keys tables: docs/keys.md and every element folder's keys.md are welkin vars --keys-of", "[gl][cli][docs]") {
    // The key tables of the docs are generated, one per owner, each from a scene of its own (so no
    // table depends on which other element folders exist): the engine's in docs/keys.md, each
    // element's in skyelements/<name>/keys.md. A key added, renamed or re-ranged without
    // regenerating its table fails here, and so does an element folder without its table.
    std::vector<std::string> owners{"engine"};
    for (const std::string& n : elements::knownElements()) owners.push_back(n);
    std::string list;
    for (const auto& o : owners) list += (list.empty() ? "" : ",") + o;
    auto r = test::runCli("vars --markdown --keys-of " + list);
    REQUIRE(r.status == 0);
    for (size_t i = 0; i < owners.size(); ++i) {
        const std::string file = owners[i] == "engine" ? "docs/keys.md" : "skyelements/" + owners[i] + "/keys.md";
        const std::string marker = "<!-- keys of " + owners[i] + ": " + file + " -->\n";
        const size_t at = r.output.find(marker);
        REQUIRE(at != std::string::npos);
        const size_t begin = at + marker.size();
        const size_t end = i + 1 < owners.size() ? r.output.find("\n<!-- keys of ", begin) : r.output.size();
        const std::string expected = r.output.substr(begin, end - begin);
        const std::string regenerate = "regenerate it: scripts/keys-tables.sh (or replace its table, from the line starting "
                                       "'| key |' to the end, with the output of `welkin vars --markdown --keys-of " + owners[i] + "`)";
        std::ifstream f(std::string(WELKIN_SOURCE_DIR) + "/" + file);
        if (!f) {
            FAIL_CHECK(file << " is missing: " << regenerate);
            continue;
        }
        std::string doc((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        const size_t table = doc.find("| key |");
        if (table == std::string::npos) {
            FAIL_CHECK(file << " has no table (no line starting '| key |'): " << regenerate);
            continue;
        }
        INFO(file << " is stale: " << regenerate);
        CHECK(doc.substr(table) == expected);
    }
    // Bad input: one line naming the option, status 1 (checked before any scene is built).
    CHECK(test::badOptionFailures("vars", {{"--markdown --keys-of nope", "--keys-of: 'nope' is neither 'engine' nor a known element (known: "},
                                           {"--keys-of engine", "--keys-of: give --markdown or --json"}})
              .empty());
}

TEST_CASE("FrameContext::attenuatedLater follows the compositing order", "[gl][processor]") {
    // An element learns whether one composited after it attenuates what is behind it (the Sky):
    // stars drawn before the Sky leave extinction to it, stars drawn after it do not.
    struct Probe final : SkyElement {
        explicit Probe(std::string n, bool attenuates) : SkyElement(std::move(n)) { setAttenuatesBehind(attenuates); }
        bool seen = false;
        void doInit(InitContext&) override {}
        void doRender(const FrameContext& ctx) override { seen = ctx.attenuatedLater; }
        void doRelease() override {}
    };
    test::glContext();
    SkyProcessor p = cpuProcessor();
    Camera cam;
    cam.width = cam.height = 2;
    p.setCamera(cam);
    auto& a = static_cast<Probe&>(p.add(std::make_unique<Probe>("behind", false)));
    auto& sky = static_cast<Probe&>(p.add(std::make_unique<Probe>("air", true)));
    auto& c = static_cast<Probe&>(p.add(std::make_unique<Probe>("front", false)));
    p.renderFrame();
    CHECK(a.seen);
    CHECK_FALSE(sky.seen);
    CHECK_FALSE(c.seen);
    CHECK(elements::makeElement("sky")->attenuatesBehind());
#ifdef WELKIN_HAS_ELEMENT_grid
    CHECK_FALSE(elements::makeElement("grid")->attenuatesBehind());
#endif
}
