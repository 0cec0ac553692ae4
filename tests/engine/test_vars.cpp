// SkyVars: sharing, versions, type and range errors. Generators: run once, re-run on change.
#include <catch2/catch.hpp>

#include <welkin/element.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>
#include <welkin/vars.hpp>

using namespace welkin;

namespace {
const Key<double> kTurbidity{"test.turbidity", Range{1.0, 10.0}, "test key"};
const Key<int> kTurbidityAsInt{"test.turbidity"};
const Key<glm::dvec3> kColour{"test.colour", Range{0.0, 1.0}};
const Key<std::string> kLabel{"test.label"};

struct Shared {
    int value = 0;
};
const Key<std::shared_ptr<Shared>> kShared{"test.shared"};
}  // namespace

TEST_CASE("SkyVars: two declarations of a key share one value", "[cpu][vars]") {
    SkyVars v;
    v.declare(kTurbidity, 2.0);
    v.declare(kTurbidity, 5.0);  // second declarer: the existing value is kept
    CHECK(v.get(kTurbidity) == 2.0);
    v.set(kTurbidity, 3.0);
    CHECK(v.get(kTurbidity) == 3.0);
    // Shared objects: the second obtain() returns the first instance.
    int made = 0;
    auto a = v.obtain<Shared>(kShared, [&] { ++made; return std::make_shared<Shared>(); });
    auto b = v.obtain<Shared>(kShared, [&] { ++made; return std::make_shared<Shared>(); });
    CHECK(a == b);
    CHECK(made == 1);
}

TEST_CASE("SkyVars: versions bump on change only", "[cpu][vars]") {
    SkyVars v;
    CHECK(v.version(kTurbidity) == 0);
    v.set(kTurbidity, 2.0);
    uint64_t v1 = v.version(kTurbidity);
    CHECK(v1 > 0);
    v.set(kTurbidity, 2.0);  // same value: no change
    CHECK(v.version(kTurbidity) == v1);
    v.set(kTurbidity, 2.5);
    CHECK(v.version(kTurbidity) == v1 + 1);
    v.set(kColour, glm::dvec3(0.1, 0.2, 0.3));
    uint64_t c1 = v.version(kColour);
    v.set(kColour, glm::dvec3(0.1, 0.2, 0.3));
    CHECK(v.version(kColour) == c1);
    v.set(kColour, glm::dvec3(0.1, 0.2, 0.4));
    CHECK(v.version(kColour) == c1 + 1);
}

TEST_CASE("SkyVars: the lookup cache never answers for another key, another object or a moved-from one", "[cpu][vars]") {
    // get()/set()/has()/version() find a key's entry through a per-object cache keyed on the Key
    // object's serial (docs/hardening.md). Each section would read a wrong value or crash if the
    // cache answered by address, outlived a move or cached a miss.
    SECTION("a key object made later at a freed one's address is a different key") {
        SkyVars v;
        v.set(Key<double>("test.a"), 1.0);
        v.set(Key<double>("test.b"), 2.0);
        for (int i = 0; i < 3; ++i) {  // the temporaries below reuse the same stack slot
            CHECK(v.get(Key<double>("test.a")) == 1.0);
            CHECK(v.get(Key<double>("test.b")) == 2.0);
        }
        CHECK_FALSE(v.has(Key<double>("test.c")));
    }
    SECTION("a miss is not cached: a key read before it exists is found once declared") {
        SkyVars v;
        CHECK_FALSE(v.has(kTurbidity));
        CHECK(v.version(kTurbidity) == 0);
        v.declare(kTurbidity, 4.0);
        CHECK(v.has(kTurbidity));
        CHECK(v.get(kTurbidity) == 4.0);
    }
    SECTION("two objects, one key: each its own value; a move carries them, the moved-from is empty") {
        SkyVars a, b;
        a.set(kTurbidity, 2.0);
        b.set(kTurbidity, 7.0);
        CHECK(a.get(kTurbidity) == 2.0);
        CHECK(b.get(kTurbidity) == 7.0);
        SkyVars c(std::move(a));
        CHECK(c.get(kTurbidity) == 2.0);
        CHECK_FALSE(a.has(kTurbidity));  // NOLINT(bugprone-use-after-move): moved-from is empty by contract
        a.set(kTurbidity, 9.0);
        CHECK(a.get(kTurbidity) == 9.0);
        CHECK(c.get(kTurbidity) == 2.0);
        b = std::move(c);
        CHECK(b.get(kTurbidity) == 2.0);
        CHECK_FALSE(c.has(kTurbidity));  // NOLINT(bugprone-use-after-move)
    }
    SECTION("more keys than cache lines: every one keeps its own value") {
        SkyVars v;
        std::vector<Key<double>> keys;
        for (int i = 0; i < 1000; ++i) keys.emplace_back("test.many" + std::to_string(i));
        for (int round = 0; round < 2; ++round)
            for (int i = 0; i < 1000; ++i) v.set(keys[size_t(i)], double(i + round));
        for (int i = 0; i < 1000; ++i) REQUIRE(v.get(keys[size_t(i)]) == double(i + 1));
    }
    SECTION("a vector changed in place bumps the version; the same value does not") {
        SkyVars v;
        v.set(kColour, glm::dvec3(0.1));
        const uint64_t before = v.version(kColour);
        const glm::dvec3* where = &v.get(kColour);
        v.set(kColour, glm::dvec3(0.2));
        CHECK(v.version(kColour) == before + 1);
        CHECK(&v.get(kColour) == where);  // assigned in place, not reallocated
        CHECK(v.get(kColour) == glm::dvec3(0.2));
        CHECK_THROWS_WITH(v.set(kColour, glm::dvec3(2.0)), Catch::Contains("test.colour"));
        CHECK(v.get(kColour) == glm::dvec3(0.2));
    }
    SECTION("a key of another type under the same name is still refused after the cache knows the first") {
        SkyVars v;
        v.set(kTurbidity, 3.0);
        CHECK(v.get(kTurbidity) == 3.0);
        CHECK_THROWS_WITH(v.get(kTurbidityAsInt), Catch::Contains("holds double"));
        CHECK_THROWS_WITH(v.set(kTurbidityAsInt, 3), Catch::Contains("holds double"));
    }
}

TEST_CASE("SkyVars: unset, wrong type and out-of-range are errors naming the key", "[cpu][vars]") {
    SkyVars v;
    CHECK_THROWS_WITH(v.get(kLabel), Catch::Contains("test.label") && Catch::Contains("not set"));
    v.declareUnset(kLabel);
    CHECK_THROWS_WITH(v.get(kLabel), Catch::Contains("not set"));
    v.set(kTurbidity, 2.0);
    CHECK_THROWS_WITH(v.get(kTurbidityAsInt), Catch::Contains("test.turbidity") && Catch::Contains("holds double"));
    CHECK_THROWS_WITH(v.declare(kTurbidityAsInt, 3), Catch::Contains("declared by") && Catch::Contains("as int"));
    CHECK_THROWS_WITH(v.set(kTurbidity, 11.0), Catch::Contains("test.turbidity") && Catch::Contains("11 not in [1, 10]"));
    CHECK(v.get(kTurbidity) == 2.0);  // a rejected set leaves the value alone
    CHECK_THROWS_WITH(v.set(kColour, glm::dvec3(0.5, 1.5, 0.0)), Catch::Contains("1.5 not in [0, 1]"));
    CHECK_THROWS_WITH(v.set(kTurbidity, std::nan("")), Catch::Contains("not finite"));
    CHECK_THROWS_WITH(v.set(keys::observerLatitude, 2.0), Catch::Contains("observer.latitude_rad"));
}

TEST_CASE("SkyVars: an enumerated key takes and prints names, the same way everywhere", "[cpu][vars]") {
    enum class Mode { Fast, Exact };
    const EnumKey<Mode> kMode{"test.mode", {{"fast", Mode::Fast}, {"exact", Mode::Exact}}, "test enumeration"};
    SkyVars v;
    v.declare(kMode, Mode::Exact);
    CHECK(v.get(kMode) == "exact");  // stored and shown as its name
    CHECK(v.valueString("test.mode") == "exact");
    CHECK(kMode.value(v) == Mode::Exact);
    v.setFromString("test.mode", "fast");  // what --var and JSON do
    CHECK(kMode.value(v) == Mode::Fast);
    v.set(kMode, Mode::Exact);  // C++ by value
    CHECK(v.get(kMode) == "exact");
    // Any other text, a number included, is refused in one line listing the names; the value stays.
    CHECK_THROWS_WITH(v.setFromString("test.mode", "1"), "key 'test.mode': '1' is not one of fast, exact");
    CHECK_THROWS_WITH(v.set(kMode, std::string("slow")), "key 'test.mode': 'slow' is not one of fast, exact");
    const Key<std::string> plain{"test.mode"};  // a reader without the names still cannot set a bad one
    CHECK_THROWS_WITH(v.set(plain, std::string("slow")), "key 'test.mode': 'slow' is not one of fast, exact");
    CHECK(kMode.value(v) == Mode::Exact);
    CHECK(v.info("test.mode")->choices == std::vector<std::string>{"fast", "exact"});
    // A second declarer with other names is an error.
    const EnumKey<int> kOther{"test.mode", {{"a", 0}, {"b", 1}}};
    CHECK_THROWS_WITH(v.declare(kOther, 0), Catch::Contains("different names"));

    // The engine's enumerated keys: quality presets and curves by name (the integer levels of
    // earlier versions are refused, naming the accepted names).
    SkyVars e = SkyVars::earth();
    e.setFromString("render.quality", "high");
    CHECK(keys::quality.value(e) == 2);
    CHECK_THROWS_WITH(e.setFromString("render.quality", "2"), "key 'render.quality': '2' is not one of low, medium, high, reference");
    e.set(keys::quality, 3);
    CHECK(e.valueString("render.quality") == "reference");
    CHECK_THROWS_WITH(e.set(keys::quality, 7), Catch::Contains("no name for the value"));
}

TEST_CASE("SkyVars::earth() declares the engine keys", "[cpu][vars]") {
    SkyVars v = SkyVars::earth();
    CHECK(keys::quality.value(v) == 1);
    CHECK(v.has(keys::observerHeight));
    CHECK(v.typeName("observer.height_m") == "double");
}

namespace {
class CountingGenerator final : public Generator {
public:
    CountingGenerator() : Generator("Counting") {
        input(kTurbidity);
        input(kColour);
    }
    int ran = 0;

private:
    void doRun(SkyVars&, const Logger&) override { ++ran; }
};
}  // namespace

TEST_CASE("Generator: runs once and again only when an input changes", "[cpu][generator]") {
    SkyVars v;
    v.set(kTurbidity, 2.0);
    v.set(kColour, glm::dvec3(0.5));
    v.set(kLabel, std::string("a"));
    Logger log;
    CountingGenerator g;
    CHECK(g.isDue(v));
    CHECK(g.runIfDue(v, log));
    CHECK_FALSE(g.runIfDue(v, log));
    CHECK(g.ran == 1);
    v.set(kTurbidity, 2.0);  // same value: not due
    CHECK_FALSE(g.runIfDue(v, log));
    v.set(kLabel, std::string("b"));  // not an input
    CHECK_FALSE(g.runIfDue(v, log));
    v.set(kColour, glm::dvec3(0.25));
    CHECK(g.runIfDue(v, log));
    CHECK(g.ran == 2);
    CHECK(g.runCount() == 2);
}

TEST_CASE("Generator: the inputs' versions it polls follow the SkyVars it is given, through moves and new objects", "[cpu][generator]") {
    // The generator keeps where each input's version lives (SkyVars::versionSlot()) with the
    // SkyVars' identity, so it needs no lookup per input per frame; each case below would read a
    // stale or a dangling counter if that cache ignored which object it came from.
    Logger log;
    CountingGenerator g;
    auto fresh = [](double t) {
        SkyVars v;
        v.set(kTurbidity, t);
        v.set(kColour, glm::dvec3(0.5));
        return v;
    };
    SkyVars a = fresh(2.0);
    CHECK(g.runIfDue(a, log));
    // A key declared after the first poll is found later (the slot was missing, not cached as 0).
    for (int i = 0; i < 200; ++i) a.set(Key<double>("test.filler." + std::to_string(i)), double(i));  // rehashes the table
    const uint64_t* slot = a.versionSlot(kTurbidity.name());
    REQUIRE(slot);
    CHECK(*slot == a.version(kTurbidity));
    CHECK_FALSE(g.runIfDue(a, log));  // nodes survive the rehash: still not due
    a.set(kTurbidity, 3.0);
    CHECK(*slot == a.version(kTurbidity));  // the counter the slot points at is the live one
    CHECK(g.runIfDue(a, log));
    CHECK(g.ran == 2);
    // Moved: the entries keep their identity and slots; the moved-from object gets a new identity.
    SkyVars b = std::move(a);
    CHECK(b.versionSlot(kTurbidity.name()) == slot);
    CHECK(a.identity() != b.identity());  // NOLINT(bugprone-use-after-move): the moved-from state is specified
    CHECK_FALSE(g.runIfDue(b, log));
    b.set(kColour, glm::dvec3(0.25));
    CHECK(g.runIfDue(b, log));
    CHECK(g.ran == 3);
    // Another SkyVars whose versions happen to equal the ones seen: not due (same versions), and
    // after a change there it runs: the slots were looked up again in the new object.
    {
        SkyVars c;
        CHECK(c.identity() != b.identity());
        c.set(kTurbidity, 3.0);
        c.set(kColour, glm::dvec3(0.25));
        for (int i = 0; i < 3; ++i) c.set(kTurbidity, 4.0 + i);  // version 4: not what b's was
        CHECK(g.runIfDue(c, log));
        CHECK(g.ran == 4);
        CHECK_FALSE(g.runIfDue(c, log));
    }
    // A new object, possibly at the freed one's address, with the same versions: its identity
    // differs, so its own counters are read (not the freed object's memory, which ASan would flag).
    for (int k = 0; k < 3; ++k) {
        SkyVars d = fresh(9.0);
        CHECK(g.runIfDue(d, log));  // versions 1 and 1 differ from what c had
        d.set(kTurbidity, 8.0);
        CHECK(g.runIfDue(d, log));
    }
    CHECK(g.ran == 10);
}

namespace {
class NamedElement final : public SkyElement {
public:
    explicit NamedElement(std::string n) : SkyElement(std::move(n)) {}

private:
    void doInit(InitContext&) override {}
    void doRender(const FrameContext&) override {}
    void doRelease() override {}
};
}  // namespace

TEST_CASE("SkyProcessor keeps elements in registration order and rejects duplicates", "[cpu][processor]") {
    SkyProcessor p;
    p.add(std::make_unique<NamedElement>("stars"));
    p.add(std::make_unique<NamedElement>("sky"));
    p.add(std::make_unique<NamedElement>("clouds"));
    REQUIRE(p.elements().size() == 3);
    CHECK(p.elements()[0]->name() == "stars");
    CHECK(p.elements()[1]->name() == "sky");
    CHECK(p.elements()[2]->name() == "clouds");
    CHECK(p.find("sky") == p.elements()[1].get());
    CHECK_THROWS_WITH(p.add(std::make_unique<NamedElement>("sky")), Catch::Contains("already registered"));
    // Bad sizes are errors naming the element, and rendering before init() is refused.
    CHECK_THROWS_WITH(p.elements()[0]->resize(0, 10), Catch::Contains("stars::resize()"));
    InitContext ic{p.vars(), p.logger()};
    (void)ic;
    Camera cam;
    FrameContext fc{p.vars(), p.logger(), cam, 0.0, nullptr};
    CHECK_THROWS_WITH(p.elements()[1]->render(fc), Catch::Contains("sky::render(): element not initialised"));
    CHECK_THROWS_WITH(p.setObserver({.latitudeRad = 2.0}), Catch::Contains("latitude") && Catch::Contains("[-90, 90]"));
    CHECK_THROWS_WITH(p.setExposure({.ev100 = 40}), Catch::Contains("ev100 40 not in [-20, 30]"));
}
