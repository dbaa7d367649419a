/*
 * What the kernel's modules share (kernel.c, task.c, task_sync.c, thread.c, cyclic.c, time_event.c), as
 * TOPPERS' kernel shares kernel_impl.h: the task and cyclic handler records, the one kernel state, and the
 * functions each module gives the others. Nothing outside the kernel includes it; the layers above use
 * scheduler.h. Every name is hako_'s: the runtime is linked with the program, whose names are its own.
 */
#ifndef HAKO_KERNEL_IMPL_H
#define HAKO_KERNEL_IMPL_H

#include <errno.h>
#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/time.h>
#include <ucontext.h>
#include <unistd.h>

#include "devices.h"
#include "ev3api.h"
#include "hako_cfg.h"
#include "real.h"
#include "runtime.h"
#include "scheduler.h"

#define HAKO_MIN_STACK (256 * 1024) /* host code (printf, libm) needs more than a v850 task's 4 KiB */
#define HAKO_THREAD_STACK (8 * 1024 * 1024) /* a thread's stack unless it asks for more: glibc's default */
#define HAKO_SPIN_SLICE_US 2000 /* CPU time since its dispatch after which a computing task is preempted */

enum task_state { DORMANT, READY, RUNNING, WAITING, ENDED };
enum wait_kind { WAIT_SLEEP, WAIT_DELAY, WAIT_OBJECT }; /* slp_tsk / tslp_tsk (wup_tsk ends it), dly_tsk, a thread's */

struct task {
    long number;
    char name[32];
    PRI priority;
    void (*entry)(intptr_t exinf); /* app.cfg's task */
    intptr_t exinf;
    void *(*thread_entry)(void *); /* a thread's */
    void *thread_arg;
    void *result;
    bool thread;
    bool released; /* a thread joined or detached: its resources go when it ends */
    enum task_state state;
    enum wait_kind wait;
    const void *wait_on;
    bool timed; /* waiting with a timeout: a time event at `due` */
    int64_t due;
    uint64_t event_order;
    int64_t ready_order; /* FIFO within a priority; a task preempted by a higher one gets a smaller one */
    int wait_result;
    uint_t activations; /* queued act_tsk calls */
    uint_t wakeups; /* queued wup_tsk calls */
    bool fresh; /* starts from its entry function when next dispatched */
    int64_t spun_at; /* the tick at which it was last preempted for spinning; -1: never */
    int saved_errno; /* errno is the process's: each task keeps its own across switches */
    void *eh_globals[2]; /* and so is the C++ runtime's record of the exceptions being handled */
    void **specific;
    ucontext_t context;
    uint8_t *area; /* the stack's mapping, its guard page first */
    size_t area_size;
};

struct cyclic {
    const hako_cyclic_cfg *cfg;
    bool active;
    int64_t base; /* when it was started */
    int64_t fired;
    int64_t due;
    uint64_t event_order;
};

/* The kernel's state: one, as the process runs one kernel. */
struct hako_kernel {
    struct task **tasks;
    long task_count, task_capacity;
    struct cyclic *cyclics;
    struct task *running; /* NULL while the kernel or a cyclic handler runs */
    ucontext_t kernel_context;
    uint64_t events_set;
    int64_t ready_tail, ready_head;
    int64_t step_used_at; /* the tick whose step a task spent whole: time must move on first */
    volatile sig_atomic_t in_service; /* a kernel service is changing the kernel's state: never preempted */
};
extern struct hako_kernel hako_k;

/* task.c: the task records, their states and the task services */
struct task *hako_task_of(ID id);
void hako_make_ready(struct task *t, bool at_head);
void hako_activate(struct task *t);
void hako_yield_if_outranked(const struct task *t);
ER hako_queue_request(uint_t *queued, uint_t max);
int hako_block(enum wait_kind wait, const void *object, bool timed, int64_t due);
void hako_end_running(void) __attribute__((noreturn));
bool hako_give_stack(struct task *t, size_t wanted);
struct task *hako_new_task(void);

/* thread.c: threads that ended and were released go */
void hako_reap(void);

/* cyclic.c */
ER hako_start_cyclic(struct cyclic *c);
void hako_fire(struct cyclic *c);

/* time_event.c: the time events (timeouts, cyclic handlers, devices) in the order they fall due */
bool hako_handle_due_event(void);
int64_t hako_next_event(void);

/* kernel.c: dispatching */
void hako_switch_to_kernel(struct task *self);

static inline const hako_device *const *hako_devices_begin(void) { return __start_hako_devices; }
static inline const hako_device *const *hako_devices_end(void)
{
    return __start_hako_devices ? __stop_hako_devices : NULL;
}

#endif /* HAKO_KERNEL_IMPL_H */
