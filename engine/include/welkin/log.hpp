// Logging through a replaceable callback (no hidden global state: each Logger is a value).
//
//   welkin::Logger log;                                   // prints warnings and errors to stderr
//   std::vector<std::string> seen;
//   log.setCallback([&](welkin::LogLevel, std::string_view m) { seen.emplace_back(m); });
//   log.warn("Sky: observer 1 mm below ground, clamped to 0 m");
#pragma once
#include <functional>
#include <string>
#include <string_view>

namespace welkin {

enum class LogLevel { Debug, Info, Warning, Error };

/// Short name: "debug", "info", "warning", "error".
std::string_view toString(LogLevel level);

using LogCallback = std::function<void(LogLevel, std::string_view message)>;

/// A log sink. The default callback writes messages at or above minLevel() to stderr.
class Logger {
public:
    Logger();
    explicit Logger(LogCallback callback, LogLevel minLevel = LogLevel::Info);

    void setCallback(LogCallback callback);
    void setMinLevel(LogLevel level) { minLevel_ = level; }
    LogLevel minLevel() const { return minLevel_; }

    void log(LogLevel level, std::string_view message) const;
    void debug(std::string_view m) const { log(LogLevel::Debug, m); }
    void info(std::string_view m) const { log(LogLevel::Info, m); }
    void warn(std::string_view m) const { log(LogLevel::Warning, m); }
    void error(std::string_view m) const { log(LogLevel::Error, m); }

private:
    LogCallback callback_;
    LogLevel minLevel_ = LogLevel::Warning;
};

}  // namespace welkin
