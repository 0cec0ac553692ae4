// One headless GL context shared by the [gl] tests of this binary (created on first use).
#pragma once
#include <welkin/gl/context.hpp>
#include <welkin/log.hpp>

#include <epoxy/gl.h>

namespace welkin::test {

inline Logger& testLogger() {
    static Logger log;
    return log;
}

/// Makes the shared headless context current and returns it.
inline gl::HeadlessContext& glContext() {
    static auto ctx = gl::HeadlessContext::create({.debug = true}, testLogger());
    ctx->makeCurrent();
    return *ctx;
}

}  // namespace welkin::test
