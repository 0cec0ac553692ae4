#include "view_panel.hpp"

#include "scene_edit.hpp"

#include <welkin/elements/registry.hpp>
#include <welkin/error.hpp>
#include <welkin/eye.hpp>
#include <welkin/keys.hpp>

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <imgui_stdlib.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <numbers>

namespace welkin::cli {

namespace {
constexpr double kDeg = std::numbers::pi / 180;
const ImVec4 kErrorColour{1.0f, 0.45f, 0.35f, 1.0f};

std::string formatNumber(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

// Keys whose three components are a colour (edited with a colour picker).
bool isColourKey(const KeyInfo& k) {
    auto has = [&](const char* w) { return k.name.find(w) != std::string::npos || k.description.find(w) != std::string::npos; };
    return has("colour") || has("color") || has("albedo") || has("tint");
}
}  // namespace

const std::vector<Site>& famousSites() {
    // Coordinates (WGS84, degrees; heights above the ellipsoid, m, rounded).
    static const std::vector<Site> sites = {
        {"Kalabsha temple (Egypt)", 23.96, 32.87, 190},
        {"Kiti, Panagia Angeloktisti (Cyprus)", 34.848, 33.571, 10},
        {"Valletta (Malta)", 35.90, 14.51, 50},
        {"Mauna Kea Observatories (Hawaii)", 19.82, -155.47, 4205},
        {"Paranal Observatory (Chile)", -24.63, -70.40, 2635},
        {"Roque de los Muchachos (La Palma)", 28.76, -17.89, 2396},
        {"Royal Observatory Greenwich", 51.48, 0.0, 45},
        {"North Pole", 90.0, 0.0, 0},
        {"South Pole (Amundsen-Scott station)", -90.0, 0.0, 2835},
    };
    return sites;
}

ViewPanel::ViewPanel(GLFWwindow* window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini: the panel's layout is the same on every start
    io.LogFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 410 core");
}

ViewPanel::~ViewPanel() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

bool ViewPanel::wantsMouse() const { return visible && ImGui::GetIO().WantCaptureMouse; }
bool ViewPanel::wantsKeyboard() const { return visible && ImGui::GetIO().WantCaptureKeyboard; }

void ViewPanel::draw(SkyProcessor& sky, ViewClock& clock, Camera& camera, Logger& log) {
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    // Top left, 40 % of the width (240 to 420 px), the window's height less a margin.
    const float width = std::clamp(display.x * 0.4f, 240.0f, 420.0f);
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Once);
    ImGui::SetNextWindowSize(ImVec2(width, std::max(100.0f, display.y - 16)), ImGuiCond_Once);
    ImGui::SetNextWindowBgAlpha(0.85f);
    if (ImGui::Begin("welkin (H hides)")) {
        if (!error_.empty()) {
            ImGui::PushStyleColor(ImGuiCol_Text, kErrorColour);
            ImGui::TextWrapped("%s", error_.c_str());
            ImGui::PopStyleColor();
        }
        auto open = [&] {
            if (expandAll) ImGui::SetNextItemOpen(true, ImGuiCond_Once);
        };
        open();
        if (ImGui::CollapsingHeader("Date and time", ImGuiTreeNodeFlags_DefaultOpen)) timeSection(sky, clock);
        open();
        if (ImGui::CollapsingHeader("Place", ImGuiTreeNodeFlags_DefaultOpen)) placeSection(sky);
        open();
        if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) displaySection(sky, camera);
        open();
        if (ImGui::CollapsingHeader("Elements")) elementsSection(sky, log);
        open();
        if (ImGui::CollapsingHeader("Frame time", ImGuiTreeNodeFlags_DefaultOpen)) timingSection(sky);
    }
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void ViewPanel::timeSection(SkyProcessor& sky, ViewClock& clock) {
    const UtcInstant now = sky.time();
    ImGui::Text("%s", now.toIso().c_str());
    DateTime dt = now.utc();
    bool changed = false;
    // The calendar: a month's grid of days; < and > page through the months.
    if (calendarMonth_ < 0) {  // the first frame: the clock's month
        calendarYear_ = dt.year;
        calendarMonth_ = dt.month - 1;
    }
    if (ImGui::ArrowButton("##prevmonth", ImGuiDir_Left) && --calendarMonth_ < 0) {
        calendarMonth_ = 11;
        --calendarYear_;
    }
    ImGui::SameLine();
    static const char* kMonths[] = {"January", "February", "March",     "April",   "May",      "June",
                                    "July",    "August",   "September", "October", "November", "December"};
    ImGui::SetNextItemWidth(92);
    ImGui::Combo("##month", &calendarMonth_, kMonths, 12);
    calendarMonth_ = std::clamp(calendarMonth_, 0, 11);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(48);
    ImGui::InputInt("##year", &calendarYear_, 0);
    calendarYear_ = std::clamp(calendarYear_, -3999, 9999);
    ImGui::SameLine();
    if (ImGui::ArrowButton("##nextmonth", ImGuiDir_Right) && ++calendarMonth_ > 11) {
        calendarMonth_ = 0;
        ++calendarYear_;
    }
    const int month = calendarMonth_ + 1;
    // Weekday of the 1st: Julian day number + 1 mod 7 is 0 on Sundays.
    const JulianDate first = toJulianDate(DateTime{calendarYear_, month, 1, 12, 0, 0.0});
    const int firstWeekday = int(((long long)std::floor(first.value() + 0.5) + 1) % 7);  // 0 Sunday
    const int firstColumn = (firstWeekday + 6) % 7;                                      // Monday first
    if (ImGui::BeginTable("calendar", 7, ImGuiTableFlags_SizingFixedFit)) {
        for (const char* d : {"Mo", "Tu", "We", "Th", "Fr", "Sa", "Su"}) ImGui::TableSetupColumn(d);
        ImGui::TableHeadersRow();
        const int days = daysInMonth(calendarYear_, month);
        for (int cell = 0; cell < firstColumn + days; ++cell) {
            ImGui::TableNextColumn();
            if (cell < firstColumn) continue;
            const int day = cell - firstColumn + 1;
            const bool today = dt.year == calendarYear_ && dt.month == month && dt.day == day;
            char label[16];
            std::snprintf(label, sizeof label, "%2d", day);
            if (today) ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.8f, 0.45f, 0.1f, 1.0f));
            if (ImGui::SmallButton(label)) {
                dt.year = calendarYear_;
                dt.month = month;
                dt.day = day;
                changed = true;
            }
            if (today) ImGui::PopStyleColor();
        }
        ImGui::EndTable();
    }
    // Hours, minutes and seconds, each on its own slider (UTC).
    int hms[3] = {dt.hour, dt.minute, int(std::floor(dt.second))};
    const int hmsMax[3] = {23, 59, 59};
    const char* hmsId[3] = {"##hour", "##minute", "##second"};
    const float hmsWidth = std::max(30.0f, (ImGui::GetContentRegionAvail().x - 70) / 3);
    for (int k = 0; k < 3; ++k) {
        if (k) ImGui::SameLine(0, 2);
        ImGui::SetNextItemWidth(hmsWidth);
        if (ImGui::SliderInt(hmsId[k], &hms[k], 0, hmsMax[k], k == 0 ? "%02d h" : k == 1 ? "%02d m" : "%02d s",
                             ImGuiSliderFlags_AlwaysClamp)) {
            dt.hour = hms[0];
            dt.minute = hms[1];
            dt.second = hms[2];
            changed = true;
        }
    }
    ImGui::SameLine();
    ImGui::TextUnformatted("UTC");
    if (ImGui::Button("Now")) {
        const std::time_t t = std::time(nullptr);
        std::tm u{};
        gmtime_r(&t, &u);
        dt = DateTime{u.tm_year + 1900, u.tm_mon + 1, u.tm_mday, u.tm_hour, u.tm_min, double(std::min(u.tm_sec, 59))};
        calendarYear_ = dt.year;
        calendarMonth_ = dt.month - 1;
        changed = true;
    }
    if (changed) {
        try {
            clock.start = UtcInstant::fromDateTime(dt);
            clock.offsetSeconds = 0;
            error_.clear();
        } catch (const Error& e) {
            error_ = std::string("time: ") + e.what();
        }
    }
    // Speed: simulated seconds per real second, on a logarithmic slider (negative runs backwards).
    ImGui::SameLine();
    if (ImGui::Button(clock.paused ? "Play" : "Pause")) clock.paused = !clock.paused;
    ImGui::SameLine();
    if (ImGui::Button("Reverse")) clock.speed = -clock.speed;
    ImGui::SameLine();
    if (ImGui::Button("1x")) clock.speed = 1;
    static const double kSpeedMin = -1e7, kSpeedMax = 1e7;
    ImGui::SetNextItemWidth(-60);
    ImGui::SliderScalar("speed", ImGuiDataType_Double, &clock.speed, &kSpeedMin, &kSpeedMax, "%.4g x",
                        ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
}

void ViewPanel::placeSection(SkyProcessor& sky) {
    Observer o = sky.observer();
    double lat = o.latitudeRad / kDeg, lon = o.longitudeRad / kDeg, h = o.heightMeters;
    bool changed = false;
    static const double latMin = -90, latMax = 90, lonMin = -180, lonMax = 180, hMin = -1e4, hMax = 1e9;
    ImGui::SetNextItemWidth(-110);
    changed |= ImGui::DragScalar("latitude, deg", ImGuiDataType_Double, &lat, 0.05f, &latMin, &latMax, "%.4f", ImGuiSliderFlags_AlwaysClamp);
    ImGui::SetNextItemWidth(-110);
    changed |= ImGui::DragScalar("longitude, deg", ImGuiDataType_Double, &lon, 0.05f, &lonMin, &lonMax, "%.4f", ImGuiSliderFlags_AlwaysClamp);
    ImGui::SetNextItemWidth(-110);
    changed |= ImGui::DragScalar("height, m", ImGuiDataType_Double, &h, 10.0f, &hMin, &hMax, "%.0f",
                                 ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic);
    ImGui::SetNextItemWidth(-110);
    if (ImGui::BeginCombo("famous sites", "choose...")) {
        for (const Site& s : famousSites()) {
            if (ImGui::Selectable(s.name)) {
                lat = s.latDeg;
                lon = s.lonDeg;
                h = s.heightM;
                changed = true;
            }
        }
        ImGui::EndCombo();
    }
    if (changed) {
        try {
            sky.setObserver({lat * kDeg, lon * kDeg, h});
            error_.clear();
        } catch (const Error& e) {
            error_ = std::string("place: ") + e.what();
        }
    }
}

void ViewPanel::displaySection(SkyProcessor& sky, Camera& camera) {
    SkyVars& v = sky.vars();
    // Quality preset (render.quality).
    int q = keys::quality.valueOr(v, 1);
    const char* qualities[] = {"low", "medium", "high", "reference"};
    ImGui::SetNextItemWidth(-110);
    if (ImGui::Combo("quality", &q, qualities, 4)) v.set(keys::quality, std::clamp(q, 0, 3));
    // Exposure: automatic (the eye's adaptation, with compensation) or a manual EV100.
    Exposure e = sky.exposure();
    bool changed = ImGui::Checkbox("automatic exposure", &e.automatic);
    static const double evMin = -20, evMax = 30, compMin = -10, compMax = 10;
    ImGui::SetNextItemWidth(-110);
    if (e.automatic) {
        changed |= ImGui::SliderScalar("compensation, EV", ImGuiDataType_Double, &e.compensationEv, &compMin, &compMax, "%.1f",
                                       ImGuiSliderFlags_AlwaysClamp);
        ImGui::Text("adapted EV100 %.2f", sky.lastEv100());
    } else {
        changed |= ImGui::SliderScalar("EV100", ImGuiDataType_Double, &e.ev100, &evMin, &evMax, "%.1f", ImGuiSliderFlags_AlwaysClamp);
    }
    if (changed) sky.setExposure(e);
    // Night vision: the eye's per-pixel mesopic and scotopic colour (eye.mesopic). The keys shown
    // here are shown again under their element: a scope of their own keeps the widgets apart.
    ImGui::PushID("display");
    if (v.contains(eye::keys::mesopic.name())) {
        ImGui::TextUnformatted("night vision (eye.mesopic)");
        keyEditor(sky, eye::keys::mesopic.name());
    }
    // Point sources: perceptual (the eye's threshold against the sky, the viewer's default) or
    // physical (flux per pixel, as in an EXR).
    if (v.contains("render.point_sources")) {
        ImGui::TextUnformatted("point sources (render.point_sources)");
        keyEditor(sky, "render.point_sources");
    }
    // Labels: whichever of the labelling keys the scene's elements declare.
    for (const char* k : {"planet.labels", "planet.label_magnitude", "constellations.labels", "stars.labels", "grid.ecliptic"}) {
        if (!v.contains(k)) continue;
        ImGui::TextUnformatted(k);
        keyEditor(sky, k);
    }
    ImGui::PopID();
    // Camera.
    int proj = int(camera.projection);
    const char* projections[] = {"perspective", "fisheye", "equirect", "cube face"};
    ImGui::SetNextItemWidth(-110);
    if (ImGui::Combo("projection", &proj, projections, 4)) camera.projection = Projection(std::clamp(proj, 0, 3));
    double fov = camera.verticalFovRad / kDeg;
    static const double fovMin = 0.5, fovMax = 150;
    ImGui::SetNextItemWidth(-110);
    if (ImGui::SliderScalar("field of view, deg", ImGuiDataType_Double, &fov, &fovMin, &fovMax, "%.1f", ImGuiSliderFlags_AlwaysClamp))
        camera.verticalFovRad = fov * kDeg;
}

bool ViewPanel::keyEditor(SkyProcessor& sky, const std::string& name) {
    SkyVars& v = sky.vars();
    const std::optional<KeyInfo> info = v.info(name);
    if (!info) return false;
    const std::string type = info->typeName;
    const std::string id = "##" + name;
    std::string text;  // the new value, in setFromString()'s syntax
    bool submitted = false;  // a string key's text was entered (it may be empty)
    const std::vector<double> num = v.numeric(name);
    const double* lo = info->range ? &info->range->min : nullptr;
    const double* hi = info->range ? &info->range->max : nullptr;
    // A range spanning more than three decades above zero is edited on a logarithmic scale.
    const bool logScale = info->range && info->range->min > 0 && info->range->max / info->range->min > 1e3;
    const ImGuiSliderFlags flags = ImGuiSliderFlags_AlwaysClamp | (logScale ? ImGuiSliderFlags_Logarithmic : 0);
    ImGui::SetNextItemWidth(-1);
    if (type == "bool") {
        bool b = !num.empty() && num[0] != 0;
        ImGui::SameLine();
        if (ImGui::Checkbox(id.c_str(), &b)) text = b ? "true" : "false";
    } else if (type == "int") {
        int i = num.empty() ? 0 : int(num[0]);
        if (info->range) {
            int a = int(info->range->min), b = int(info->range->max);
            if (ImGui::SliderInt(id.c_str(), &i, a, b, "%d", ImGuiSliderFlags_AlwaysClamp)) text = std::to_string(i);
        } else if (ImGui::InputInt(id.c_str(), &i, 1, 10, ImGuiInputTextFlags_EnterReturnsTrue)) {
            text = std::to_string(i);
        }
    } else if (type == "double") {
        double d = num.empty() ? 0 : num[0];
        const char* fmt = logScale ? "%.4g" : "%.5g";
        bool ch = info->range ? ImGui::SliderScalar(id.c_str(), ImGuiDataType_Double, &d, lo, hi, fmt, flags)
                              : ImGui::InputDouble(id.c_str(), &d, 0, 0, "%.6g", ImGuiInputTextFlags_EnterReturnsTrue);
        if (ch) text = formatNumber(d);
    } else if (type == "dvec2" || type == "dvec3" || type == "dvec4") {
        const int n = type == "dvec2" ? 2 : type == "dvec3" ? 3 : 4;
        double d[4] = {0, 0, 0, 0};
        for (int k = 0; k < n && k < int(num.size()); ++k) d[k] = num[size_t(k)];
        bool ch = false;
        if (n == 3 && isColourKey(*info) && info->range && info->range->min <= 0 && info->range->max >= 1) {
            float f[3] = {float(d[0]), float(d[1]), float(d[2])};
            if ((ch = ImGui::ColorEdit3(id.c_str(), f, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR)))
                for (int k = 0; k < 3; ++k) d[k] = f[k];
        } else if (info->range) {
            ch = ImGui::DragScalarN(id.c_str(), ImGuiDataType_Double, d, n, float((info->range->max - info->range->min) / 500), lo, hi,
                                    "%.4g", flags);
        } else {
            ch = ImGui::InputScalarN(id.c_str(), ImGuiDataType_Double, d, n, nullptr, nullptr, "%.6g", ImGuiInputTextFlags_EnterReturnsTrue);
        }
        if (ch) {
            for (int k = 0; k < n; ++k) text += (k ? "," : "") + formatNumber(d[k]);
        }
    } else if (type == "string") {
        auto it = std::find(stringKeys_.begin(), stringKeys_.end(), name);
        if (it == stringKeys_.end()) {
            stringKeys_.push_back(name);
            stringEdits_.push_back(v.valueString(name));
            it = stringKeys_.end() - 1;
        }
        std::string& edit = stringEdits_[size_t(it - stringKeys_.begin())];
        // Applied on Enter (an empty text too); while not being edited the field follows the key.
        if (ImGui::InputText(id.c_str(), &edit, ImGuiInputTextFlags_EnterReturnsTrue)) submitted = true;
        if (!ImGui::IsItemActive() && !submitted) edit = v.valueString(name);
        if (submitted) text = edit;
    } else {
        ImGui::TextDisabled("(%s: not editable here)", type.c_str());
    }
    if (ImGui::IsItemHovered() && !info->description.empty())
        ImGui::SetTooltip("%s%s%s", info->description.c_str(), info->unit.empty() ? "" : ", ", info->unit.c_str());
    if (text.empty() && !submitted) return false;
    try {
        sky.setOption(name, text);  // checked against the key's type and range; outputs refused
        error_.clear();
        return true;
    } catch (const Error& e) {
        error_ = e.what();
        return false;
    }
}

void ViewPanel::setElementOn(SkyProcessor& sky, const std::string& name, bool on, Logger& log) {
    error_ = setElementEnabled(sky, name, on);
    if (!error_.empty()) log.warn(error_);
}

void ViewPanel::elementsSection(SkyProcessor& sky, Logger& log) {
    for (const std::string& name : elements::knownElements()) {
        SkyElement* e = sky.find(name);
        bool on = e != nullptr;
        if (ImGui::Checkbox(("##on-" + name).c_str(), &on)) {
            setElementOn(sky, name, on, log);
            e = sky.find(name);
        }
        ImGui::SameLine();
        if (!e) {
            ImGui::TextDisabled("%s", name.c_str());
            continue;
        }
        if (expandAll) ImGui::SetNextItemOpen(true, ImGuiCond_Once);
        if (ImGui::TreeNode(name.c_str())) {
            ImGui::PushID(name.c_str());
            if (e->optionKeys().empty()) ImGui::TextDisabled("(no keys)");
            for (const KeyInfo& k : e->optionKeys()) {
                ImGui::TextUnformatted(k.name.c_str());
                if (k.typeName != std::string("bool")) ImGui::Indent();
                keyEditor(sky, k.name);
                if (k.typeName != std::string("bool")) ImGui::Unindent();
            }
            ImGui::PopID();
            ImGui::TreePop();
        }
    }
}

void ViewPanel::timingSection(SkyProcessor& sky) {
    const auto now = std::chrono::steady_clock::now();
    if (stats_.is_null() || now - statsAt_ > std::chrono::milliseconds(500)) {
        stats_ = sky.stats();
        statsAt_ = now;
    }
    ImGui::Text("%.1f frames/s (%.1f ms)", double(ImGui::GetIO().Framerate), 1000.0 / std::max(1e-3, double(ImGui::GetIO().Framerate)));
    auto ms = [](const nlohmann::json& j, const char* k) { return j.contains(k) && j[k].is_number() ? j[k].get<double>() : 0.0; };
    ImGui::Text("frame %.2f ms: generators %.2f, tone map %.2f", ms(stats_, "frame_ms"), ms(stats_, "generators_ms"), ms(stats_, "tonemap_ms"));
    if (!stats_.value("timing_includes_gpu", false)) ImGui::TextDisabled("CPU time only (started with --no-panel)");
    if (!ImGui::BeginTable("timing", 3, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) return;
    ImGui::TableSetupColumn("element / generator");
    ImGui::TableSetupColumn("update ms");
    ImGui::TableSetupColumn("render ms");
    ImGui::TableHeadersRow();
    if (stats_.contains("elements")) {
        for (const auto& e : stats_["elements"]) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(e.value("name", "").c_str());
            ImGui::TableNextColumn();
            ImGui::Text("%.2f", ms(e, "update_ms"));
            ImGui::TableNextColumn();
            ImGui::Text("%.2f", ms(e, "render_ms"));
            if (!e.contains("generators")) continue;
            for (const auto& g : e["generators"]) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::Text("  %s (%d runs)", g.value("name", "").c_str(), g.value("runs", 0));
                ImGui::TableNextColumn();
                ImGui::Text("%.2f", ms(g, "last_ms"));
                ImGui::TableNextColumn();
            }
        }
    }
    // The processor's own generators (the astronomy): in the run order, not owned by an element.
    if (stats_.contains("generators")) {
        for (const auto& g : stats_["generators"]) {
            bool owned = false;
            for (const auto& e : stats_.value("elements", nlohmann::json::array()))
                for (const auto& eg : e.value("generators", nlohmann::json::array())) owned |= eg.value("name", "") == g.value("name", "");
            if (owned) continue;
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::Text("%s (%d runs)", g.value("name", "").c_str(), g.value("runs", 0));
            ImGui::TableNextColumn();
            ImGui::Text("%.2f", ms(g, "last_ms"));
            ImGui::TableNextColumn();
        }
    }
    ImGui::EndTable();
}

}  // namespace welkin::cli
