// Private: shader compiler logs mapped back to the assembled chunks' files and lines.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace welkin::gl::detail {

/// Rewrites every "source:line" of a GLSL compiler log (Mesa "0:300012(5): ...", NVIDIA
/// "0(300012) : ...", others "ERROR: 0:300012: ...") as "file:line", where chunk k (1-based,
/// `chunkNames[k - 1]`) starts at line k * chunkLines + 1 and line numbers below chunkLines
/// belong to the generated header. Lines of the log are joined with " | ".
std::string mapShaderLog(const std::string& log, const std::vector<std::string>& chunkNames, size_t chunkLines);

}  // namespace welkin::gl::detail
