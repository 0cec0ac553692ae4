// `--var KEY=VALUE` values (welkin/vars.hpp SkyVars::setFromString, what
// SkyProcessor::setOption and the command call): one key of every type that can be set from text
// (bool, int, double with and without a range, an angle in rad that also takes "deg", vectors of
// 2, 3 and 4 components, text) plus one that cannot (a matrix), and the Earth defaults' keys.
// The first byte picks the key, the rest is the value. An accepted value must satisfy the key's
// range and read back (valueString) as text that sets the same value again.
#include "fuzz_common.hpp"

#include <welkin/vars.hpp>

using namespace welkin;

namespace {
const Key<bool> kBool{"fuzz.flag"};
const Key<int> kInt{"fuzz.count", Range{-5.0, 1000.0}};
const Key<double> kDouble{"fuzz.height_m", Range{-10.0, 1e5}};
const Key<double> kFree{"fuzz.gain"};
const Key<double> kAngle{"fuzz.angle_rad", Range{-3.2, 3.2}};
const Key<glm::dvec2> kVec2{"fuzz.offset_m", Range{-1e4, 1e4}};
const Key<glm::dvec3> kVec3{"fuzz.colour", Range{0.0, 10.0}};
const Key<glm::dvec4> kVec4{"fuzz.weights"};
const Key<std::string> kText{"fuzz.file"};
const Key<glm::dmat3> kMatrix{"fuzz.rotation"};

SkyVars makeVars() {
    SkyVars v = SkyVars::earth();
    v.declare(kBool, false);
    v.declare(kInt, 3);
    v.declare(kDouble, 0.0);
    v.declare(kFree, 1.0);
    v.declare(kAngle, 0.0);
    v.declare(kVec2, glm::dvec2(0.0));
    v.declare(kVec3, glm::dvec3(1.0));
    v.declare(kVec4, glm::dvec4(0.0));
    v.declare(kText, std::string());
    v.declare(kMatrix, glm::dmat3(1.0));
    return v;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static SkyVars vars = makeVars();
    static const std::vector<std::string> names = vars.names();
    const std::string& name = names[data[0] % names.size()];
    const std::string value = fuzz::text(data + 1, size - 1);
    if (!fuzz::accepts([&] { vars.setFromString(name, value); }, false)) return 0;
    const std::optional<KeyInfo> info = vars.info(name);
    FUZZ_CHECK(info.has_value());
    const std::vector<double> numbers = vars.numeric(name);
    for (double x : numbers) {
        FUZZ_CHECK(std::isfinite(x));
        if (info->range) FUZZ_CHECK(x >= info->range->min && x <= info->range->max);
    }
    // Round trip through the text `welkin vars` prints.
    const std::string printed = vars.valueString(name);
    FUZZ_CHECK(fuzz::accepts([&] { vars.setFromString(name, printed); }, false));
    FUZZ_CHECK(vars.numeric(name) == numbers);
    if (info->type == typeid(std::string)) FUZZ_CHECK(vars.valueString(name) == printed);
    return 0;
}
