/*
 * The real C library functions behind the runtime's own of the same names (real.h).
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <limits.h>
#include <linux/futex.h>
#include <stdlib.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "real.h"

static struct hako_real calls;
static int resolved;

static void *find(const char *name)
{
    void *f = dlsym(RTLD_NEXT, name);
    if (f == NULL) {
        static const char message[] = "athrill-native: bench fault: the C library lacks a function the runtime needs\n";
        (void)!write(STDERR_FILENO, message, sizeof message - 1);
        _exit(3);
    }
    return f;
}

const struct hako_real *hako_real(void)
{
    if (!resolved) {
#define HAKO_REAL_FIND(ret, name, params) *(void **)&calls.name = find(#name);
        HAKO_REAL_CALLS(HAKO_REAL_FIND)
#undef HAKO_REAL_FIND
        resolved = 1;
    }
    return &calls;
}

double hako_wall_s(void)
{
    struct timespec ts;
    hako_real()->clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static struct timespec span(double seconds)
{
    return (struct timespec){(time_t)seconds, (long)((seconds - (double)(time_t)seconds) * 1e9)};
}

void hako_wall_nap(double seconds)
{
    struct timespec ts = span(seconds);
    hako_real()->nanosleep(&ts, NULL);
}

void hako_wall_wait(uint32_t *word, uint32_t expected, double seconds)
{
    struct timespec ts = span(seconds);
    hako_real()->syscall(SYS_futex, word, FUTEX_WAIT, expected, &ts, NULL, 0);
}

void hako_wall_wake(uint32_t *word) { hako_real()->syscall(SYS_futex, word, FUTEX_WAKE, INT_MAX, NULL, NULL, 0); }
