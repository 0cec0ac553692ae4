/* LD_PRELOAD shim for `welkin bench display`: records the CLOCK_MONOTONIC time of every buffer
 * swap (glXSwapBuffers, eglSwapBuffers) of the process it is loaded into, so that welkin and
 * Stellarium are timed by one identical method (the frame as presented, not as the program reports).
 *
 *   WELKIN_SWAP_LOG=/tmp/swaps.txt LD_PRELOAD=build/bin/libwelkin_swap_shim.so stellarium ...
 *
 * Each swap appends one line: the time in nanoseconds on CLOCK_MONOTONIC, written with write(2)
 * at once so the record survives the process being ended by a signal. Without WELKIN_SWAP_LOG the
 * shim records nothing. Programs that open libGL/libEGL with dlopen and look the swap up with
 * dlsym (GLFW does) are caught by wrapping dlsym as well; programs linked to libGL (Qt) are caught
 * by the exported glXSwapBuffers/eglSwapBuffers below. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

typedef void (*GlxSwapFn)(void* display, unsigned long drawable);
typedef unsigned (*EglSwapFn)(void* display, void* surface);
typedef void* (*DlsymFn)(void* handle, const char* name);
typedef void* (*GetProcFn)(const unsigned char* name);

static GlxSwapFn realGlxSwap;
static EglSwapFn realEglSwap;
static int logFd = -2; /* -2: not opened yet, -1: no log */
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

static DlsymFn realDlsym(void) {
    static DlsymFn fn;
    if (!fn) fn = (DlsymFn)dlvsym(RTLD_NEXT, "dlsym", "GLIBC_2.34");
    if (!fn) fn = (DlsymFn)dlvsym(RTLD_NEXT, "dlsym", "GLIBC_2.2.5");
    return fn;
}

static void record(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    pthread_mutex_lock(&lock);
    if (logFd == -2) {
        const char* path = getenv("WELKIN_SWAP_LOG");
        logFd = path && *path ? open(path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644) : -1;
    }
    if (logFd >= 0) {
        char line[32];
        int n = snprintf(line, sizeof line, "%lld\n", (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec);
        if (n > 0 && write(logFd, line, (size_t)n) < 0) { /* nothing to do: the count is short */ }
    }
    pthread_mutex_unlock(&lock);
}

void glXSwapBuffers(void* display, unsigned long drawable) {
    if (!realGlxSwap) realGlxSwap = (GlxSwapFn)realDlsym()(RTLD_NEXT, "glXSwapBuffers");
    if (realGlxSwap) realGlxSwap(display, drawable);
    record();
}

unsigned eglSwapBuffers(void* display, void* surface) {
    if (!realEglSwap) realEglSwap = (EglSwapFn)realDlsym()(RTLD_NEXT, "eglSwapBuffers");
    unsigned ok = realEglSwap ? realEglSwap(display, surface) : 0;
    record();
    return ok;
}

/* GLFW: dlopen("libGL.so.1") then dlsym(handle, "glXSwapBuffers"): hand back the wrapper and
 * remember the library's own function. */
void* dlsym(void* handle, const char* name) {
    DlsymFn real = realDlsym();
    void* sym = real ? real(handle, name) : NULL;
    if (!sym || !name) return sym;
    if (strcmp(name, "glXSwapBuffers") == 0 && sym != (void*)glXSwapBuffers) {
        realGlxSwap = (GlxSwapFn)sym;
        return (void*)glXSwapBuffers;
    }
    if (strcmp(name, "eglSwapBuffers") == 0 && sym != (void*)eglSwapBuffers) {
        realEglSwap = (EglSwapFn)sym;
        return (void*)eglSwapBuffers;
    }
    return sym;
}
