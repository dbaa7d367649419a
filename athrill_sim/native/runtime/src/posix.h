/*
 * What the POSIX layer's files (posix_*.c) share: the conversions between the program's clocks and simulated
 * time, and the line a call the bench does not cover leaves in the log.
 *
 * Every clock reads simulated time (sim_time.h): the monotonic ones (MONOTONIC, BOOTTIME, the CPU-time clocks)
 * from the kernel's start, the real-time ones from HAKO_CLOCK_EPOCH_S on, so that steady_clock starts where
 * get_tim does and a program's timestamps repeat from run to run.
 */
#ifndef HAKO_POSIX_H
#define HAKO_POSIX_H

#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <sys/time.h>
#include <time.h>

#include "runtime.h"
#include "scheduler.h"

/* Whether `clock` counts from the epoch (CLOCK_REALTIME and its kinds), rather than from the kernel's start. */
bool hako_clock_is_real(clockid_t clock);

/* A clock's reading for simulated time `us`. */
struct timespec hako_clock_at(clockid_t clock, int64_t us);

/* The simulated time an absolute time of `clock` is at, rounded up to a microsecond (HAKO_FOREVER if far). */
int64_t hako_clock_time_us(clockid_t clock, const struct timespec *at);

/* A duration in microseconds, rounded up (HAKO_FOREVER if far); -1 for a malformed one. */
int64_t hako_duration_us(const struct timespec *d);

/* Wait until simulated time `due` (HAKO_FOREVER: for ever) on the running task's own account: 0, or EDEADLK
 * where no task runs (a handler, or before the tasks start), which cannot wait. */
int hako_sleep_until(int64_t due);

/* A relative wait of `us`, counted from the current tick (kernel.c) */
int hako_sleep_for(int64_t us);

/* The one log line of a call the bench does not cover, naming it (once per call name and reason). */
void hako_uncovered(const char *call, const char *what);

/* The runtime's own clock_gettime, gettimeofday, nanosleep, clock_nanosleep and sigaction, by names no program
 * defines: the C library's names are weak (athrill_sim/native/build.py), and a program's own wins for them. */
int hako_clock_gettime(clockid_t clock, struct timespec *tp);
int hako_gettimeofday(struct timeval *restrict tv, void *restrict tz);
int hako_nanosleep(const struct timespec *req, struct timespec *rem);
int hako_clock_nanosleep(clockid_t clock, int flags, const struct timespec *req, struct timespec *rem);
int hako_sigaction(int sig, const struct sigaction *restrict act, struct sigaction *restrict old);

#endif /* HAKO_POSIX_H */
