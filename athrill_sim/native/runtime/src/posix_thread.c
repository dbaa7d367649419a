/*
 * POSIX threads as the kernel's tasks (scheduler.h): std::thread, std::async and pthread_create start one, at
 * the priority of the task that starts it, ready after the tasks already ready there; it then runs as app.cfg's
 * tasks do, until it waits, ends or spends a whole step. A pthread_t is the task's number. Everything runs on
 * one thread of the operating system, in an order fixed by the program alone, which is what makes a test
 * repeat; what that costs is said in docs/NATIVE.md (variables declared thread_local are one for all).
 *
 * Covered: create, join (and try/timed/clock join), detach, self, exit, once, keys, yield, names, scheduling
 * parameters and affinity (accepted, without effect: the bench has one core). pthread_kill and pthread_cancel
 * are not, and say so.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "posix.h"

#define NAME_LEN 16 /* the kernel's limit on a thread's name, with its terminator */

struct start {
    void *(*entry)(void *);
    void *arg;
};

static void (*key_destructors[HAKO_KEYS])(void *);
static bool key_used[HAKO_KEYS];
static void *kernel_specific[HAKO_KEYS]; /* the keys' values where no task runs */
static char names[1024][NAME_LEN]; /* by task number; later threads keep the kernel's name */

static hako_task *thread_of(pthread_t thread) { return hako_task_by_number((long)thread); }

/* POSIX: each key's destructor, for each non-NULL value, up to PTHREAD_DESTRUCTOR_ITERATIONS rounds. */
static void run_key_destructors(void)
{
    hako_task *self = hako_self();
    for (int round = 0; round < 4; round++) {
        bool any = false;
        for (unsigned k = 0; k < HAKO_KEYS; k++) {
            void **slot = self != NULL ? hako_task_specific(self, k) : &kernel_specific[k];
            if (!key_used[k] || key_destructors[k] == NULL || slot == NULL || *slot == NULL)
                continue;
            void *value = *slot;
            *slot = NULL;
            key_destructors[k](value);
            any = true;
        }
        if (!any)
            return;
    }
}

static void *thread_main(void *arg)
{
    struct start start = *(struct start *)arg;
    free(arg);
    void *result = start.entry(start.arg);
    run_key_destructors();
    return result;
}

int pthread_create(pthread_t *restrict thread, const pthread_attr_t *restrict attr, void *(*entry)(void *),
                   void *restrict arg)
{
    HAKO_SERVICE;
    size_t stack = 0;
    int detach = PTHREAD_CREATE_JOINABLE;
    if (attr != NULL) {
        pthread_attr_getstacksize(attr, &stack);
        pthread_attr_getdetachstate(attr, &detach);
    }
    struct start *start = malloc(sizeof *start);
    if (start == NULL)
        return EAGAIN;
    *start = (struct start){entry, arg};
    hako_task *t = hako_thread_create(thread_main, start, stack);
    if (t == NULL) {
        free(start);
        return EAGAIN;
    }
    if (detach == PTHREAD_CREATE_DETACHED)
        hako_thread_release(t);
    *thread = (pthread_t)hako_task_number(t);
    return 0;
}

/* Wait until `thread` ends, at most until `due`. */
static int join_until(pthread_t thread, void **result, int64_t due)
{
    HAKO_SERVICE;
    hako_task *t = thread_of(thread);
    if (t == NULL || !hako_thread_is_thread(t))
        return ESRCH;
    if (t == hako_self())
        return EDEADLK;
    while (!hako_thread_ended(t, result)) {
        int err = hako_block_on(t, due);
        if (err == EDEADLK) {
            hako_uncovered("pthread_join", "joining a running thread where no task runs cannot wait");
            return EDEADLK;
        }
        if (err == ETIMEDOUT)
            return ETIMEDOUT;
    }
    return hako_thread_release(t);
}

int pthread_join(pthread_t thread, void **result) { return join_until(thread, result, HAKO_FOREVER); }

int pthread_tryjoin_np(pthread_t thread, void **result)
{
    HAKO_SERVICE;
    hako_task *t = thread_of(thread);
    if (t == NULL || !hako_thread_is_thread(t))
        return ESRCH;
    return hako_thread_ended(t, result) ? hako_thread_release(t) : EBUSY;
}

int pthread_clockjoin_np(pthread_t thread, void **result, clockid_t clock, const struct timespec *at)
{
    HAKO_SERVICE;
    return join_until(thread, result, hako_clock_time_us(clock, at));
}

int pthread_timedjoin_np(pthread_t thread, void **result, const struct timespec *at)
{
    HAKO_SERVICE;
    return pthread_clockjoin_np(thread, result, CLOCK_REALTIME, at);
}

int pthread_detach(pthread_t thread)
{
    HAKO_SERVICE;
    hako_task *t = thread_of(thread);
    if (t == NULL || !hako_thread_is_thread(t))
        return ESRCH;
    return hako_thread_release(t);
}

/* A task's number; where no task runs, the operating system's thread (a value no task number takes). */
static pthread_t kernel_thread;

pthread_t pthread_self(void)
{
    HAKO_SERVICE;
    hako_task *self = hako_self();
    if (self != NULL)
        return (pthread_t)hako_task_number(self);
    if (kernel_thread == 0)
        kernel_thread = (pthread_t)-1;
    return kernel_thread;
}

void pthread_exit(void *result)
{
    HAKO_SERVICE;
    if (hako_self() == NULL) {
        hako_uncovered(__func__, "where no task runs it ends the program");
        hako_kernel_exit();
    }
    run_key_destructors();
    hako_thread_exit(result);
}

int sched_yield(void)
{
    HAKO_SERVICE;
    hako_yield();
    return 0;
}

/* -- once ----------------------------------------------------------------------------------------------- */

enum { ONCE_NEW, ONCE_RUNNING, ONCE_DONE }; /* PTHREAD_ONCE_INIT is 0 */

int pthread_once(pthread_once_t *once, void (*routine)(void))
{
    HAKO_SERVICE;
    while (*once == ONCE_RUNNING) /* another task is in it and waits for something: wait for it */
        if (hako_block_on(once, HAKO_FOREVER) == EDEADLK)
            return EDEADLK;
    if (*once == ONCE_DONE)
        return 0;
    *once = ONCE_RUNNING;
    routine();
    *once = ONCE_DONE;
    hako_wake(once, INT32_MAX);
    return 0;
}

/* -- keys ------------------------------------------------------------------------------------------------ */

int pthread_key_create(pthread_key_t *key, void (*destructor)(void *))
{
    HAKO_SERVICE;
    for (unsigned k = 0; k < HAKO_KEYS; k++) {
        if (key_used[k])
            continue;
        key_used[k] = true;
        key_destructors[k] = destructor;
        *key = k;
        return 0;
    }
    return EAGAIN;
}

int pthread_key_delete(pthread_key_t key)
{
    HAKO_SERVICE;
    if (key >= HAKO_KEYS || !key_used[key])
        return EINVAL;
    key_used[key] = false;
    key_destructors[key] = NULL;
    for (long n = 1; n <= hako_task_limit(); n++) {
        hako_task *t = hako_task_by_number(n);
        void **slot = t != NULL ? hako_task_specific(t, key) : NULL;
        if (slot != NULL)
            *slot = NULL;
    }
    kernel_specific[key] = NULL;
    return 0;
}

static void **specific(pthread_key_t key)
{
    if (key >= HAKO_KEYS || !key_used[key])
        return NULL;
    hako_task *self = hako_self();
    return self != NULL ? hako_task_specific(self, key) : &kernel_specific[key];
}

void *pthread_getspecific(pthread_key_t key)
{
    HAKO_SERVICE;
    void **slot = specific(key);
    return slot != NULL ? *slot : NULL;
}

int pthread_setspecific(pthread_key_t key, const void *value)
{
    HAKO_SERVICE;
    void **slot = specific(key);
    if (slot == NULL)
        return EINVAL;
    *slot = (void *)value;
    return 0;
}

/* -- names, scheduling, affinity: accepted ------------------------------------------------------------- */

static char *name_of(pthread_t thread)
{
    long n = (long)thread;
    if (thread == kernel_thread || n < 1 || n >= (long)(sizeof names / sizeof names[0]) || thread_of(thread) == NULL)
        return NULL;
    if (names[n][0] == '\0')
        snprintf(names[n], NAME_LEN, "%s", hako_task_name(thread_of(thread)));
    return names[n];
}

int pthread_setname_np(pthread_t thread, const char *name)
{
    HAKO_SERVICE;
    char *slot = name_of(thread);
    if (slot == NULL)
        return ESRCH;
    if (strlen(name) >= NAME_LEN)
        return ERANGE;
    snprintf(slot, NAME_LEN, "%s", name);
    return 0;
}

int pthread_getname_np(pthread_t thread, char *name, size_t size)
{
    HAKO_SERVICE;
    const char *slot = name_of(thread);
    if (slot == NULL)
        return ESRCH;
    if (strlen(slot) >= size)
        return ERANGE;
    memcpy(name, slot, strlen(slot) + 1);
    return 0;
}

int pthread_setschedparam(pthread_t thread, int policy, const struct sched_param *param)
{
    HAKO_SERVICE;
    (void)policy, (void)param;
    return thread_of(thread) != NULL || thread == kernel_thread ? 0 : ESRCH;
}

int pthread_getschedparam(pthread_t thread, int *restrict policy, struct sched_param *restrict param)
{
    HAKO_SERVICE;
    if (thread_of(thread) == NULL && thread != kernel_thread)
        return ESRCH;
    *policy = SCHED_OTHER;
    param->sched_priority = 0;
    return 0;
}

int pthread_setschedprio(pthread_t thread, int priority)
{
    HAKO_SERVICE;
    (void)priority;
    return thread_of(thread) != NULL || thread == kernel_thread ? 0 : ESRCH;
}

int pthread_setaffinity_np(pthread_t thread, size_t size, const cpu_set_t *set)
{
    HAKO_SERVICE;
    (void)size, (void)set;
    return thread_of(thread) != NULL || thread == kernel_thread ? 0 : ESRCH;
}

int pthread_getaffinity_np(pthread_t thread, size_t size, cpu_set_t *set)
{
    HAKO_SERVICE;
    if (thread_of(thread) == NULL && thread != kernel_thread)
        return ESRCH;
    memset(set, 0, size);
    CPU_SET_S(0, size, set);
    return 0;
}

/* -- not covered ---------------------------------------------------------------------------------------- */

int pthread_kill(pthread_t thread, int sig)
{
    HAKO_SERVICE;
    (void)thread;
    if (sig == 0)
        return thread_of(thread) != NULL || thread == kernel_thread ? 0 : ESRCH;
    hako_uncovered(__func__, "signals between threads are not delivered; it fails with ENOSYS");
    return ENOSYS;
}

int pthread_cancel(pthread_t thread)
{
    HAKO_SERVICE;
    (void)thread;
    hako_uncovered(__func__, "threads are not cancelled; it fails with ENOSYS");
    return ENOSYS;
}
