// The ISO 8601 time parser (welkin/time.hpp UtcInstant::parse: `--time`, `--from`, `--to`), both
// calendars. The first byte picks the calendar, the rest is the text. An accepted instant prints
// (toIso) as text the parser accepts again, naming the same instant to the printed millisecond.
#include "fuzz_common.hpp"

#include <welkin/time.hpp>

using namespace welkin;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const Calendar calendar = (data[0] & 1) ? Calendar::Julian : Calendar::Gregorian;
    const std::string text = fuzz::text(data + 1, size - 1);
    UtcInstant t;
    if (!fuzz::accepts([&] { t = UtcInstant::parse(text, calendar); }, false)) return 0;
    const std::string iso = t.toIso();
    UtcInstant again;
    FUZZ_CHECK(fuzz::accepts([&] { again = UtcInstant::parse(iso, calendar); }, false));
    const double a = t.julianDate().day + t.julianDate().fraction, b = again.julianDate().day + again.julianDate().fraction;
    // toIso prints milliseconds (rounded down at .9995 so as not to print 60.000): 1 ms apart at most;
    // the sum of two doubles near 2.4e6 days resolves ~5e-10 d = 40 us.
    FUZZ_CHECK(std::abs(a - b) * 86400.0 <= 1e-3 + 1e-4);
    return 0;
}
