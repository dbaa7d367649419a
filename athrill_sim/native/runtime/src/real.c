/*
 * The real C library functions behind the runtime's own of the same names (real.h).
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdlib.h>
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
        *(void **)&calls.clock_gettime = find("clock_gettime");
        *(void **)&calls.nanosleep = find("nanosleep");
        *(void **)&calls.syscall = find("syscall");
        *(void **)&calls.sigaction = find("sigaction");
        *(void **)&calls.setitimer = find("setitimer");
        *(void **)&calls.sigsuspend = find("sigsuspend");
        *(void **)&calls.pthread_cond_timedwait = find("pthread_cond_timedwait");
        *(void **)&calls.open = find("open");
        *(void **)&calls.openat = find("openat");
        *(void **)&calls.fopen = find("fopen");
        *(void **)&calls.connect = find("connect");
        *(void **)&calls.getaddrinfo = find("getaddrinfo");
        *(void **)&calls.poll = find("poll");
        *(void **)&calls.select = find("select");
        *(void **)&calls.epoll_wait = find("epoll_wait");
        *(void **)&calls.pclose = find("pclose");
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

void hako_wall_nap(double seconds)
{
    struct timespec ts = {(time_t)seconds, (long)((seconds - (double)(time_t)seconds) * 1e9)};
    hako_real()->nanosleep(&ts, NULL);
}
