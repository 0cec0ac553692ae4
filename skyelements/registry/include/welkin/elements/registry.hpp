// Element factory by name, for the command line, JSON scenes and the viewer.
//
//   auto names = welkin::elements::knownElements();             // {"grid", ...}
//   processor.add(welkin::elements::makeElement("grid"));        // throws listing known names
#pragma once
#include <welkin/element.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace welkin::elements {

/// Names accepted by makeElement(), in the recommended compositing order.
std::vector<std::string> knownElements();
/// The elements rendered when none are named: every known element except overlays (grid),
/// or {"grid"} while no other element exists.
std::vector<std::string> defaultElements();
/// A new element with default options. Throws welkin::Error "unknown element 'x' (known: a, b)".
std::unique_ptr<SkyElement> makeElement(std::string_view name);
/// Splits a comma list ("stars,sky,grid"), trimming spaces; empty items are an error.
std::vector<std::string> parseElementList(std::string_view list);

}  // namespace welkin::elements
