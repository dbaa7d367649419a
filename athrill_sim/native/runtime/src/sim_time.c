/*
 * The simulated clock (sim_time.h). What was spent in a step is kept below one step, so the clock a program
 * reads never runs past the next snapshot's time: reads stay monotonic across the kernel's move to it.
 */
#include "sim_time.h"

static int64_t tick_us;
static int64_t spent_us;

int64_t hako_tick(void) { return tick_us; }

int64_t hako_now(void) { return tick_us + spent_us; }

void hako_time_set_tick(int64_t tick)
{
    tick_us = tick;
    spent_us = 0;
}

bool hako_time_spend(int64_t us)
{
    spent_us += us;
    if (spent_us < HAKO_PHYSICS_STEP_US)
        return false;
    spent_us = HAKO_PHYSICS_STEP_US - 1; /* held here until the kernel moves on */
    return true;
}

int64_t hako_whole_steps(int64_t us)
{
    return (us + HAKO_PHYSICS_STEP_US - 1) / HAKO_PHYSICS_STEP_US * HAKO_PHYSICS_STEP_US;
}
