/*
 * The C library's clocks and sleeps on simulated time (posix.h): clock_gettime for every clock, gettimeofday,
 * time, clock; sleep, usleep, nanosleep, clock_nanosleep. std::chrono's clocks and std::this_thread's sleeps
 * are built on these (libstdc++ calls them), as are the C library's own localtime and strftime (which take a
 * time the program read). Each clock read takes HAKO_CALL_COST_US, so that two reads differ and a loop waiting
 * on a clock sees it move.
 *
 * The POSIX timers and alarms are posix_timers.c's, apart, because RasPike-ART's asp takes these clocks and
 * sleeps with a timer of its own (athrill_sim/native/runtime/asp).
 */
#define _GNU_SOURCE
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>

#include "posix.h"
#include "real.h"

#define NS_PER_US 1000LL
#define US_PER_S 1000000LL
#define FAR_S (INT64_MAX / US_PER_S / 2) /* beyond this many seconds a time is taken as never */

bool hako_clock_is_real(clockid_t clock)
{
    return clock == CLOCK_REALTIME || clock == CLOCK_REALTIME_COARSE || clock == CLOCK_REALTIME_ALARM ||
           clock == CLOCK_TAI;
}

struct timespec hako_clock_at(clockid_t clock, int64_t us)
{
    int64_t s = us / US_PER_S + (hako_clock_is_real(clock) ? HAKO_CLOCK_EPOCH_S : 0);
    return (struct timespec){(time_t)s, (long)(us % US_PER_S * NS_PER_US)};
}

int64_t hako_duration_us(const struct timespec *d)
{
    if (d->tv_sec < 0 || d->tv_nsec < 0 || d->tv_nsec >= 1000000000L)
        return -1;
    if (d->tv_sec > FAR_S)
        return HAKO_FOREVER;
    return (int64_t)d->tv_sec * US_PER_S + (d->tv_nsec + NS_PER_US - 1) / NS_PER_US;
}

int64_t hako_clock_time_us(clockid_t clock, const struct timespec *at)
{
    int64_t s = (int64_t)at->tv_sec - (hako_clock_is_real(clock) ? HAKO_CLOCK_EPOCH_S : 0);
    if (s > FAR_S)
        return HAKO_FOREVER;
    if (s < 0)
        return 0;
    return s * US_PER_S + (at->tv_nsec + NS_PER_US - 1) / NS_PER_US;
}

static const char sleeping; /* what a sleep waits on: nothing wakes it but its time */

int hako_sleep_until(int64_t due)
{
    int err = hako_block_on(&sleeping, due);
    return err == EDEADLK ? EDEADLK : 0;
}

int hako_sleep_for(int64_t us)
{
    if (us <= 0) {
        hako_yield();
        return 0;
    }
    if (us == HAKO_FOREVER || us > HAKO_FOREVER - hako_tick())
        return hako_sleep_until(HAKO_FOREVER);
    return hako_sleep_until(hako_tick() + hako_whole_steps(us));
}

void hako_uncovered(const char *call, const char *what)
{
    static char said[32][48];
    for (size_t i = 0; i < sizeof said / sizeof said[0]; i++) {
        if (strcmp(said[i], call) == 0)
            return;
        if (said[i][0] == '\0') {
            snprintf(said[i], sizeof said[i], "%s", call);
            break;
        }
    }
    hako_log("athrill-native: %s() is not covered by the bench's simulated clock and devices: %s "
             "(docs/NATIVE.md)",
             call, what);
}

/* A wait the running task cannot make (a handler, or a constructor before the tasks start): said once. */
static void cannot_wait(const char *call)
{
    hako_uncovered(call, "called where no task runs (a handler, or before the tasks start), it returns at once");
}

/* -- clocks ------------------------------------------------------------------------------------------- */

/* Each read takes its time after it: the first read at a tick reads the tick. */
int clock_gettime(clockid_t clock, struct timespec *tp)
{
    *tp = hako_clock_at(clock, hako_now());
    hako_spend_call();
    return 0;
}
int hako_clock_gettime(clockid_t clock, struct timespec *tp) __attribute__((alias("clock_gettime")));

int gettimeofday(struct timeval *restrict tv, void *restrict tz)
{
    (void)tz;
    struct timespec ts = hako_clock_at(CLOCK_REALTIME, hako_now());
    *tv = (struct timeval){ts.tv_sec, ts.tv_nsec / NS_PER_US};
    hako_spend_call();
    return 0;
}
int hako_gettimeofday(struct timeval *restrict tv, void *restrict tz) __attribute__((alias("gettimeofday")));

time_t time(time_t *t)
{
    time_t now = hako_clock_at(CLOCK_REALTIME, hako_now()).tv_sec;
    hako_spend_call();
    if (t != NULL)
        *t = now;
    return now;
}

clock_t clock(void)
{
    clock_t now = (clock_t)(hako_now() * CLOCKS_PER_SEC / US_PER_S);
    hako_spend_call();
    return now;
}

/* -- sleeps ------------------------------------------------------------------------------------------- */

static int sleep_relative(const char *call, int64_t us)
{
    if (hako_sleep_for(us) == EDEADLK)
        cannot_wait(call);
    return 0;
}

unsigned int sleep(unsigned int seconds)
{
    sleep_relative(__func__, (int64_t)seconds * US_PER_S);
    return 0;
}

int usleep(useconds_t usec) { return sleep_relative(__func__, (int64_t)usec); }

int nanosleep(const struct timespec *req, struct timespec *rem)
{
    int64_t us = req != NULL ? hako_duration_us(req) : -1;
    if (us < 0) {
        errno = EINVAL;
        return -1;
    }
    sleep_relative(__func__, us);
    if (rem != NULL)
        *rem = (struct timespec){0, 0};
    return 0;
}
int hako_nanosleep(const struct timespec *req, struct timespec *rem) __attribute__((alias("nanosleep")));

int clock_nanosleep(clockid_t clock, int flags, const struct timespec *req, struct timespec *rem)
{
    if (req == NULL)
        return EINVAL;
    if (!(flags & TIMER_ABSTIME)) {
        int64_t us = hako_duration_us(req);
        if (us < 0)
            return EINVAL;
        sleep_relative(__func__, us);
        if (rem != NULL)
            *rem = (struct timespec){0, 0};
        return 0;
    }
    if (req->tv_nsec < 0 || req->tv_nsec >= 1000000000L)
        return EINVAL;
    if (hako_sleep_until(hako_clock_time_us(clock, req)) == EDEADLK)
        cannot_wait(__func__);
    return 0;
}
int hako_clock_nanosleep(clockid_t clock, int flags, const struct timespec *req, struct timespec *rem)
    __attribute__((alias("clock_nanosleep")));
