/*
 * RasPike-ART's asp on the bench's simulated clock: a library preloaded into asp under qemu-user (built for
 * aarch64 by athrill_sim/raspike_art/clock.py) with the native runtime's own clock, lockstep and mapped files
 * (sim_time.c, lockstep.c, mapped_files.c) and its clocks and sleeps (posix_time.c). What asp adds to them
 * is its kernel's tick, which is a POSIX interval timer (RasPike-ART target/raspi_gcc/target_timer.c):
 * - setitimer(ITIMER_REAL) only records when the timer falls due in simulated time (no real timer runs);
 *   the value it gives back is what is left of it in simulated time (pause_itimer, target_timer.c 109, reads
 *   its progress from it);
 * - sigsuspend, asp's idle loop (target_kernel_impl.c 287), is where asp says "nothing to do until the timer":
 *   the bench moves to the physics step the timer falls due in and the clock on to the timer's time itself
 *   (as calls spend time within a step), and SIGALRM is raised so that the real sigsuspend delivers it at
 *   once. Not rounded up to the next step: ASP3 asks for its events a microsecond late (a 10 ms tick is
 *   10 ms and 1 us away), which rounded up would make every period a step longer;
 * - a sleep runs the bench up to its end, raising SIGALRM at each time the timer falls due on the way;
 * - pthread_cond_timedwait and pthread_cond_wait, with which libraspike-art waits for what its receiving
 *   thread hands over (an acknowledgement, raspike_protocol.c 359-384, with a deadline of time(0) + 3 s; a
 *   status with a port's new mode, 387-414), are idle too: a deadline is on the simulated clock, and while no
 *   answer comes (ANSWER_SLICE_NS of wall time) the bench moves on a step, since the Pi sends its commands
 *   only when a status arrives (raspike_protocol.c 333) and the hub sends one every 10 ms; SIGALRM is raised
 *   when the timer falls due, as the robot's tick interrupts that wait. A move of the bench at such an idle
 *   point drains asp's serial port (asp_serial.c), so an answer of the hub is in before the next wait begins;
 *   the wall slice is for a team's own threads.
 * asp's main thread, where its kernel and its tasks run, spends time and moves the bench: the receiving thread
 * runs in wall time, and its clock reads and waits cannot make one run differ from the next. A team's own
 * thread (std::thread) that sleeps moves the bench too, and its runs are not the same twice (DESIGN-NOTES).
 * Every clock read spends HAKO_CALL_COST_US, as in the native runtime; a step used up that way moves the
 * bench on by one step, so that a loop polling a clock sees time pass, and owes its drain to the next idle
 * point (the caller may hold the port's mutex, which the receiving thread needs to take the bytes in).
 *
 * The bench's run directory and test come from the environment (HAKO_RUN_DIR, HAKO_TEST), set with qemu's -E:
 * asp's own command line is RasPike-ART's. Without HAKO_RUN_DIR it is a bench fault, in one line.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/time.h>
#include <unistd.h>

#include "asp.h"
#include "posix.h"
#include "real.h"

#define US_PER_S 1000000LL

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER; /* asp's receiving thread reads clocks too */
static int64_t timer_due = HAKO_FOREVER; /* ITIMER_REAL's next expiry [simulated us] */
static int64_t timer_interval; /* and its reload (0: one-shot) */
static pthread_t main_thread; /* where asp's kernel runs, and so its tick's handler */
static bool drain_owed; /* the bench moved with no drain since the last: owed at the next idle point */

__attribute__((constructor)) static void asp_time_start(void)
{
    main_thread = pthread_self();
    /* Line by line, as on the team's terminal (`make start`): the bench's pipe would hold a program's lines in
     * stdio's buffer, and lose them when the test ends and asp is stopped. */
    setvbuf(stdout, NULL, _IOLBF, 0);
    const char *run_dir = getenv("HAKO_RUN_DIR");
    if (run_dir == NULL)
        hako_bench_fault("HAKO_RUN_DIR is not set: asp's clock library runs only under the bench");
    hako_files_open(run_dir);
    const char *test = getenv("HAKO_TEST");
    if (test != NULL)
        hako_wait_for_test((uint32_t)strtoul(test, NULL, 10));
    hako_announce();
    hako_time_set_tick((int64_t)hako_rx_unity_time());
}

bool hako_asp_is_main(void) { return gettid() == getpid(); }

/* The timer fell due: its SIGALRM goes to the main thread, where asp's kernel takes its tick, also when a
 * team's own thread moved the bench (its handler run in that thread would find no kernel context there:
 * ASP3's time_event.c asserts sense_context()). */
static void tick_main(void)
{
    if (hako_asp_is_main())
        raise(SIGALRM);
    else
        pthread_kill(main_thread, SIGALRM);
}

/* Move the bench to the step `until` falls in, and the clock within it to `until` itself, as calls spend it,
 * the serial port drained (also for a move that owed it) if `drained`; true when the timer fell due on the
 * way, which is then reloaded or stopped. The caller holds the lock. */
static bool run_until_drained(int64_t until, bool drained)
{
    int64_t step = until == HAKO_FOREVER ? HAKO_FOREVER : until - until % HAKO_PHYSICS_STEP_US;
    if (step > hako_tick()) {
        hako_publish(hako_now(), step);
        hako_wait_snapshot(step);
        hako_time_set_tick(step);
        drain_owed = true;
    }
    if (drained && drain_owed) {
        hako_serial_drain();
        drain_owed = false;
    }
    if (until > hako_now())
        hako_time_spend(until - hako_now()); /* less than a step: never used up */
    if (timer_due > hako_now())
        return false;
    timer_due = timer_interval > 0 ? timer_due + timer_interval : HAKO_FOREVER;
    return true;
}

static bool run_until(int64_t until) { return run_until_drained(until, true); }

void hako_asp_step_undrained(void)
{
    pthread_mutex_lock(&lock);
    bool fired = run_until_drained(hako_tick() + HAKO_PHYSICS_STEP_US, false);
    pthread_mutex_unlock(&lock);
    if (fired)
        tick_main();
}

/* When the timer falls due, not beyond a sleep's end `limit` (whole steps, as the native runtime's waits). */
static int64_t next_due(int64_t limit)
{
    int64_t end = limit == HAKO_FOREVER ? HAKO_FOREVER : hako_whole_steps(limit);
    return timer_due < end ? timer_due : end;
}

/* -- what posix_time.c's clocks and sleeps ask of a kernel -------------------------------------------- */

/* A clock read's cost; a step used up moves the bench, owing its drain to the next idle point (asp_serial.c):
 * the caller may hold the port's mutex, which the receiving thread needs. */
void hako_spend_call(void)
{
    if (!hako_asp_is_main())
        return;
    pthread_mutex_lock(&lock);
    bool fired = hako_time_spend(HAKO_CALL_COST_US) &&
                 run_until_drained(hako_tick() + HAKO_PHYSICS_STEP_US, hako_serial_backlog());
    pthread_mutex_unlock(&lock);
    if (fired)
        tick_main();
}

int hako_block_on(const void *object, int64_t due)
{
    (void)object; /* only sleeps wait here: nothing but their time ends them */
    for (;;) {
        pthread_mutex_lock(&lock);
        bool fired = run_until(next_due(due));
        bool over = hako_now() >= due;
        pthread_mutex_unlock(&lock);
        if (fired)
            tick_main(); /* its handler runs now unless asp has SIGALRM blocked, as in a real sleep */
        if (over)
            return 0;
    }
}

void hako_yield(void) { hako_spend_call(); }

/* -- asp's tick -------------------------------------------------------------------------------------- */

static int64_t timeval_us(const struct timeval *tv)
{
    struct timespec ts = {tv->tv_sec, tv->tv_usec * 1000L};
    return hako_duration_us(&ts);
}

static struct timeval us_timeval(int64_t us) { return (struct timeval){us / US_PER_S, us % US_PER_S}; }

/* The timer as getitimer gives it: what is left (at least 1 us while it has not fired: 0 means stopped). */
static void current(struct itimerval *out)
{
    int64_t left = timer_due - hako_now();
    if (timer_due == HAKO_FOREVER)
        left = 0;
    else if (left < 1)
        left = 1;
    *out = (struct itimerval){us_timeval(timer_interval), us_timeval(left)};
}

int getitimer(__itimer_which_t which, struct itimerval *value)
{
    if (which != ITIMER_REAL) {
        hako_uncovered(__func__, "only ITIMER_REAL runs on simulated time; it fails with ENOSYS");
        errno = ENOSYS;
        return -1;
    }
    pthread_mutex_lock(&lock);
    current(value);
    pthread_mutex_unlock(&lock);
    return 0;
}

int setitimer(__itimer_which_t which, const struct itimerval *restrict value, struct itimerval *restrict old)
{
    if (which != ITIMER_REAL) {
        hako_uncovered(__func__, "only ITIMER_REAL runs on simulated time; it fails with ENOSYS");
        errno = ENOSYS;
        return -1;
    }
    int64_t first = timeval_us(&value->it_value), interval = timeval_us(&value->it_interval);
    if (first < 0 || interval < 0 || value->it_value.tv_usec >= US_PER_S || value->it_interval.tv_usec >= US_PER_S) {
        errno = EINVAL;
        return -1;
    }
    pthread_mutex_lock(&lock);
    if (old != NULL)
        current(old);
    bool armed = first > 0 && first != HAKO_FOREVER;
    timer_due = armed ? hako_now() + first : HAKO_FOREVER;
    timer_interval = armed && interval != HAKO_FOREVER ? interval : 0;
    pthread_mutex_unlock(&lock);
    return 0;
}

/* asp's idle loop: the bench runs to the timer; its SIGALRM, pending, is what the real sigsuspend delivers. */
int sigsuspend(const sigset_t *mask)
{
    pthread_mutex_lock(&lock);
    bool fired = run_until(timer_due);
    pthread_mutex_unlock(&lock);
    if (fired)
        tick_main();
    return hako_real()->sigsuspend(mask);
}

/* -- waits for asp's other thread ------------------------------------------------------------------- */

/* The time a signal of another thread is awaited each step, in wall time [ns], before the bench moves on:
 * for a team's own threads. asp's receiving thread cannot signal within it, since it takes in the hub's bytes
 * only while the bench moves (hako_serial_drain). */
#define ANSWER_SLICE_NS 2000000L
#define OTHER_SLICE_S 3600 /* a thread other than the main one, waiting with no deadline [s of wall time] */

/* Wait for another thread's signal until simulated time `due`, for a slice of wall time at most. A slice that
 * ends with no signal is a wake-up POSIX allows (0), never a wait begun again here: glibc may let a waiter
 * whose slice ran out take a signal all the same, and only the caller's predicate loop can see it (begun again,
 * RasPike-ART's vdev thread missed mpthread_start_proc's signal and asp hung at its start, one run in ten). In
 * the main thread the bench then moves a step, with the caller's mutex released (the receiving thread may need
 * it to take in the step's bytes, and the robot's tick interrupts such a wait too): the caller sees what the
 * step brought, at the step it came in. Another thread waits in wall time, as the main thread moves the bench
 * and its deadline passes; with no deadline, nothing but a signal ends its wait, so its slice is long. */
static int idle_wait(pthread_cond_t *cond, pthread_mutex_t *mutex, int64_t due)
{
    bool main_thread = hako_asp_is_main();
    hako_spend_call();
    if (hako_now() >= due)
        return ETIMEDOUT;
    struct timespec wall;
    hako_real()->clock_gettime(CLOCK_REALTIME, &wall);
    if (!main_thread && due == HAKO_FOREVER)
        wall.tv_sec += OTHER_SLICE_S;
    else
        wall.tv_nsec += ANSWER_SLICE_NS;
    if (wall.tv_nsec >= 1000000000L) {
        wall.tv_sec++;
        wall.tv_nsec -= 1000000000L;
    }
    int result = hako_real()->pthread_cond_timedwait(cond, mutex, &wall);
    if (result != ETIMEDOUT)
        return result;
    if (main_thread) {
        pthread_mutex_unlock(mutex);
        pthread_mutex_lock(&lock);
        bool fired = run_until(hako_tick() + HAKO_PHYSICS_STEP_US);
        pthread_mutex_unlock(&lock);
        if (fired)
            tick_main();
        pthread_mutex_lock(mutex);
    }
    return 0;
}

int pthread_cond_timedwait(pthread_cond_t *restrict cond, pthread_mutex_t *restrict mutex,
                           const struct timespec *restrict at)
{
    return idle_wait(cond, mutex, hako_clock_time_us(CLOCK_REALTIME, at)); /* the condattr's default clock */
}

int pthread_cond_wait(pthread_cond_t *restrict cond, pthread_mutex_t *restrict mutex)
{
    return idle_wait(cond, mutex, HAKO_FOREVER);
}
