// The command's output-file checks (`welkin render --out/--stats/--lighting`, `welkin timelapse
// --contact-sheet/--video`): run before any rendering, so a bad path fails at once with a
// one-line error naming the option. File-system queries only: nothing is created or written.
//
//   welkin::cli::checkRenderOutputPaths("sky.png", "stats.json", "");   // throws welkin::Error
#pragma once
#include <string>

namespace welkin::cli {

/// True if `path` ends in `ext` ("…", lower case), ignoring the case of `path`.
bool endsWithIgnoringCase(std::string path, const std::string& ext);
/// Checks that a file can be created at `path` before any work: its directory exists and is
/// writable, it is not a directory, and an existing file there is writable. Throws welkin::Error
/// naming `option` ("--stats '…': directory '…' does not exist").
void checkFileWritable(const std::string& path, const char* option);
/// Checks `welkin render`'s outputs: `out` an image path (welkin::checkWritable), `stats` and
/// `lighting` (empty: not asked for) .json files that can be written and are not the same file
/// (compared after resolving ".", ".." and symbolic links). Throws welkin::Error naming the option.
void checkRenderOutputPaths(const std::string& out, const std::string& stats, const std::string& lighting);

}  // namespace welkin::cli
