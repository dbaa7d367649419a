/*
 * POSIX synchronization on the kernel's waits (scheduler.h): mutexes, condition variables, read-write locks,
 * barriers, spin locks, semaphores, and the futex calls libstdc++ makes itself through syscall() (std::future,
 * std::atomic::wait, std::counting_semaphore, static locals). std::mutex, std::condition_variable and
 * std::shared_mutex are built on these. A task that finds one taken blocks until the holder lets it go; a timed
 * wait ends at the first tick at or after its time (posix.h). Since every thread runs on one thread of the
 * operating system and only ever gives way in a call, nothing here needs an atomic operation.
 *
 * Each object keeps its state in the program's own pthread_*_t, as glibc does: a mutex in glibc's fields of the
 * same meaning (so its static initializers, PTHREAD_RECURSIVE_MUTEX_INITIALIZER_NP among them, are read as
 * glibc reads them), the others at the start of theirs (all zero, as their static initializers are, is new).
 * Where no task runs (a handler, or a constructor before the tasks start) nothing can wait: a wait that would
 * block there fails with EDEADLK and says so.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <limits.h>
#include <linux/futex.h>
#include <pthread.h>
#include <semaphore.h>
#include <stdarg.h>
#include <string.h>
#include <sys/syscall.h>

#include "posix.h"
#include "real.h"

#define KERNEL_OWNER INT_MAX /* who holds what was taken where no task runs */

static int me(void)
{
    hako_task *self = hako_self();
    return self != NULL ? (int)hako_task_number(self) : KERNEL_OWNER;
}

static int cannot_wait(const char *call)
{
    hako_uncovered(call, "it would wait where no task runs, and fails with EDEADLK");
    return EDEADLK;
}

/* -- mutexes -------------------------------------------------------------------------------------------- */

static int kind_of(const pthread_mutex_t *m) { return m->__data.__kind & 3; } /* PTHREAD_MUTEX_KIND_MASK_NP */

int pthread_mutex_init(pthread_mutex_t *m, const pthread_mutexattr_t *attr)
{
    HAKO_SERVICE;
    int kind = PTHREAD_MUTEX_NORMAL;
    if (attr != NULL)
        pthread_mutexattr_gettype(attr, &kind);
    memset(m, 0, sizeof *m);
    m->__data.__kind = kind;
    return 0;
}

int pthread_mutex_destroy(pthread_mutex_t *m) { return m->__data.__owner != 0 ? EBUSY : 0; }

/* Take `m` for `self`, waiting until `due`; the lock is handed over to the first waiter on unlock. */
static int lock_until(pthread_mutex_t *m, int64_t due, const char *call)
{
    HAKO_SERVICE;
    int self = me();
    if (m->__data.__owner == self) {
        if (kind_of(m) == PTHREAD_MUTEX_RECURSIVE) {
            if (m->__data.__count == UINT_MAX)
                return EAGAIN;
            m->__data.__count++;
            return 0;
        }
        if (kind_of(m) == PTHREAD_MUTEX_ERRORCHECK)
            return EDEADLK;
        hako_log("%s: %s locks a mutex it holds: it waits for ever, as on Linux", call, hako_task_name(hako_self()));
    }
    while (m->__data.__owner != 0 && m->__data.__owner != self) {
        int err = hako_block_on(m, due);
        if (err == EDEADLK)
            return cannot_wait(call);
        if (err == ETIMEDOUT && m->__data.__owner != self)
            return ETIMEDOUT;
    }
    if (m->__data.__owner == 0) {
        m->__data.__owner = self;
        m->__data.__count = 1;
    }
    return 0;
}

int pthread_mutex_lock(pthread_mutex_t *m) { return lock_until(m, HAKO_FOREVER, __func__); }

int pthread_mutex_timedlock(pthread_mutex_t *restrict m, const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return lock_until(m, hako_clock_time_us(CLOCK_REALTIME, at), __func__);
}

int pthread_mutex_clocklock(pthread_mutex_t *restrict m, clockid_t clock, const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return lock_until(m, hako_clock_time_us(clock, at), __func__);
}

int pthread_mutex_trylock(pthread_mutex_t *m)
{
    HAKO_SERVICE;
    int self = me();
    if (m->__data.__owner == self && kind_of(m) == PTHREAD_MUTEX_RECURSIVE) {
        m->__data.__count++;
        return 0;
    }
    if (m->__data.__owner != 0)
        return EBUSY;
    m->__data.__owner = self;
    m->__data.__count = 1;
    return 0;
}

/* Let `m` go whole, to the first task waiting for it, if any. */
static void hand_over(pthread_mutex_t *m)
{
    hako_task *next = hako_wake_first(m);
    m->__data.__owner = next != NULL ? (int)hako_task_number(next) : 0;
    m->__data.__count = next != NULL ? 1 : 0;
}

int pthread_mutex_unlock(pthread_mutex_t *m)
{
    HAKO_SERVICE;
    if (m->__data.__owner != me() && kind_of(m) != PTHREAD_MUTEX_NORMAL)
        return EPERM;
    if (m->__data.__owner == 0)
        return kind_of(m) == PTHREAD_MUTEX_NORMAL ? 0 : EPERM;
    if (kind_of(m) == PTHREAD_MUTEX_RECURSIVE && --m->__data.__count > 0)
        return 0;
    hand_over(m);
    return 0;
}

int pthread_mutex_consistent(pthread_mutex_t *m)
{
    HAKO_SERVICE;
    (void)m;
    return EINVAL; /* no mutex here is robust: a thread only ends by returning or pthread_exit */
}

/* -- condition variables -------------------------------------------------------------------------------- */

struct cond {
    int32_t clock; /* pthread_condattr_setclock's; zero, the initializer's, is CLOCK_REALTIME */
};
_Static_assert(sizeof(struct cond) <= sizeof(pthread_cond_t), "a condition variable's state fits in it");

int pthread_cond_init(pthread_cond_t *restrict c, const pthread_condattr_t *restrict attr)
{
    HAKO_SERVICE;
    clockid_t clock = CLOCK_REALTIME;
    if (attr != NULL)
        pthread_condattr_getclock(attr, &clock);
    memset(c, 0, sizeof *c);
    ((struct cond *)c)->clock = clock;
    return 0;
}

int pthread_cond_destroy(pthread_cond_t *c)
{
    HAKO_SERVICE;
    (void)c;
    return 0;
}

static int wait_until(pthread_cond_t *c, pthread_mutex_t *m, int64_t due, const char *call)
{
    HAKO_SERVICE;
    int self = me();
    if (m->__data.__owner != self)
        return EPERM;
    if (hako_self() == NULL)
        return cannot_wait(call);
    unsigned depth = m->__data.__count;
    hand_over(m);
    int err = hako_block_on(c, due);
    lock_until(m, HAKO_FOREVER, call);
    m->__data.__count = depth;
    return err == ETIMEDOUT ? ETIMEDOUT : 0;
}

int pthread_cond_wait(pthread_cond_t *restrict c, pthread_mutex_t *restrict m)
{
    HAKO_SERVICE;
    return wait_until(c, m, HAKO_FOREVER, __func__);
}

int pthread_cond_timedwait(pthread_cond_t *restrict c, pthread_mutex_t *restrict m, const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return wait_until(c, m, hako_clock_time_us(((struct cond *)c)->clock, at), __func__);
}

int pthread_cond_clockwait(pthread_cond_t *restrict c, pthread_mutex_t *restrict m, clockid_t clock,
                           const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return wait_until(c, m, hako_clock_time_us(clock, at), __func__);
}

int pthread_cond_signal(pthread_cond_t *c)
{
    HAKO_SERVICE;
    hako_wake(c, 1);
    return 0;
}

int pthread_cond_broadcast(pthread_cond_t *c)
{
    HAKO_SERVICE;
    hako_wake(c, INT_MAX);
    return 0;
}

/* -- read-write locks ----------------------------------------------------------------------------------- */

struct rwlock {
    int32_t writer; /* the task that holds it to write, or 0 */
    uint32_t readers;
};
_Static_assert(sizeof(struct rwlock) <= sizeof(pthread_rwlock_t), "a read-write lock's state fits in it");

int pthread_rwlock_init(pthread_rwlock_t *restrict rw, const pthread_rwlockattr_t *restrict attr)
{
    HAKO_SERVICE;
    (void)attr;
    memset(rw, 0, sizeof *rw);
    return 0;
}

int pthread_rwlock_destroy(pthread_rwlock_t *rw)
{
    HAKO_SERVICE;
    const struct rwlock *l = (const struct rwlock *)rw;
    return l->writer != 0 || l->readers != 0 ? EBUSY : 0;
}

static int take(pthread_rwlock_t *rw, bool write, int64_t due, const char *call)
{
    HAKO_SERVICE;
    struct rwlock *l = (struct rwlock *)rw;
    if (l->writer == me())
        return EDEADLK;
    while (l->writer != 0 || (write && l->readers != 0)) {
        int err = hako_block_on(rw, due);
        if (err == EDEADLK)
            return cannot_wait(call);
        if (err == ETIMEDOUT)
            return ETIMEDOUT;
    }
    if (write)
        l->writer = me();
    else
        l->readers++;
    return 0;
}

int pthread_rwlock_rdlock(pthread_rwlock_t *rw) { return take(rw, false, HAKO_FOREVER, __func__); }

int pthread_rwlock_wrlock(pthread_rwlock_t *rw) { return take(rw, true, HAKO_FOREVER, __func__); }

int pthread_rwlock_tryrdlock(pthread_rwlock_t *rw)
{
    HAKO_SERVICE;
    return ((struct rwlock *)rw)->writer != 0 ? EBUSY : take(rw, false, 0, __func__);
}

int pthread_rwlock_trywrlock(pthread_rwlock_t *rw)
{
    HAKO_SERVICE;
    const struct rwlock *l = (const struct rwlock *)rw;
    return l->writer != 0 || l->readers != 0 ? EBUSY : take(rw, true, 0, __func__);
}

int pthread_rwlock_timedrdlock(pthread_rwlock_t *restrict rw, const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return take(rw, false, hako_clock_time_us(CLOCK_REALTIME, at), __func__);
}

int pthread_rwlock_timedwrlock(pthread_rwlock_t *restrict rw, const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return take(rw, true, hako_clock_time_us(CLOCK_REALTIME, at), __func__);
}

int pthread_rwlock_clockrdlock(pthread_rwlock_t *restrict rw, clockid_t clock, const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return take(rw, false, hako_clock_time_us(clock, at), __func__);
}

int pthread_rwlock_clockwrlock(pthread_rwlock_t *restrict rw, clockid_t clock, const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return take(rw, true, hako_clock_time_us(clock, at), __func__);
}

int pthread_rwlock_unlock(pthread_rwlock_t *rw)
{
    HAKO_SERVICE;
    struct rwlock *l = (struct rwlock *)rw;
    if (l->writer == me())
        l->writer = 0;
    else if (l->readers > 0)
        l->readers--;
    else
        return EPERM;
    hako_wake(rw, INT_MAX); /* they look again, in the order they came */
    return 0;
}

/* -- barriers and spin locks ---------------------------------------------------------------------------- */

struct barrier {
    uint32_t count;
    uint32_t arrived;
    uint32_t round;
};
_Static_assert(sizeof(struct barrier) <= sizeof(pthread_barrier_t), "a barrier's state fits in it");

int pthread_barrier_init(pthread_barrier_t *restrict b, const pthread_barrierattr_t *restrict attr, unsigned count)
{
    HAKO_SERVICE;
    (void)attr;
    if (count == 0)
        return EINVAL;
    memset(b, 0, sizeof *b);
    ((struct barrier *)b)->count = count;
    return 0;
}

int pthread_barrier_destroy(pthread_barrier_t *b)
{
    HAKO_SERVICE;
    (void)b;
    return 0;
}

int pthread_barrier_wait(pthread_barrier_t *b)
{
    HAKO_SERVICE;
    struct barrier *s = (struct barrier *)b;
    if (++s->arrived == s->count) {
        s->arrived = 0;
        s->round++;
        hako_wake(b, INT_MAX);
        return PTHREAD_BARRIER_SERIAL_THREAD;
    }
    uint32_t round = s->round;
    while (s->round == round)
        if (hako_block_on(b, HAKO_FOREVER) == EDEADLK)
            return cannot_wait(__func__);
    return 0;
}

/* A spin lock held across a wait: the spinner gives way (and takes a call's time) until it is let go. */
int pthread_spin_init(pthread_spinlock_t *lock, int pshared)
{
    HAKO_SERVICE;
    (void)pshared;
    *lock = 0;
    return 0;
}

int pthread_spin_destroy(pthread_spinlock_t *lock)
{
    HAKO_SERVICE;
    (void)lock;
    return 0;
}

int pthread_spin_lock(pthread_spinlock_t *lock)
{
    HAKO_SERVICE;
    while (*lock != 0) {
        if (hako_self() == NULL)
            return cannot_wait(__func__);
        hako_yield();
    }
    *lock = 1;
    return 0;
}

int pthread_spin_trylock(pthread_spinlock_t *lock)
{
    HAKO_SERVICE;
    if (*lock != 0)
        return EBUSY;
    *lock = 1;
    return 0;
}

int pthread_spin_unlock(pthread_spinlock_t *lock)
{
    HAKO_SERVICE;
    *lock = 0;
    return 0;
}

/* -- semaphores ----------------------------------------------------------------------------------------- */

struct sem {
    uint32_t value;
};
_Static_assert(sizeof(struct sem) <= sizeof(sem_t), "a semaphore's state fits in it");

static int fail(int err)
{
    errno = err;
    return -1;
}

int sem_init(sem_t *s, int pshared, unsigned value)
{
    HAKO_SERVICE;
    (void)pshared;
    if (value > SEM_VALUE_MAX)
        return fail(EINVAL);
    memset(s, 0, sizeof *s);
    ((struct sem *)s)->value = value;
    return 0;
}

int sem_destroy(sem_t *s)
{
    HAKO_SERVICE;
    (void)s;
    return 0;
}

static int sem_wait_until(sem_t *s, int64_t due, const char *call)
{
    HAKO_SERVICE;
    struct sem *v = (struct sem *)s;
    while (v->value == 0) {
        int err = hako_block_on(s, due);
        if (err == EDEADLK)
            return fail(cannot_wait(call));
        if (err == ETIMEDOUT)
            return fail(ETIMEDOUT);
    }
    v->value--;
    return 0;
}

int sem_wait(sem_t *s) { return sem_wait_until(s, HAKO_FOREVER, __func__); }

int sem_trywait(sem_t *s)
{
    HAKO_SERVICE;
    struct sem *v = (struct sem *)s;
    if (v->value == 0)
        return fail(EAGAIN);
    v->value--;
    return 0;
}

int sem_timedwait(sem_t *restrict s, const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return sem_wait_until(s, hako_clock_time_us(CLOCK_REALTIME, at), __func__);
}

int sem_clockwait(sem_t *restrict s, clockid_t clock, const struct timespec *restrict at)
{
    HAKO_SERVICE;
    return sem_wait_until(s, hako_clock_time_us(clock, at), __func__);
}

int sem_post(sem_t *s)
{
    HAKO_SERVICE;
    struct sem *v = (struct sem *)s;
    if (v->value == SEM_VALUE_MAX)
        return fail(EOVERFLOW);
    v->value++;
    hako_wake(s, 1);
    return 0;
}

int sem_getvalue(sem_t *restrict s, int *restrict value)
{
    HAKO_SERVICE;
    *value = (int)((struct sem *)s)->value;
    return 0;
}

sem_t *sem_open(const char *name, int flags, ...)
{
    HAKO_SERVICE;
    (void)name, (void)flags;
    hako_uncovered(__func__, "named semaphores are shared between processes; it fails with ENOSYS");
    errno = ENOSYS;
    return SEM_FAILED;
}

/* -- futexes, as libstdc++ calls them (syscall) ------------------------------------------------------------ */

static long futex(uint32_t *word, int op, uint32_t value, const struct timespec *timeout, uint32_t value3)
{
    HAKO_SERVICE;
    (void)value3;
    int command = op & FUTEX_CMD_MASK;
    if (command == FUTEX_WAKE || command == FUTEX_WAKE_BITSET)
        return hako_wake(word, value > INT_MAX ? INT_MAX : (int)value);
    if (command != FUTEX_WAIT && command != FUTEX_WAIT_BITSET) {
        hako_uncovered("syscall(SYS_futex)", "only FUTEX_WAIT and FUTEX_WAKE are; it fails with ENOSYS");
        return fail(ENOSYS);
    }
    if (*word != value)
        return fail(EAGAIN);
    int64_t due = HAKO_FOREVER;
    if (timeout != NULL && command == FUTEX_WAIT) {
        int64_t us = hako_duration_us(timeout);
        due = us == HAKO_FOREVER ? HAKO_FOREVER : hako_now() + us;
    } else if (timeout != NULL) {
        due = hako_clock_time_us(op & FUTEX_CLOCK_REALTIME ? CLOCK_REALTIME : CLOCK_MONOTONIC, timeout);
    }
    int err = hako_block_on(word, due);
    if (err == EDEADLK)
        return fail(cannot_wait("syscall(SYS_futex)"));
    return err == ETIMEDOUT ? fail(ETIMEDOUT) : 0;
}

long syscall(long number, ...)
{
    HAKO_SERVICE;
    va_list args;
    va_start(args, number);
    long a[6];
    for (int i = 0; i < 6; i++)
        a[i] = va_arg(args, long);
    va_end(args);
    switch (number) {
    case SYS_futex:
        return futex((uint32_t *)a[0], (int)a[1], (uint32_t)a[2], (const struct timespec *)a[3], (uint32_t)a[5]);
    case SYS_clock_gettime:
        return hako_clock_gettime((clockid_t)a[0], (struct timespec *)a[1]);
    case SYS_gettimeofday:
        return hako_gettimeofday((struct timeval *)a[0], (void *)a[1]);
    case SYS_nanosleep:
        return hako_nanosleep((const struct timespec *)a[0], (struct timespec *)a[1]);
    case SYS_clock_nanosleep: {
        int err =
            hako_clock_nanosleep((clockid_t)a[0], (int)a[1], (const struct timespec *)a[2], (struct timespec *)a[3]);
        return err != 0 ? fail(err) : 0;
    }
    default:
        return hako_real()->syscall(number, a[0], a[1], a[2], a[3], a[4], a[5]);
    }
}
