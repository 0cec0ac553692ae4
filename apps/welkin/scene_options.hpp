// Options shared by `welkin render` and `welkin view`: time, place, elements, camera, exposure.
#pragma once
#include <CLI/CLI.hpp>

#include <welkin/processor.hpp>

#include "output_paths.hpp"

#include <string>
#include <vector>

namespace welkin::cli {

struct SceneOptions {
    std::string time;
    double latDeg = 0, lonDeg = 0, heightM = 0;
    std::string elements;
    bool elementsGiven = false;  // --elements present (an empty list is then an error)
    std::string projection = "perspective";
    double azDeg = 180, altDeg = 20, fovDeg = 60;
    int cubeFace = 0;
    std::string size = "1280x720";
    std::string exposure = "auto";
    std::string quality = "medium";
    std::vector<std::string> vars;  ///< --var KEY=VALUE, in order
    /// render.point_sources set before the --var values (which may override it): perceptual for
    /// displayed images (welkin view, PNGs, demos), physical for HDR output (welkin render to .exr).
    std::string pointSources = "perceptual";

    /// Adds the options to a subcommand.
    void addTo(CLI::App& app, bool requireTimeAndPlace);
    /// Validates everything (throws welkin::Error naming the option and range).
    void validate() const;
    UtcInstant instant() const;
    Observer observer() const;
    Camera camera() const;
    Exposure exposureSetting() const;
    int qualityLevel() const;
    std::vector<std::string> elementNames() const;
    /// Adds the elements and the scene state to a processor, then the --var values (after the
    /// elements, which declare their options).
    void apply(SkyProcessor& processor) const;
    /// Sets the --var values on `processor` (each "KEY=VALUE"); throws naming the option.
    void applyVars(SkyProcessor& processor) const;
};

// endsWithIgnoringCase(), checkFileWritable(): output_paths.hpp.

/// Throws welkin::Error naming `option` if `t`'s civil year is outside the astronomy's span
/// [-2000, 6000] (astro::kEphemerisFirstYear, kEphemerisLastYear).
void checkAstronomyYear(const UtcInstant& t, const char* option);

/// Parses "WxH" (each in [1, 16384]); throws naming `option`.
void parseSize(const std::string& text, const char* option, int& width, int& height);

}  // namespace welkin::cli
