// welkin timelapse: a sequence of frames from --from to --to every --step, with every `welkin
// render` option (docs/timelapse.md). Resumable: a frame is written to a temporary file and
// renamed (writeImage), so a frame present in --out is complete and is skipped on the next run;
// the temporary files a killed run left are removed. Optionally a contact sheet and, through
// ffmpeg, a video.
#include "command.hpp"
#include "scene_options.hpp"

#include <welkin/error.hpp>
#include <welkin/gl/context.hpp>
#include <welkin/image.hpp>
#include <welkin/keys.hpp>
#include <welkin/processor.hpp>

#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <regex>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace welkin::cli {

namespace {

namespace fs = std::filesystem;

constexpr long kMaxFrames = 100000;
constexpr int kThumbMaxWidth = 160;  // contact sheet: thumbnails at most this wide, px
constexpr int kLabelHeight = 16;     // contact sheet: the band under each thumbnail for its time, px

struct TimelapseOptions {
    SceneOptions scene;
    CLI::Option* timeOption = nullptr;  // --time is replaced by --from/--to: refused if given
    std::string from, to, step;
    std::string out;
    std::string format = "png";  // png (tone-mapped) | exr (linear cd/m^2)
    std::string contactSheet;
    std::string video;
    double fps = 24;  // video frames per second, [1, 240]
};

/// "30s", "10m", "1.5h", "1d" -> seconds; throws naming --step.
double parseDuration(const std::string& text) {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    const std::string unit = end ? std::string(end) : std::string();
    double scale = 0;
    if (unit == "s") scale = 1;
    else if (unit == "m" || unit == "min") scale = 60;
    else if (unit == "h") scale = 3600;
    else if (unit == "d") scale = 86400;
    if (end == text.c_str() || scale == 0)
        throw Error("--step '" + text + "' is not a duration (a number with s, m, h or d, e.g. 30s, 10m, 1h, 1d)");
    if (!(v > 0) || !std::isfinite(v)) throw Error("--step '" + text + "' must be positive");
    return v * scale;
}

std::string frameName(long i, const std::string& format) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "frame-%05ld.%s", i, format.c_str());
    return buf;
}

// Where ffmpeg is on PATH, or "".
std::string findOnPath(const std::string& program) {
    const char* path = std::getenv("PATH");
    if (!path) return {};
    std::string p = path;
    size_t start = 0;
    while (start <= p.size()) {
        size_t colon = p.find(':', start);
        std::string dir = p.substr(start, colon == std::string::npos ? std::string::npos : colon - start);
        if (dir.empty()) dir = ".";
        const std::string candidate = dir + "/" + program;
        if (::access(candidate.c_str(), X_OK) == 0 && !fs::is_directory(candidate)) return candidate;
        if (colon == std::string::npos) break;
        start = colon + 1;
    }
    return {};
}


// --- progress -----------------------------------------------------------------------------

class Progress {
public:
    Progress(long total, long alreadyDone) : total_(total), done_(alreadyDone), tty_(::isatty(2) != 0) {}
    void frameDone(const std::string& time) {
        ++done_;
        ++rendered_;
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        const double rate = elapsed > 0 ? rendered_ / elapsed : 0;
        const double eta = rate > 0 ? (total_ - done_) / rate : 0;
        char etaText[32];
        std::snprintf(etaText, sizeof etaText, "%ld:%02ld:%02ld", long(eta) / 3600, long(eta) / 60 % 60, long(eta) % 60);
        if (tty_) {
            constexpr int kBar = 30;
            const int filled = int(double(kBar) * done_ / std::max(1L, total_));
            std::string bar = std::string(size_t(filled), '#') + std::string(size_t(kBar - filled), '.');
            std::fprintf(stderr, "\r[%s] %ld/%ld frames  %.2f frames/s  ETA %s  %s ", bar.c_str(), done_, total_, rate, etaText, time.c_str());
            if (done_ == total_) std::fputc('\n', stderr);
        } else {
            std::fprintf(stderr, "frame %ld/%ld  %s  %.2f frames/s  ETA %s\n", done_, total_, time.c_str(), rate, etaText);
        }
        std::fflush(stderr);
    }

private:
    long total_, done_, rendered_ = 0;
    bool tty_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// --- contact sheet ------------------------------------------------------------------------

float srgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }
float linearToSrgb(float v) { return v <= 0.0031308f ? v * 12.92f : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f; }

// A box-filtered thumbnail (averaged in linear light) of a tone-mapped (sRGB-encoded) image.
Image thumbnail(const Image& src, int w, int h) {
    Image t{w, h, 3, std::vector<float>(size_t(w) * size_t(h) * 3)};
    for (int y = 0; y < h; ++y) {
        const int y0 = y * src.height / h, y1 = std::max(y0 + 1, (y + 1) * src.height / h);
        for (int x = 0; x < w; ++x) {
            const int x0 = x * src.width / w, x1 = std::max(x0 + 1, (x + 1) * src.width / w);
            for (int c = 0; c < 3; ++c) {
                double sum = 0;
                for (int yy = y0; yy < y1; ++yy)
                    for (int xx = x0; xx < x1; ++xx) sum += srgbToLinear(std::clamp(src.at(xx, yy, c), 0.0f, 1.0f));
                t.at(x, y, c) = linearToSrgb(float(sum / ((y1 - y0) * (x1 - x0))));
            }
        }
    }
    return t;
}

// Text on the CPU with Dear ImGui's built-in bitmap font (ProggyClean, 13 px): its atlas is
// rasterised without a GL context.
class SheetFont {
public:
    SheetFont() {
        font_ = atlas_.AddFontDefault();
        atlas_.GetTexDataAsAlpha8(&pixels_, &width_, &height_);
    }
    // Draws `text` with its top-left at (x, y), white over the image, clipped to [x, x + maxWidth).
    void draw(Image& img, int x, int y, int maxWidth, const std::string& text) const {
        float pen = float(x);
        for (char ch : text) {
            const ImFontGlyph* g = font_->FindGlyph(ImWchar(static_cast<unsigned char>(ch)));
            if (!g) continue;
            const int gx0 = int(std::lround(pen + g->X0)), gy0 = y + int(std::lround(g->Y0));
            const int gw = int(std::lround(g->X1 - g->X0)), gh = int(std::lround(g->Y1 - g->Y0));
            const int u0 = int(std::lround(g->U0 * float(width_))), v0 = int(std::lround(g->V0 * float(height_)));
            for (int j = 0; j < gh; ++j)
                for (int i = 0; i < gw; ++i) {
                    const int px = gx0 + i, py = gy0 + j;
                    if (px < x || px >= x + maxWidth || px >= img.width || py < 0 || py >= img.height) continue;
                    const float a = float(pixels_[size_t(v0 + j) * size_t(width_) + size_t(u0 + i)]) / 255.0f;
                    for (int c = 0; c < 3; ++c) img.at(px, py, c) = img.at(px, py, c) * (1 - a) + a;
                }
            pen += g->AdvanceX;
        }
    }

private:
    ImFontAtlas atlas_;
    ImFont* font_ = nullptr;
    unsigned char* pixels_ = nullptr;
    int width_ = 0, height_ = 0;
};

struct SheetLayout {
    int thumbW = 0, thumbH = 0, columns = 0, rows = 0;
    int width() const { return columns * thumbW; }
    int height() const { return rows * (thumbH + kLabelHeight); }
};

// Thumbnails at most kThumbMaxWidth wide (the frame's size if smaller), about as many columns
// as rows: columns = ceil(sqrt(frames)).
SheetLayout sheetLayout(long frames, int frameW, int frameH) {
    SheetLayout l;
    l.thumbW = std::min(frameW, kThumbMaxWidth);
    l.thumbH = std::max(1, int(std::lround(double(frameH) * l.thumbW / frameW)));
    l.columns = int(std::ceil(std::sqrt(double(frames))));
    l.rows = int((frames + l.columns - 1) / l.columns);
    return l;
}

// --- video --------------------------------------------------------------------------------

void writeVideo(const std::string& ffmpeg, const TimelapseOptions& o) {
    fs::path target(o.video);
    fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    const std::string tmp = (dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) + ".mp4")).string();
    char fps[32];
    std::snprintf(fps, sizeof fps, "%g", o.fps);
    const std::string pattern = (fs::path(o.out) / ("frame-%05d." + o.format)).string();
    // Even sizes for yuv420p; H.264 when the build has it (libx264), else ffmpeg's own MPEG-4.
    std::vector<std::string> args = {ffmpeg, "-nostdin", "-y", "-loglevel", "error", "-framerate", fps, "-i", pattern,
                                     "-vf", "scale=trunc(iw/2)*2:trunc(ih/2)*2", "-pix_fmt", "yuv420p", tmp};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawn(&pid, ffmpeg.c_str(), nullptr, nullptr, argv.data(), environ) != 0)
        throw Error("--video: cannot start '" + ffmpeg + "'");
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    std::error_code ec, ignored;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        fs::remove(tmp, ignored);
        throw Error("--video '" + o.video + "': ffmpeg failed (status " + std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
    }
    fs::rename(tmp, o.video, ec);
    if (ec) {
        fs::remove(tmp, ignored);
        throw Error("--video '" + o.video + "': " + ec.message());
    }
}

// --- the run ------------------------------------------------------------------------------

int run(const TimelapseOptions& o) {
    // Everything is checked before a frame is rendered or a file touched.
    if (o.timeOption && o.timeOption->count() > 0) throw Error("--time is not a timelapse option: use --from and --to");
    o.scene.validate();
    UtcInstant from, to;
    try {
        from = UtcInstant::parse(o.from);
    } catch (const Error& e) {
        throw Error(std::string("--from ") + e.what());
    }
    try {
        to = UtcInstant::parse(o.to);
    } catch (const Error& e) {
        throw Error(std::string("--to ") + e.what());
    }
    checkAstronomyYear(from, "--from");
    checkAstronomyYear(to, "--to");
    const double stepS = parseDuration(o.step);
    const double spanS = daysBetween(from.julianDate(), to.julianDate()) * 86400.0;
    if (spanS < 0) throw Error("--to " + o.to + " is before --from " + o.from);
    // Frames at from + i step up to and including `to` (a millisecond's slack for rounding).
    const double count = std::floor(spanS / stepS + 1e-3 / stepS) + 1;
    if (count > double(kMaxFrames))
        throw Error("--from/--to/--step give " + std::to_string((long long)count) + " frames; at most " + std::to_string(kMaxFrames));
    const long frames = long(count);
    if (o.format != "png" && o.format != "exr") throw Error("--format '" + o.format + "' unknown (accepted: png, exr)");
    if (!o.contactSheet.empty()) {
        if (!endsWithIgnoringCase(o.contactSheet, ".png")) throw Error("--contact-sheet '" + o.contactSheet + "' must end in .png");
        checkFileWritable(o.contactSheet, "--contact-sheet");
    }
    std::string ffmpeg;
    if (!o.video.empty()) {
        if (!endsWithIgnoringCase(o.video, ".mp4")) throw Error("--video '" + o.video + "' must end in .mp4");
        if (o.format != "png") throw Error("--video needs --format png (ffmpeg encodes the tone-mapped frames)");
        if (!(o.fps >= 1 && o.fps <= 240)) throw Error("--fps " + std::to_string(o.fps) + " not in [1, 240]");
        checkFileWritable(o.video, "--video");
        ffmpeg = findOnPath("ffmpeg");
        if (ffmpeg.empty()) throw Error("--video needs ffmpeg, which is not on PATH (install it, e.g. apt-get install ffmpeg)");
    }
    std::error_code ec;
    const fs::path outDir(o.out);
    if (fs::exists(outDir, ec) && !fs::is_directory(outDir, ec)) throw Error("--out '" + o.out + "' exists and is not a directory");
    if (!fs::exists(outDir, ec)) {
        const fs::path parent = outDir.parent_path().empty() ? fs::path(".") : outDir.parent_path();
        if (!fs::is_directory(parent, ec)) throw Error("--out '" + o.out + "': directory '" + parent.string() + "' does not exist");
        if (!fs::create_directory(outDir, ec) && ec) throw Error("--out '" + o.out + "': " + ec.message());
    }
    if (::access(outDir.c_str(), W_OK) != 0) throw Error("--out '" + o.out + "' is not writable");

    // Resume: temporary files of a killed run (writeImage's ".frame-NNNNN.png.tmpPID.png") go;
    // complete frames stay and are skipped.
    const std::regex stale(R"(\.frame-\d{5}\.(png|exr)\.tmp\d+\.(png|exr))");
    for (const auto& entry : fs::directory_iterator(outDir, ec)) {
        if (std::regex_match(entry.path().filename().string(), stale)) fs::remove(entry.path(), ec);
    }
    std::vector<bool> present(static_cast<size_t>(frames), false);
    long already = 0;
    for (long i = 0; i < frames; ++i) {
        present[size_t(i)] = fs::is_regular_file(outDir / frameName(i, o.format), ec);
        already += present[size_t(i)] ? 1 : 0;
    }
    if (already > 0) std::fprintf(stderr, "%ld of %ld frames already in %s: skipped\n", already, frames, o.out.c_str());

    const Camera cam = o.scene.camera();
    const SheetLayout sheet = sheetLayout(frames, cam.width, cam.height);
    Image contact;
    if (!o.contactSheet.empty()) contact = Image{sheet.width(), sheet.height(), 3, std::vector<float>(size_t(sheet.width()) * size_t(sheet.height()) * 3)};
    SheetFont font;
    auto placeThumb = [&](long i, const Image& toneMapped, const std::string& label) {
        if (o.contactSheet.empty()) return;
        const Image t = thumbnail(toneMapped, sheet.thumbW, sheet.thumbH);
        const int x0 = int(i % sheet.columns) * sheet.thumbW, y0 = int(i / sheet.columns) * (sheet.thumbH + kLabelHeight);
        for (int y = 0; y < t.height; ++y)
            for (int x = 0; x < t.width; ++x)
                for (int c = 0; c < 3; ++c) contact.at(x0 + x, y0 + y, c) = t.at(x, y, c);
        font.draw(contact, x0 + 2, y0 + sheet.thumbH + 1, sheet.thumbW - 2, label);
    };
    auto label = [](const UtcInstant& t) {
        const DateTime& d = t.utc();
        char buf[48];
        std::snprintf(buf, sizeof buf, "%04d-%02d-%02d %02d:%02d:%02dZ", d.year, d.month, d.day, d.hour, d.minute, int(d.second));
        return std::string(buf);
    };

    Logger log;
    auto ctx = gl::HeadlessContext::create({}, log);
    {
        SkyProcessor sky(SkyVars::earth(), log);
        o.scene.apply(sky);
        sky.vars().set(keys::interactive, false);  // every frame complete, whatever --var said
        sky.init();
        Progress progress(frames, already);
        for (long i = 0; i < frames; ++i) {
            const UtcInstant t = from.plusSeconds(double(i) * stepS);
            const std::string path = (outDir / frameName(i, o.format)).string();
            const bool needRender = !present[size_t(i)] || (!o.contactSheet.empty() && o.format != "png");
            if (!needRender) {  // a complete frame of an earlier run: its thumbnail from the file
                if (!o.contactSheet.empty()) placeThumb(i, readImage(path), label(t));
                continue;
            }
            // Each frame as `welkin render` makes it, whatever came before: every generator runs
            // (no table kept within its tolerance from the previous frame) and the eye starts
            // adapted to the frame. A frame of a resumed run equals the uninterrupted run's.
            sky.setTime(t);
            for (Generator* g : sky.generatorOrder()) g->invalidate();
            sky.resetAdaptation();
            sky.renderFrame();
            if (!present[size_t(i)]) {
                Image img = o.format == "exr" ? sky.readHdr() : sky.readToneMapped();
                for (float v : img.pixels)
                    if (!std::isfinite(v)) throw Error("frame " + std::to_string(i) + " (" + t.toIso() + ") has a non-finite pixel; not written");
                writeImage(img, path);  // temporary file, then rename: never a partial frame
            }
            if (!o.contactSheet.empty()) placeThumb(i, o.format == "png" ? readImage(path) : sky.readToneMapped(), label(t));
            if (!present[size_t(i)]) progress.frameDone(t.toIso());
        }
        sky.release();
    }
    if (!o.contactSheet.empty()) {
        writeImage(contact, o.contactSheet);
        std::printf("%s\n", o.contactSheet.c_str());
    }
    if (!o.video.empty()) {
        writeVideo(ffmpeg, o);
        std::printf("%s\n", o.video.c_str());
    }
    std::printf("%ld frames in %s\n", frames, o.out.c_str());
    return 0;
}

Registrar reg("timelapse", "render frames from --from to --to every --step (resumable), a contact sheet, a video", [](CLI::App& sub) {
    auto o = std::make_shared<TimelapseOptions>();  // the action below owns it
    o->scene.addTo(sub, false);
    o->timeOption = sub.get_option("--time");
    o->timeOption->group("");  // hidden from --help: refused with a pointer to --from and --to
    sub.get_option("--lat")->required();
    sub.get_option("--lon")->required();
    sub.add_option("--from", o->from, "first frame's instant, ISO 8601")->required();
    sub.add_option("--to", o->to, "last instant, ISO 8601 (a frame falls on it when --step divides the span)")->required();
    sub.add_option("--step", o->step, "time between frames: a number with s, m, h or d (30s, 10m, 1h, 1d); at most 100000 frames")
        ->required();
    sub.add_option("--out", o->out, "directory of the frames frame-00000.png ... (created if missing; frames already there are kept)")
        ->required();
    sub.add_option("--format", o->format, "png (tone-mapped sRGB) | exr (linear radiance, cd/m^2)")->capture_default_str();
    sub.add_option("--contact-sheet", o->contactSheet, "also write a grid of thumbnails with their times (.png)");
    sub.add_option("--video", o->video, "also encode the frames with ffmpeg (.mp4; needs ffmpeg on PATH and --format png)");
    sub.add_option("--fps", o->fps, "video frames per second, [1, 240]")->capture_default_str();
    return [o]() { return run(*o); };
});

}  // namespace
}  // namespace welkin::cli
