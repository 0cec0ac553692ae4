// The Dear ImGui panel of `welkin view` (docs/viewer.md): date and time with a calendar, time
// speed, place with a list of famous sites, elements on and off with each element's keys,
// quality, exposure, night vision, labels, and the frame time of every element and generator.
//
//   ViewPanel panel(window);               // after the window's own GLFW callbacks are installed
//   ...  sky.renderFrame(); sky.toneMapInto(0);
//   if (panel.visible) panel.draw(sky, clock, camera, log);   // over the sky, in framebuffer 0
//   if (!panel.wantsMouse()) { /* the mouse moves the camera */ }
//
// The panel edits the processor directly (its SkyVars through setFromString(), so every value is
// checked against the key's type and range; a refused value is shown in the panel, never thrown),
// and the viewer's clock and camera. Keys typed into a text field are not seen by the viewer.
#pragma once
#include <welkin/camera.hpp>
#include <welkin/log.hpp>
#include <welkin/processor.hpp>
#include <welkin/time.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>
#include <vector>

struct GLFWwindow;

namespace welkin::cli {

/// The viewer's clock: the shown instant is start + offsetSeconds.
struct ViewClock {
    UtcInstant start;            ///< the instant at offsetSeconds 0
    double offsetSeconds = 0.0;  ///< simulated seconds since start
    double speed = 60.0;         ///< simulated seconds per real second, [-1e7, 1e7]
    bool paused = false;
};

/// A place in the panel's list (degrees, metres above the ellipsoid).
struct Site {
    const char* name;
    double latDeg, lonDeg, heightM;
};
/// The demos' sites, observatories and the poles.
const std::vector<Site>& famousSites();

class ViewPanel {
public:
    /// Creates the ImGui context and its GLFW and OpenGL 3 backends on `window` (its context
    /// current). The backends chain the window's callbacks installed before this call.
    explicit ViewPanel(GLFWwindow* window);
    ~ViewPanel();
    ViewPanel(const ViewPanel&) = delete;
    ViewPanel& operator=(const ViewPanel&) = delete;

    bool visible = true;     ///< drawn this frame (H or Tab toggles it in the viewer)
    bool expandAll = false;  ///< open every section and element on the first frame (screenshots, tests)

    /// The panel has the mouse (hovered or dragging one of its widgets) / the keyboard (a text
    /// field is being edited); false while hidden.
    bool wantsMouse() const;
    bool wantsKeyboard() const;

    /// Builds the panel for this frame, applies the user's edits to `sky`, `clock` and `camera`,
    /// and draws it into the default framebuffer (over what is there).
    void draw(SkyProcessor& sky, ViewClock& clock, Camera& camera, Logger& log);

private:
    void timeSection(SkyProcessor& sky, ViewClock& clock);
    void placeSection(SkyProcessor& sky);
    void displaySection(SkyProcessor& sky, Camera& camera);
    void elementsSection(SkyProcessor& sky, Logger& log);
    void timingSection(SkyProcessor& sky);
    /// An editor for one SkyVars key chosen by its type and range; returns true if it changed.
    bool keyEditor(SkyProcessor& sky, const std::string& name);
    void setElementOn(SkyProcessor& sky, const std::string& name, bool on, Logger& log);

    std::string error_;  // the last refused edit, shown in red until the next edit succeeds
    std::vector<std::string> stringEdits_;  // text being typed into string keys, by key
    std::vector<std::string> stringKeys_;
    nlohmann::json stats_;  // the processor's stats, refreshed twice a second
    std::chrono::steady_clock::time_point statsAt_{};
    int calendarYear_ = 0, calendarMonth_ = -1;  // the month the calendar shows (month 0-based; -1: not yet set)
};

}  // namespace welkin::cli
