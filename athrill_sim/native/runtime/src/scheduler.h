/*
 * What the kernel (kernel.c) offers the layers above it beside ASP3's services: the POSIX layer's threads
 * and waits (posix_*.c), and the devices' cost of a call. A thread is a task of the kernel's, scheduled as
 * app.cfg's tasks are; every wait is a task blocking on an object's address until another task wakes it or
 * its time comes.
 */
#ifndef HAKO_SCHEDULER_H
#define HAKO_SCHEDULER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sim_time.h"

typedef struct task hako_task;

/* A service of the kernel's, or of a layer above it, changing state the tasks share: the kernel's CPU-time
 * rescue never preempts a task in one (kernel.c). Marks the rest of its scope (GCC's cleanup runs on every
 * return), inside another one too. */
#define HAKO_SERVICE                                                                                                   \
    __attribute__((cleanup(hako_leave_service))) int hako_service_guard_ = hako_enter_service();                       \
    (void)hako_service_guard_
int hako_enter_service(void);
void hako_leave_service(int *was);

/* The task running now; NULL in a handler, in the kernel, or before the first task runs. */
hako_task *hako_self(void);

/* A task's number: app.cfg's tasks 1..N, threads after them; 0 for none. */
long hako_task_number(const hako_task *t);
hako_task *hako_task_by_number(long number); /* NULL for none, or an ended thread's that went */
long hako_task_limit(void); /* the highest number given so far */
const char *hako_task_name(const hako_task *t);

/* A call of the program's that takes HAKO_CALL_COST_US: may move the kernel on to the next tick first. */
void hako_spend_call(void);

/* Block the running task on `object` until hako_wake names it (0) or the clock reaches `due` (ETIMEDOUT; a due
 * time in the past times out at once, HAKO_FOREVER never). EDEADLK where no task runs: nothing could wake it. */
int hako_block_on(const void *object, int64_t due);

/* Make up to `max` tasks blocked on `object` ready, in the order they blocked; how many were. */
int hako_wake(const void *object, int max);

/* Make the first task blocked on `object` ready; which one (NULL: none was). */
hako_task *hako_wake_first(const void *object);

/* Let every other ready task of the running one's priority run first (sched_yield). */
void hako_yield(void);

/* A new thread at the running task's priority (the lowest one where no task runs), ready after those already
 * ready; NULL when there is no memory for it. */
hako_task *hako_thread_create(void *(*entry)(void *), void *arg, size_t stack_size);

/* End the running thread (or task) with `result`. */
void hako_thread_exit(void *result) __attribute__((noreturn));

/* Whether thread `t` has ended, and with what; its resources go when it is both ended and released. */
bool hako_thread_ended(const hako_task *t, void **result);
bool hako_thread_is_thread(const hako_task *t);
int hako_thread_release(hako_task *t); /* joined or detached: 0, or EINVAL if it already was */

#define HAKO_KEYS 128 /* pthread keys: PTHREAD_KEYS_MAX is 1024, programs use a handful */

/* Per-thread values (pthread keys), HAKO_KEYS of them; NULL for a key beyond. */
void **hako_task_specific(hako_task *t, unsigned key);

/* In a forked child: the running task goes on alone, as the forking thread does on Linux. */
void hako_kernel_forked(void);

/* Tasks that the kernel's exit finds still waiting for one another (not for a time or a wake-up call). */
int hako_tasks_stuck(void);

#endif /* HAKO_SCHEDULER_H */
