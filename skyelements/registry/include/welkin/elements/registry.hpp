// The element registry: every element folder of skyelements/, generated at build time from the
// folders (each declares WELKIN_ELEMENT_DESCRIPTOR(<folder>)). For the command line, JSON scenes,
// the viewer and hosts that pick elements by name.
//
//   for (auto* d : welkin::elements::descriptors()) std::puts(d->name.c_str());  // sky, grid, ...
//   processor.add(welkin::elements::makeElement("grid"));        // throws listing known names
//   for (auto& n : welkin::elements::defaultElements()) processor.add(welkin::elements::makeElement(n));
//   for (auto& n : welkin::elements::expandElementList("default,grid")) ...   // the default set + a grid
#pragma once
#include <welkin/element.hpp>

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace welkin::elements {

/// Every element's descriptor, in the default compositing order: by Layer (background first),
/// then by name.
const std::vector<const ElementDescriptor*>& descriptors();
/// The descriptor named `name`, or nullptr.
const ElementDescriptor* findDescriptor(std::string_view name);
/// Names accepted by makeElement(), in the default compositing order.
std::vector<std::string> knownElements();
/// The elements rendered when none are named (descriptors with inDefaultSet), in the default
/// compositing order.
std::vector<std::string> defaultElements();
/// A new element with default options. Throws welkin::Error "unknown element 'x' (known: a, b)".
std::unique_ptr<SkyElement> makeElement(std::string_view name);
/// Splits a comma list ("stars,sky,grid"), trimming spaces; empty items are an error.
std::vector<std::string> parseElementList(std::string_view list);
/// A scene's element list: parseElementList() with the item `default` replaced by
/// defaultElements(), in place ("default,clouds,rainbow": the default scene, then clouds, then a
/// rainbow over them). Throws welkin::Error for a name listed twice (two instances of one element
/// would declare the same options twice) or an unknown name (listing the known ones).
std::vector<std::string> expandElementList(std::string_view list);

}  // namespace welkin::elements
