#include <welkin/log.hpp>

#include <cstdio>

namespace welkin {

std::string_view toString(LogLevel level) {
    switch (level) {
        case LogLevel::Debug: return "debug";
        case LogLevel::Info: return "info";
        case LogLevel::Warning: return "warning";
        case LogLevel::Error: return "error";
    }
    return "?";
}

namespace {
void stderrSink(LogLevel level, std::string_view message) {
    std::fprintf(stderr, "welkin %.*s: %.*s\n", int(toString(level).size()), toString(level).data(),
                 int(message.size()), message.data());
}
}  // namespace

Logger::Logger() : callback_(stderrSink) {}
Logger::Logger(LogCallback callback, LogLevel minLevel) : callback_(std::move(callback)), minLevel_(minLevel) {
    if (!callback_) callback_ = stderrSink;
}

void Logger::setCallback(LogCallback callback) { callback_ = callback ? std::move(callback) : LogCallback(stderrSink); }

void Logger::log(LogLevel level, std::string_view message) const {
    if (level >= minLevel_) callback_(level, message);
}

}  // namespace welkin
