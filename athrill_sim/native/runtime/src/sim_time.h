/*
 * Simulated time, owned by sim_time.c: the one clock every part of the runtime and every clock the program
 * reads (get_tim, clock_gettime, std::chrono, time()) follows.
 *
 * The kernel moves the clock from one physics step to the next (the *tick*: always a whole number of
 * steps, the instant of the sensor snapshot the program sees). Between two ticks the program's calls that
 * read a clock or use a device each *spend* HAKO_CALL_COST_US, so that consecutive clock reads differ and a
 * loop that polls without sleeping sees time pass; when one step's worth is spent the kernel moves on to
 * the next tick before the program goes on (kernel.c, hako_spend).
 */
#ifndef HAKO_SIM_TIME_H
#define HAKO_SIM_TIME_H

#include <stdbool.h>
#include <stdint.h>

#include "hako_timing.h"

#define HAKO_FOREVER INT64_MAX /* a wait with no timeout */

/* The tick: the time of the snapshot in the guest windows, a whole number of physics steps. */
int64_t hako_tick(void);

/* What the program's clocks read: the tick and what was spent since it. Never reaches the next tick. */
int64_t hako_now(void);

/* A new tick (the kernel moved to a new snapshot): nothing spent in it yet. */
void hako_time_set_tick(int64_t tick_us);

/* Spend `us` of this step; true when the step is used up, and the kernel should move to the next tick. */
bool hako_time_spend(int64_t us);

/* A duration rounded up to whole physics steps. */
int64_t hako_whole_steps(int64_t us);

#endif /* HAKO_SIM_TIME_H */
