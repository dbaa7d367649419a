/*
 * A player that computes without a call would stop simulated time for good: libraspike-art's readings are
 * plain loads of the last status (raspike_internal.h 55-60), so a busy wait on the force sensor, or a task's
 * closing `while (1) {}`, never reaches this library, the bench never moves, and the physics side's watchdog
 * ended the test as silent. As the native kernel does (kernel.c), a baton's holder that has computed for a
 * slice of CPU time since it took the baton makes simulated time pass by up to HAKO_SPIN_TIME_US (less where a
 * player or the kernel's timer falls due sooner), the hub's bytes reaching the program meanwhile.
 *
 * The CPU clock is the process's ITIMER_VIRTUAL (qemu-user passes it to the host), restarted whenever a player
 * takes the baton: between two hand-offs only the holder computes (asp's receiving thread runs within the
 * moves), so what it counts is the holder's. ASP3 blocks every signal but its interrupts in its tasks, and a
 * task's threads inherit that, so the signal is taken by a thread that is not a player (RasPike-ART's own,
 * started before the kernel), which moves the bench for the holder; the kernel's tick, if it falls due, is
 * sent to the main thread as the timer's interrupt. Unlike the native kernel's, the holder goes on holding the
 * baton: other players wait until it calls.
 *
 * The first slice is long, so that qemu translating code a task runs for the first time never counts as a
 * spin; once the holder has been found spinning and has made no call since, a short one. A player that computes
 * less than the long slice before it calls is never moved, however loaded the machine.
 */
#define _GNU_SOURCE
#include <signal.h>
#include <stdint.h>
#include <sys/time.h>

#include "asp.h"
#include "real.h"
#include "runtime.h"

#define FIRST_SLICE_US 100000 /* CPU time a player may compute after taking the baton before it spins */
#define SPIN_SLICE_US 2000 /* then, while it goes on spinning: each such slice is HAKO_SPIN_TIME_US simulated */

static volatile sig_atomic_t armed;

static void arm(long slice_us)
{
    struct itimerval slice = {{0, slice_us}, {0, slice_us}};
    if (hako_real()->setitimer(ITIMER_VIRTUAL, &slice, NULL) != 0)
        hako_bench_fault("cannot start asp's CPU clock");
}

static void on_spin(int sig)
{
    (void)sig;
    if (hako_asp_spun(HAKO_SPIN_TIME_US))
        arm(SPIN_SLICE_US);
}

void hako_asp_spin_clock_start(void)
{
    struct sigaction sa = {.sa_handler = on_spin, .sa_flags = SA_RESTART};
    sigemptyset(&sa.sa_mask);
    if (hako_real()->sigaction(SIGVTALRM, &sa, NULL) != 0)
        hako_bench_fault("cannot start asp's CPU clock");
    armed = 1;
    hako_asp_slice_start();
}

void hako_asp_slice_start(void)
{
    if (armed)
        arm(FIRST_SLICE_US);
}
