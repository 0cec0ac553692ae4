// Where welkin keeps tables it computes once and reads back on later runs (the rainbow's Mie
// tables, the halos' crystal tables, an element's own).
//
//   const std::filesystem::path file = welkin::cacheDirectory() / "mytable-0123abcd.bin";
//   // read it if present and valid, else build, write to a temporary name beside it, rename
//
// The folder is $WELKIN_CACHE_DIR if set, else $XDG_CACHE_HOME/welkin, else ~/.cache/welkin,
// else the system's temporary folder /welkin. It is not created here: the writer creates it.
#pragma once
#include <filesystem>

namespace welkin {

/// The cache folder (see above); a pure function of the environment.
std::filesystem::path cacheDirectory();

}  // namespace welkin
