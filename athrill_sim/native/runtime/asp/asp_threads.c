/*
 * asp's threads on the bench's clock, by the native runtime's rule that simulated time moves only while every
 * thread of the program is idle (kernel.c), kept here as a baton: of asp's players (its main thread, where the
 * kernel and every task run, and each thread a task starts, std::thread among them, with theirs), one runs at
 * a time, in an order fixed by the program alone, so that a team's threads run the same in every run.
 *
 * The baton is handed on where a player waits: a sleep, a condition wait, asp's idle sigsuspend, a mutex
 * another player holds, a join; and where a player has spent a whole step without waiting, which moves the
 * bench (asp_time.c) and puts the player after the others that may run, as the native kernel preempts a task
 * there. It goes to the next player (in the order they were started) that may run; the kernel's tick comes
 * first, as an interrupt would. When none may run, the one that would hand it on moves the bench to the
 * earliest time any of them waits for (no further than the hub's next sending while one waits for a signal
 * that asp's receiving thread may give, when the bench moves and takes the hub's bytes in), and looks again.
 *
 * asp's receiving thread (RasPike-ART's vdev thread, started by a constructor before asp's kernel) is not a
 * player: it runs in wall time, only while the bench moves (asp_serial.c), so what it does is part of a move.
 * A thread is a player if a player started it once asp's kernel has set its timer.
 *
 * The kernel's SIGALRM is raised only in the main thread while it holds the baton: what it preempts (a task
 * dispatched by ASP3's handler) then runs with the baton too. A condition is signalled by a player or by the
 * receiving thread during a move, so a count of each condition's signals, kept without the lock (the
 * receiving thread signals while the mover holds it), says which waiters may go on; a wait that sees no signal
 * returns as a wake-up POSIX allows, and the caller's loop looks at its predicate.
 *
 * Not covered: pthread_exit (a player that ends so, rather than by returning, keeps the baton's order waiting:
 * the physics side's watchdog ends the test), pthread_mutex_timedlock and the futex calls of libstdc++'s
 * std::atomic::wait and std::future, which wait in wall time.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

#include "asp.h"
#include "posix.h"
#include "real.h"

#define PLAYERS_MAX 256
#define SIGNALLED_MAX 1024 /* conditions with a count of signals: a fixed table, the count found by address */
#define MAIN 0

enum state { RUNNING, WAITING, ENDED, FREE };

struct player {
    enum state state;
    pthread_t thread;
    struct hako_wait wait; /* what it waits for, while WAITING */
    pthread_cond_t turn; /* signalled when the baton comes to it (zeroed: glibc's PTHREAD_COND_INITIALIZER) */
};

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static struct player players[PLAYERS_MAX] = {{.state = RUNNING}}; /* MAIN's thread: hako_asp_players_start */
static int player_count = 1; /* slots used, MAIN's among them */
static int holder = MAIN;
static bool tick_pending; /* the timer fell due: SIGALRM is owed to the main thread */
static bool kernel_started;
static __thread int self = -1; /* the calling thread's slot; -1: not a player */

/* Each condition's signals, and who has signalled it: a condition only players signal cannot be signalled
 * during a move, so a wait for it does not hold moves to the hub's sendings. */
struct signals {
    _Atomic(const void *) cond;
    _Atomic uint64_t count;
    atomic_bool by_player;
    atomic_bool by_other; /* by a thread that is not a player: asp's receiving thread, within a move */
};
static struct signals signalled[SIGNALLED_MAX];

void hako_asp_lock(void) { hako_real()->pthread_mutex_lock(&lock); }
void hako_asp_unlock(void) { pthread_mutex_unlock(&lock); }

void hako_asp_players_start(void)
{
    self = MAIN;
    players[MAIN].thread = pthread_self();
}

void hako_asp_kernel_started(void)
{
    if (!kernel_started)
        hako_asp_spin_clock_start();
    kernel_started = true;
}

bool hako_asp_player(void) { return self >= 0; }

/* `cond`'s signals; its slot is taken at the first use. */
static struct signals *signals_of(const void *cond)
{
    size_t start = ((uintptr_t)cond >> 3) % SIGNALLED_MAX;
    for (size_t i = 0; i < SIGNALLED_MAX; i++) {
        size_t k = (start + i) % SIGNALLED_MAX;
        const void *found = NULL;
        if (atomic_compare_exchange_strong(&signalled[k].cond, &found, cond) || found == cond)
            return &signalled[k];
    }
    hako_bench_fault("asp signals more than %d condition variables", SIGNALLED_MAX);
}

uint64_t hako_asp_signals(const void *cond) { return atomic_load(&signals_of(cond)->count); }

static void count_signal(const void *cond)
{
    struct signals *it = signals_of(cond);
    atomic_store(self >= 0 ? &it->by_player : &it->by_other, true);
    atomic_fetch_add(&it->count, 1);
}

/* Whether only players have signalled `cond`, as far as the program has run: a condition nothing has signalled
 * yet may be the receiving thread's. */
static bool players_signal(const void *cond)
{
    const struct signals *it = signals_of(cond);
    return atomic_load(&it->by_player) && !atomic_load(&it->by_other);
}

bool hako_asp_awaits_hub(void)
{
    for (int p = 0; p < player_count; p++) {
        const struct hako_wait *w = &players[p].wait;
        if (players[p].state == WAITING &&
            ((w->kind == HAKO_WAIT_SIGNAL && !players_signal(w->object)) || w->kind == HAKO_WAIT_MUTEX))
            return true;
    }
    return false;
}

static bool mutex_free(const pthread_mutex_t *m) { return __atomic_load_n(&m->__data.__lock, __ATOMIC_ACQUIRE) == 0; }

static bool ended(int p) { return players[p].state == ENDED || players[p].state == FREE; }

/* Whether player `p` may run now. The main thread's every wait gives way to the kernel's tick. */
static bool may_run(int p)
{
    const struct player *it = &players[p];
    if (it->state != WAITING)
        return it->state == RUNNING;
    if (p == MAIN && tick_pending)
        return true;
    const struct hako_wait *w = &it->wait;
    switch (w->kind) {
    case HAKO_WAIT_TIME:
        return hako_now() >= w->due;
    case HAKO_WAIT_SIGNAL:
        return hako_now() >= w->due || hako_asp_signals(w->object) != w->signals;
    case HAKO_WAIT_TICK:
        return false;
    case HAKO_WAIT_MUTEX:
        return mutex_free(w->object);
    case HAKO_WAIT_JOIN:
        return ended((int)(intptr_t)w->object);
    }
    return false;
}

/* The time the bench moves to when no player may run: the earliest any waits for, and the kernel's timer. A
 * wait for a signal goes no further than the next time the hub may send (the receiving thread signals what it
 * brings), unless only players signal that condition. */
static int64_t next_move(void)
{
    int64_t step = hako_tick() + HAKO_PHYSICS_STEP_US, until = hako_asp_timer_due();
    int64_t hub_sends = hako_serial_hub_sends();
    for (int p = 0; p < player_count; p++) {
        const struct hako_wait *w = &players[p].wait;
        if (players[p].state != WAITING)
            continue;
        int64_t due;
        switch (w->kind) {
        case HAKO_WAIT_TIME:
            due = hako_whole_steps(w->due);
            break;
        case HAKO_WAIT_SIGNAL:
            due = w->due < hub_sends || players_signal(w->object) ? w->due : hub_sends;
            break;
        case HAKO_WAIT_MUTEX: /* held by the receiving thread, which lets go within a move */
            due = step;
            break;
        default: /* the tick is the timer's, a join another player's end */
            continue;
        }
        until = due < until ? due : until;
    }
    return until;
}

/* The baton from the caller's player `from` to the next that may run, the bench moved until one may. */
static void hand_on(int from)
{
    for (;;) {
        int next = -1;
        if (tick_pending && may_run(MAIN))
            next = MAIN;
        for (int i = 1; next < 0 && i <= player_count; i++)
            if (may_run((from + i) % player_count))
                next = (from + i) % player_count;
        if (next >= 0) {
            holder = next;
            /* the baton's own condition, to its one waiter: waking every player at each hand-off cost a
             * futex round trip through qemu for each */
            hako_real()->pthread_cond_signal(&players[next].turn);
            return;
        }
        if (hako_asp_move(next_move(), true))
            tick_pending = true;
    }
}

static void await_turn(void)
{
    while (holder != self)
        hako_real()->pthread_cond_wait(&players[self].turn, &lock);
}

/* SIGALRM, if owed, now that the main thread holds the baton and not the lock. */
static void deliver_tick(void)
{
    if (self != MAIN)
        return;
    hako_asp_lock();
    bool owed = tick_pending;
    tick_pending = false;
    hako_asp_unlock();
    if (owed)
        raise(SIGALRM);
}

void hako_asp_wait(const struct hako_wait *w)
{
    hako_asp_lock();
    players[self].state = WAITING;
    players[self].wait = *w;
    hand_on(self);
    await_turn();
    players[self].state = RUNNING;
    hako_asp_unlock();
    hako_asp_slice_start();
    deliver_tick();
}

void hako_asp_spent_step(bool fired)
{
    hako_asp_lock();
    tick_pending |= fired;
    hand_on(self);
    await_turn();
    hako_asp_unlock();
    hako_asp_slice_start();
    deliver_tick();
}

bool hako_asp_spun(int64_t spin_us)
{
    if (self >= 0 || pthread_mutex_trylock(&lock) != 0) /* a player here waits; the library is busy */
        return false;
    if (players[holder].state != RUNNING) {
        hako_asp_unlock();
        return false;
    }
    int64_t until = hako_tick() + spin_us, due = next_move();
    /* no drain: the receiving thread may be the one here, and the spinner may hold the port's mutex */
    tick_pending |= hako_asp_move(due < until ? due : until, false);
    hako_asp_told_taken();
    hako_serial_release();
    bool tick = holder == MAIN && tick_pending;
    tick_pending &= !tick;
    hako_asp_unlock();
    if (tick)
        pthread_kill(players[MAIN].thread, SIGALRM);
    return true;
}

/* -- the calls that start, end and wait for threads ------------------------------------------------------ */

struct start {
    void *(*entry)(void *);
    void *arg;
    int slot;
};

static void *player_main(void *arg)
{
    struct start start = *(struct start *)arg;
    free(arg);
    self = start.slot;
    hako_asp_lock();
    await_turn();
    hako_asp_unlock();
    hako_asp_slice_start();
    void *result = start.entry(start.arg);
    hako_asp_lock();
    players[self].state = ENDED;
    hand_on(self);
    hako_asp_unlock();
    return result;
}

static int free_slot(void)
{
    for (int p = 1; p < player_count; p++)
        if (players[p].state == FREE)
            return p;
    if (player_count == PLAYERS_MAX)
        hako_bench_fault("asp has more than %d threads of its tasks at once", PLAYERS_MAX);
    return player_count++;
}

int pthread_create(pthread_t *restrict thread, const pthread_attr_t *restrict attr, void *(*entry)(void *),
                   void *restrict arg)
{
    if (self < 0 || !kernel_started)
        return hako_real()->pthread_create(thread, attr, entry, arg);
    struct start *start = malloc(sizeof *start);
    if (start == NULL)
        return EAGAIN;
    hako_asp_lock();
    int slot = free_slot();
    players[slot] = (struct player){.state = RUNNING};
    *start = (struct start){entry, arg, slot};
    hako_asp_unlock();
    int err = hako_real()->pthread_create(thread, attr, player_main, start);
    hako_asp_lock();
    if (err != 0) {
        players[slot].state = FREE;
        free(start);
    } else
        players[slot].thread = *thread;
    hako_asp_unlock();
    return err;
}

static int slot_of(pthread_t thread)
{
    for (int p = 1; p < player_count; p++)
        if (players[p].state != FREE && pthread_equal(players[p].thread, thread))
            return p;
    return -1;
}

int pthread_join(pthread_t thread, void **result)
{
    hako_asp_lock();
    int slot = self >= 0 ? slot_of(thread) : -1;
    hako_asp_unlock();
    struct hako_wait wait = {HAKO_WAIT_JOIN, HAKO_FOREVER, (const void *)(intptr_t)slot, 0};
    while (slot >= 0 && slot != self && !ended(slot)) /* the main thread's wait also ends at the tick */
        hako_asp_wait(&wait);
    int err = hako_real()->pthread_join(thread, result); /* it has ended, or is ending outside the baton */
    if (slot >= 0 && err == 0) {
        hako_asp_lock();
        players[slot].state = FREE;
        hako_asp_unlock();
    }
    return err;
}

int pthread_mutex_lock(pthread_mutex_t *m)
{
    if (self < 0 || player_count == 1)
        return hako_real()->pthread_mutex_lock(m);
    for (;;) {
        int err = pthread_mutex_trylock(m);
        if (err != EBUSY || m->__data.__owner == gettid())
            return err == EBUSY ? hako_real()->pthread_mutex_lock(m) : err; /* the real one's answer to a relock */
        hako_asp_wait(&(struct hako_wait){HAKO_WAIT_MUTEX, HAKO_FOREVER, m, 0});
    }
}

int pthread_cond_signal(pthread_cond_t *cond)
{
    count_signal(cond);
    return hako_real()->pthread_cond_signal(cond);
}

int pthread_cond_broadcast(pthread_cond_t *cond)
{
    count_signal(cond);
    return hako_real()->pthread_cond_broadcast(cond);
}
