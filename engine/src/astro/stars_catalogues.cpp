// Star catalogue loaders: kstars stars.dat, Yale BSC5, HYG CSV.
#include <welkin/astro/stars.hpp>
#include <welkin/error.hpp>

namespace welkin::astro {

std::vector<Star> parseKStarsCatalogue(const std::string&, const std::string& source, double) {
    throw Error("astro::parseKStarsCatalogue(" + source + "): not implemented yet");
}
std::vector<Star> parseYaleBrightStarCatalogue(const std::string&, const std::string& source, double) {
    throw Error("astro::parseYaleBrightStarCatalogue(" + source + "): not implemented yet");
}
std::vector<Star> parseHygCsv(const std::string&, const std::string& source, double) {
    throw Error("astro::parseHygCsv(" + source + "): not implemented yet");
}
std::vector<Star> loadKStarsCatalogue(const std::string& path, double m) { return parseKStarsCatalogue({}, path, m); }
std::vector<Star> loadYaleBrightStarCatalogue(const std::string& path, double m) { return parseYaleBrightStarCatalogue({}, path, m); }
std::vector<Star> loadHygCsv(const std::string& path, double m) { return parseHygCsv({}, path, m); }

}  // namespace welkin::astro
