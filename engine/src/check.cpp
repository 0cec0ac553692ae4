#include <welkin/check.hpp>
#include <welkin/error.hpp>

#include <cstdio>

namespace welkin {

namespace {
[[noreturn]] void fail(const char* where, const char* what, double v, double lo, double hi, Shown shown, bool open) {
    char buf[256];
    // An empty `where` (a command-line option names itself): "--lat 100 not in [-90, 90]".
    std::snprintf(buf, sizeof buf, "%s%s%s %g%s not in %c%g, %g%c", where, *where ? ": " : "", what, v * shown.scale, shown.unit,
                  open ? '(' : '[', lo * shown.scale, hi * shown.scale, open ? ')' : ']');
    throw Error(buf);
}
}  // namespace

void checkRange(const char* where, const char* what, double v, double lo, double hi, Shown shown) {
    if (!(v >= lo && v <= hi)) fail(where, what, v, lo, hi, shown, false);
}

void checkOpenRange(const char* where, const char* what, double v, double lo, double hi, Shown shown) {
    if (!(v > lo && v < hi)) fail(where, what, v, lo, hi, shown, true);
}

}  // namespace welkin
