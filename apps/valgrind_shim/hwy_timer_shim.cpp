// LD_PRELOAD shim for running `welkin` under valgrind 3.19 (Debian 12): libhwy (Highway, loaded
// through OpenImageIO and libjxl) calls hwy::platform::TimerResolution() from its initialiser,
// which executes RDTSCP, an instruction valgrind 3.19 does not decode (SIGILL at load). This
// definition takes its place; Highway uses the value only for its own timers, which welkin never
// calls. Built as a module beside the welkin command; `welkin bench all` preloads it into the
// callgrind run of `welkin bench framework`.
#include <cstdint>

namespace hwy::platform {
uint64_t TimerResolution() { return 1; }  // ticks: any positive value
}  // namespace hwy::platform
