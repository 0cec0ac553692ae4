// Edits of a running scene shared by `welkin view`'s panel and its tests (no ImGui here).
//
//   std::string error = setElementEnabled(sky, "grid", true);   // "" on success
//   if (!error.empty()) showInRed(error);
#pragma once
#include <welkin/processor.hpp>

#include <string>

namespace welkin::cli {

/// Turns the element `name` (a name of the element registry) on or off in `sky`, whose GL
/// context must be current. On: added in the default compositing order (the elements that come
/// after it are taken out and put back behind it) and initialised at once; if that fails it is
/// taken out again. Off: removed and its GL resources released. Returns "" or the one-line reason
/// it could not be done (unknown name, failed initialisation); never throws welkin::Error.
std::string setElementEnabled(SkyProcessor& sky, const std::string& name, bool on);

}  // namespace welkin::cli
