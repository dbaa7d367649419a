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
 * - a sleep waits until its end, SIGALRM raised each time the timer falls due on the way;
 * - pthread_cond_timedwait, pthread_cond_clockwait and pthread_cond_wait, with which libraspike-art waits for
 *   what its receiving thread hands over (an acknowledgement, raspike_protocol.c 359-384, with a deadline of
 *   time(0) + 3 s; a status with a port's new mode, 387-414), and a team's threads for each other, wait for a
 *   signal with a deadline on the simulated clock; while none comes the bench moves no further than the hub
 *   may next send (an answer at the step after asp wrote to it, else its next status: asp_serial.c), since the
 *   Pi sends its commands only when a status arrives (raspike_protocol.c 333); SIGALRM is raised when the
 *   timer falls due, as the robot's tick interrupts that wait. A move of the bench at such a wait drains asp's
 *   serial port (asp_serial.c), so an answer of the hub is in before any thread runs at that step.
 * A move that nothing asp reads can see is not waited for: asp reads the world only through the hub, which
 * sends of its own only a status (hako_serial_hub_quiet). Before the hub's next status, a move is
 * - alone where asp has sent the hub nothing since its last answer: no answer at all, and the physics side
 *   catches up to the step of asp's next answer before it takes that in (hakoniwa/physics/sync.py);
 * - told where asp has sent bytes but no player waits for what the hub may send back (hako_asp_awaits_hub) and
 *   no drain is owed: the answer goes out and asp moves on while the physics side takes the bytes in at the
 *   step they were sent; before its next answer asp waits for that one's snapshot, since the slot is one. The
 *   hub's reply to them (it acknowledges only what libraspike-art waits for) reaches asp at its next drain.
 * The physics side steps the same steps and takes asp's bytes at the same ones, so the laps are the same; of
 * team_spike_threads' four stops every 10 ms, one is waited for (the hub's status), where all four were.
 * Who waits, and who moves the bench when all wait, is the baton's (asp_threads.c): asp's main thread, where
 * its kernel and its tasks run, and the threads its tasks start. asp's receiving thread runs in wall time
 * within the moves, and its clock reads and waits cannot make one run differ from the next.
 * Every clock read spends HAKO_CALL_COST_US, as in the native runtime; a step used up that way moves the
 * bench on by one step, so that a loop polling a clock sees time pass, and owes its drain to the next wait
 * (the caller may hold the port's mutex, which the receiving thread needs to take the bytes in).
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

static int64_t timer_due = HAKO_FOREVER; /* ITIMER_REAL's next expiry [simulated us] */
static int64_t timer_interval; /* and its reload (0: one-shot) */
static bool drain_owed; /* the bench moved with no drain since the last: owed at the next wait */
static int64_t told_wake = -1; /* an answer's snapshot not waited for (a told move's); -1: none */

__attribute__((constructor)) static void asp_time_start(void)
{
    hako_asp_players_start();
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

bool hako_asp_move(int64_t until, bool drained)
{
    int64_t step = until == HAKO_FOREVER ? HAKO_FOREVER : until - until % HAKO_PHYSICS_STEP_US;
    if (step > hako_tick()) {
        bool quiet = hako_serial_hub_quiet(step), sent = hako_serial_sent();
        if (quiet && !sent) { /* alone: nothing to tell, nothing to hear */
            hako_time_set_tick(step);
        } else {
            /* told: asp's bytes go with the answer, and nothing asp waits for can come back before the hub's
             * next status, so asp moves on while the physics side takes them in */
            bool told = quiet && !drain_owed && !hako_asp_awaits_hub();
            hako_asp_told_taken(); /* the answer slot is one */
            hako_serial_published();
            hako_publish(hako_now(), step);
            told_wake = told ? step : -1;
            if (!told) {
                hako_wait_snapshot(step);
                drain_owed = true;
            }
            hako_time_set_tick(step);
        }
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

void hako_asp_told_taken(void)
{
    if (told_wake >= 0)
        hako_wait_snapshot(told_wake);
    told_wake = -1;
}

int64_t hako_asp_timer_due(void) { return timer_due; }

void hako_asp_step_undrained(void)
{
    hako_asp_lock();
    bool fired = hako_asp_move(hako_tick() + HAKO_PHYSICS_STEP_US, false);
    hako_asp_unlock();
    if (fired)
        raise(SIGALRM); /* the main thread's, before any other player starts */
}

/* -- what posix_time.c's clocks and sleeps ask of a kernel -------------------------------------------- */

/* A clock read's cost; a step used up moves the bench, owing its drain to the next wait (asp_serial.c): the
 * caller may hold the port's mutex, which the receiving thread needs. */
void hako_spend_call(void)
{
    if (!hako_asp_player())
        return;
    hako_asp_lock();
    bool used = hako_time_spend(HAKO_CALL_COST_US);
    bool fired = used && hako_asp_move(hako_tick() + HAKO_PHYSICS_STEP_US, hako_serial_backlog());
    hako_asp_unlock();
    if (used)
        hako_asp_spent_step(fired);
}

#define OTHER_NAP_S 100e-6 /* how often a thread other than the players looks whether its sleep is over */

int hako_block_on(const void *object, int64_t due)
{
    (void)object; /* only sleeps wait here: nothing but their time ends them */
    if (!hako_asp_player()) {
        while (hako_now() < due) /* the players move the bench (read without the lock, which a move holds) */
            hako_wall_nap(OTHER_NAP_S);
        return 0;
    }
    while (hako_now() < due) /* a wait of the main thread also ends at the kernel's tick, delivered */
        hako_asp_wait(&(struct hako_wait){HAKO_WAIT_TIME, due, NULL, 0});
    return 0;
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
    hako_asp_lock();
    current(value);
    hako_asp_unlock();
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
    hako_asp_lock();
    hako_asp_kernel_started(); /* target_timer_initialize: asp's tasks start */
    if (old != NULL)
        current(old);
    bool armed = first > 0 && first != HAKO_FOREVER;
    timer_due = armed ? hako_now() + first : HAKO_FOREVER;
    timer_interval = armed && interval != HAKO_FOREVER ? interval : 0;
    hako_asp_unlock();
    return 0;
}

/* asp's idle loop: the bench runs to the timer; its SIGALRM, pending, is what the real sigsuspend delivers. */
int sigsuspend(const sigset_t *mask)
{
    if (hako_asp_is_main())
        hako_asp_wait(&(struct hako_wait){HAKO_WAIT_TICK, HAKO_FOREVER, NULL, 0});
    return hako_real()->sigsuspend(mask);
}

/* -- condition waits ------------------------------------------------------------------------------------ */

/* The time a thread other than the players waits for a signal at a time, in wall time [ns], before its caller
 * looks at its deadline on the simulated clock again; with no deadline, nothing but a signal ends its wait. A
 * slice that ends with no signal is a wake-up POSIX allows (0), never a wait begun again here: glibc may let a
 * waiter whose slice ran out take a signal all the same, and only the caller's predicate loop can see it (begun
 * again, RasPike-ART's vdev thread missed mpthread_start_proc's signal and asp hung at its start, one run in
 * ten). */
#define OTHER_SLICE_NS 2000000L
#define OTHER_FOREVER_S 3600

/* Wait for a signal of `cond` until simulated time `due`. A player's wait that ends with no signal (the
 * kernel's tick in the main thread) is a wake-up POSIX allows (0), and the caller's loop looks at its
 * predicate; its mutex is taken again as a player takes one (asp_threads.c). */
static int idle_wait(pthread_cond_t *cond, pthread_mutex_t *mutex, int64_t due)
{
    hako_spend_call();
    if (!hako_asp_player()) {
        if (hako_now() >= due)
            return ETIMEDOUT;
        struct timespec wall;
        hako_real()->clock_gettime(CLOCK_REALTIME, &wall);
        if (due == HAKO_FOREVER)
            wall.tv_sec += OTHER_FOREVER_S;
        else
            wall.tv_nsec += OTHER_SLICE_NS;
        if (wall.tv_nsec >= 1000000000L) {
            wall.tv_sec++;
            wall.tv_nsec -= 1000000000L;
        }
        int result = hako_real()->pthread_cond_timedwait(cond, mutex, &wall);
        return result == ETIMEDOUT ? 0 : result;
    }
    if (hako_now() >= due)
        return ETIMEDOUT;
    struct hako_wait wait = {HAKO_WAIT_SIGNAL, due, cond, hako_asp_signals(cond)};
    pthread_mutex_unlock(mutex);
    hako_asp_wait(&wait);
    pthread_mutex_lock(mutex);
    return hako_now() >= due ? ETIMEDOUT : 0;
}

int pthread_cond_timedwait(pthread_cond_t *restrict cond, pthread_mutex_t *restrict mutex,
                           const struct timespec *restrict at)
{
    return idle_wait(cond, mutex, hako_clock_time_us(CLOCK_REALTIME, at)); /* the condattr's default clock */
}

int pthread_cond_clockwait(pthread_cond_t *restrict cond, pthread_mutex_t *restrict mutex, clockid_t clock,
                           const struct timespec *restrict at)
{
    return idle_wait(cond, mutex, hako_clock_time_us(clock, at));
}

int pthread_cond_wait(pthread_cond_t *restrict cond, pthread_mutex_t *restrict mutex)
{
    return idle_wait(cond, mutex, HAKO_FOREVER);
}
