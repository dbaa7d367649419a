/*
 * The kernel: the tasks and cyclic handlers of app.cfg, and the program's threads, run by a deterministic
 * cooperative scheduler in simulated time.
 *
 * Simulated time moves from tick to tick (sim_time.h) only while no task is ready: the earliest time event
 * (a task's timeout or a cyclic handler's next firing) is published to the physics process as the wake-up
 * time, and the kernel waits for the sensor snapshot of exactly that instant. Computation takes no simulated
 * time, but each call that reads a clock or uses a device spends HAKO_CALL_COST_US, and a task that spends a
 * whole step without waiting is preempted there: the kernel moves to the next tick before anything else runs,
 * and the task goes on after the other ready tasks of its priority (as threads share a core on Linux), so a
 * loop that polls a clock or a sensor sees time pass the same way on every machine.
 *
 * At one instant, time events are handled in the order they fall due (ties: the order they were set); cyclic
 * handlers run before any task, as a time-event handler preempts tasks on ASP3; tasks run highest priority
 * (lowest number) first, FIFO within a priority. A task runs until it blocks or ends, spends a step, or
 * activates or wakes a task of higher priority, which then runs first while the caller waits at the head of
 * its priority, as on ASP3. A program with one task therefore runs exactly as athrill_sim/kernel.py.
 *
 * A relative wait is counted from the tick it is asked at and rounded up to whole steps, as the mock kernel
 * does: tslp_tsk(d) wakes at tick + ceil(d / step) * step, whatever the task spent in that step (a few
 * microseconds, where rounding its end up would add a whole step). An absolute one wakes at the first tick at
 * or after its time.
 *
 * A task that computes without any call (EV3RT programs end in `while (1) {}`) would stop simulated time,
 * where on the real emulator its instructions take time and interrupts still come. So a task that has run for
 * HAKO_SPIN_SLICE_US of CPU time since it was dispatched is preempted (in its own code), and simulated time
 * may pass by up to HAKO_SPIN_TIME_US (less if a time event falls due sooner), as if the spin had taken that
 * long. The slice is counted from each dispatch, so a task that computes for less than a slice before it
 * blocks is never preempted, whatever the machine and its load. A spin never interrupts a kernel service or
 * the C library (the signal only preempts the program's own code), and how many iterations such a spin makes
 * per step depends on the machine, as on the real emulator.
 */
#define _GNU_SOURCE
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
#define HAKO_SPIN_TIME_US 10000 /* the simulated time a preempted spin is taken to have used */
#define HAKO_KEYS 128 /* pthread keys: PTHREAD_KEYS_MAX is 1024, programs use a handful */

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

static struct task **tasks;
static long task_count, task_capacity;
static struct cyclic *cyclics;
static struct task *running; /* NULL while the kernel or a cyclic handler runs */
static ucontext_t kernel_context;
static uint64_t events_set;
static int64_t ready_tail, ready_head;
static int64_t step_used_at = -1; /* the tick whose step a task spent whole: time must move on first */
static volatile sig_atomic_t in_service; /* a kernel service is changing the kernel's state: never preempted */

int hako_enter_service(void)
{
    int was = in_service;
    in_service = 1;
    return was;
}

void hako_leave_service(int *was) { in_service = *was; }

/* The C++ runtime's per-thread exception record, where the program is C++ (libstdc++'s __cxa_get_globals). */
extern void *__cxa_get_globals(void) __attribute__((weak));

static struct task *task_of(ID id)
{
    if (id == TSK_SELF)
        return running;
    return id >= 1 && (uint_t)id <= hako_task_count ? tasks[id - 1] : NULL;
}

/* EV3RT's cyclic handlers (EV3_CRE_CYC) and ASP3's (CRE_CYC) are numbered apart, each from 1 in app.cfg's
 * order: ev3_sta_cyc takes the first kind's IDs only and answers E_ID for any other, as EV3RT's does
 * (ev3cyclic_dri.c, CHECK_EV3CYCID), and sta_cyc the second's. */
static struct cyclic *cyclic_of(ID id, bool ev3)
{
    ID seen = 0;
    for (uint_t i = 0; i < hako_cyclic_count; i++)
        if (cyclics[i].cfg->ev3 == ev3 && ++seen == id)
            return &cyclics[i];
    return NULL;
}

static void make_ready(struct task *t, bool at_head)
{
    t->state = READY;
    t->timed = false;
    t->wait_on = NULL;
    t->ready_order = at_head ? --ready_head : ++ready_tail;
}

static void activate(struct task *t)
{
    t->fresh = true;
    t->wakeups = 0;
    make_ready(t, false);
}

/* Back to the kernel from the running task, which resumes here when dispatched again (still in a service). */
static void switch_to_kernel(struct task *self)
{
    swapcontext(&self->context, &kernel_context);
    in_service = 1;
}

/* Called after `t` became ready: a running task of lower priority lets it run first. */
static void yield_if_outranked(const struct task *t)
{
    if (running == NULL || t->priority >= running->priority)
        return;
    struct task *self = running;
    make_ready(self, true);
    switch_to_kernel(self);
}

/* An act_tsk or wup_tsk for a task that cannot take it now: remembered, up to `max`. */
static ER queue_request(uint_t *queued, uint_t max)
{
    if (*queued >= max)
        return E_QOVR;
    (*queued)++;
    return E_OK;
}

static int block(enum wait_kind wait, const void *object, bool timed, int64_t due)
{
    struct task *self = running;
    self->state = WAITING;
    self->wait = wait;
    self->wait_on = object;
    self->timed = timed;
    self->due = due;
    self->event_order = ++events_set;
    switch_to_kernel(self);
    return self->wait_result;
}

/* -- task services ------------------------------------------------------------------------------------ */

ER act_tsk(ID tskid)
{
    HAKO_SERVICE;
    struct task *t = task_of(tskid);
    if (t == NULL || t->thread)
        return E_ID;
    if (t->state != DORMANT)
        return queue_request(&t->activations, TMAX_ACTCNT);
    activate(t);
    yield_if_outranked(t);
    return E_OK;
}

static void end_running(void) __attribute__((noreturn));
static void end_running(void)
{
    struct task *self = running;
    if (self->thread) {
        self->state = ENDED;
        hako_wake(self, INT32_MAX); /* its joiners */
    } else if (self->activations > 0) {
        self->activations--;
        activate(self);
    } else {
        self->state = DORMANT;
    }
    setcontext(&kernel_context);
    abort(); /* not reached */
}

ER ext_tsk(void)
{
    HAKO_SERVICE;
    if (running == NULL)
        return E_CTX;
    end_running();
}

ER ter_tsk(ID tskid)
{
    HAKO_SERVICE;
    struct task *t = task_of(tskid);
    if (t == NULL)
        return E_ID;
    if (t == running)
        return E_ILUSE;
    if (t->state == DORMANT)
        return E_OBJ;
    t->state = DORMANT;
    t->timed = false;
    if (t->activations > 0) { /* ASP3: a queued activation starts it again */
        t->activations--;
        activate(t);
        yield_if_outranked(t);
    }
    return E_OK;
}

ER get_pri(ID tskid, PRI *p_tskpri)
{
    struct task *t = task_of(tskid);
    if (t == NULL)
        return E_ID;
    if (t->state == DORMANT)
        return E_OBJ;
    *p_tskpri = t->priority;
    return E_OK;
}

ER get_tid(ID *p_tskid)
{
    *p_tskid = running != NULL ? (ID)running->number : TSK_NONE;
    return E_OK;
}

ER slp_tsk(void)
{
    HAKO_SERVICE;
    if (running == NULL)
        return E_CTX;
    if (running->wakeups > 0) {
        running->wakeups--;
        return E_OK;
    }
    return block(WAIT_SLEEP, NULL, false, 0);
}

ER tslp_tsk(TMO tmout)
{
    HAKO_SERVICE;
    if (running == NULL)
        return E_CTX;
    if (running->wakeups > 0) {
        running->wakeups--;
        return E_OK;
    }
    if (tmout == TMO_FEVR) /* ASP3: no timeout, the task sleeps until woken */
        return block(WAIT_SLEEP, NULL, false, 0);
    if (tmout <= 0) /* TMO_POL: polling, times out at once */
        return E_TMOUT;
    return block(WAIT_SLEEP, NULL, true, hako_tick() + hako_whole_steps(tmout));
}

ER dly_tsk(RELTIM dlytim)
{
    HAKO_SERVICE;
    if (running == NULL)
        return E_CTX;
    if (dlytim == 0)
        return E_OK;
    return block(WAIT_DELAY, NULL, true, hako_tick() + hako_whole_steps(dlytim));
}

ER wup_tsk(ID tskid)
{
    HAKO_SERVICE;
    struct task *t = task_of(tskid);
    if (t == NULL || t->thread)
        return E_ID;
    if (t->state == DORMANT)
        return E_OBJ;
    if (t->state != WAITING || t->wait != WAIT_SLEEP)
        return queue_request(&t->wakeups, TMAX_WUPCNT);
    t->wait_result = E_OK;
    make_ready(t, false);
    yield_if_outranked(t);
    return E_OK;
}

ER get_tim(SYSTIM *p_systim)
{
    *p_systim = (SYSTIM)hako_now();
    hako_spend_call(); /* after the read: a read at a tick reads the tick */
    return E_OK;
}

/* -- the POSIX layer's threads and waits (scheduler.h) ------------------------------------------------ */

hako_task *hako_self(void) { return running; }

long hako_task_number(const hako_task *t) { return t != NULL ? t->number : 0; }

hako_task *hako_task_by_number(long number) { return number >= 1 && number <= task_count ? tasks[number - 1] : NULL; }

long hako_task_limit(void) { return task_count; }

const char *hako_task_name(const hako_task *t) { return t != NULL ? t->name : "the kernel"; }

void hako_spend_call(void)
{
    HAKO_SERVICE;
    if (!hako_time_spend(HAKO_CALL_COST_US) || running == NULL)
        return; /* a handler's calls are never preempted */
    struct task *self = running;
    step_used_at = hako_tick();
    make_ready(self, false);
    switch_to_kernel(self);
}

int hako_block_on(const void *object, int64_t due)
{
    HAKO_SERVICE;
    if (running == NULL)
        return EDEADLK;
    if (due <= hako_now())
        return ETIMEDOUT;
    bool timed = due != HAKO_FOREVER;
    return block(WAIT_OBJECT, object, timed, timed ? hako_whole_steps(due) : 0);
}

hako_task *hako_wake_first(const void *object)
{
    HAKO_SERVICE;
    struct task *first = NULL;
    for (long i = 0; i < task_count; i++) {
        struct task *t = tasks[i];
        if (t != NULL && t->state == WAITING && t->wait == WAIT_OBJECT && t->wait_on == object &&
            (first == NULL || t->event_order < first->event_order))
            first = t;
    }
    if (first != NULL) {
        first->wait_result = 0;
        make_ready(first, false);
    }
    return first;
}

int hako_wake(const void *object, int max)
{
    int woken = 0;
    while (woken < max && hako_wake_first(object) != NULL)
        woken++;
    return woken;
}

void hako_yield(void)
{
    hako_spend_call();
    HAKO_SERVICE;
    if (running == NULL)
        return;
    struct task *self = running;
    make_ready(self, false);
    switch_to_kernel(self);
}

/* A stack with a guard page below it: an overflow faults instead of corrupting its neighbour. */
static bool give_stack(struct task *t, size_t wanted)
{
    size_t page = (size_t)sysconf(_SC_PAGESIZE);
    size_t size = (wanted > HAKO_MIN_STACK ? wanted : HAKO_MIN_STACK) + page - 1;
    size = size / page * page;
    uint8_t *area = mmap(NULL, size + page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_STACK, -1, 0);
    if (area == MAP_FAILED)
        return false;
    if (mprotect(area, page, PROT_NONE) != 0) {
        munmap(area, size + page);
        return false;
    }
    t->area = area;
    t->area_size = size + page;
    t->context.uc_stack.ss_sp = area + page;
    t->context.uc_stack.ss_size = size;
    return true;
}

static struct task *new_task(void)
{
    if (task_count == task_capacity) {
        long capacity = task_capacity ? task_capacity * 2 : 16;
        struct task **grown = realloc(tasks, (size_t)capacity * sizeof *grown);
        if (grown == NULL)
            return NULL;
        tasks = grown;
        task_capacity = capacity;
    }
    struct task *t = calloc(1, sizeof *t);
    if (t == NULL)
        return NULL;
    t->number = task_count + 1;
    t->spun_at = -1;
    tasks[task_count++] = t;
    return t;
}

hako_task *hako_thread_create(void *(*entry)(void *), void *arg, size_t stack_size)
{
    HAKO_SERVICE;
    struct task *t = new_task();
    if (t == NULL)
        return NULL;
    if (!give_stack(t, stack_size > HAKO_THREAD_STACK ? stack_size : HAKO_THREAD_STACK)) {
        tasks[--task_count] = NULL;
        free(t);
        return NULL;
    }
    snprintf(t->name, sizeof t->name, "thread %ld", t->number);
    t->thread = true;
    t->thread_entry = entry;
    t->thread_arg = arg;
    t->priority = running != NULL ? running->priority : TMAX_TPRI;
    activate(t);
    return t;
}

void hako_thread_exit(void *result)
{
    HAKO_SERVICE;
    running->result = result;
    end_running();
}

bool hako_thread_ended(const hako_task *t, void **result)
{
    if (t->state != ENDED)
        return false;
    if (result != NULL)
        *result = t->result;
    return true;
}

bool hako_thread_is_thread(const hako_task *t) { return t->thread; }

int hako_thread_release(hako_task *t)
{
    if (t->released)
        return EINVAL;
    t->released = true;
    return 0;
}

void **hako_task_specific(hako_task *t, unsigned key)
{
    if (key >= HAKO_KEYS)
        return NULL;
    if (t->specific == NULL && (t->specific = calloc(HAKO_KEYS, sizeof *t->specific)) == NULL)
        return NULL;
    return &t->specific[key];
}

void hako_kernel_forked(void)
{
    HAKO_SERVICE;
    for (long i = 0; i < task_count; i++)
        if (tasks[i] != NULL && tasks[i] != running) {
            tasks[i]->state = tasks[i]->thread ? ENDED : DORMANT;
            tasks[i]->activations = 0;
            tasks[i]->timed = false;
        }
    for (uint_t i = 0; i < hako_cyclic_count; i++)
        cyclics[i].active = false;
}

int hako_tasks_stuck(void)
{
    int stuck = 0;
    for (long i = 0; i < task_count; i++)
        if (tasks[i] != NULL && tasks[i]->state == WAITING && tasks[i]->wait == WAIT_OBJECT && !tasks[i]->timed)
            stuck++;
    return stuck;
}

/* A thread that ended and was joined or detached: its stack and record go (never while it runs on them). */
static void reap(void)
{
    for (long i = 0; i < task_count; i++) {
        struct task *t = tasks[i];
        if (t == NULL || !t->thread || t->state != ENDED || !t->released)
            continue;
        munmap(t->area, t->area_size);
        free(t->specific);
        free(t);
        tasks[i] = NULL;
    }
}

/* -- cyclic handlers ---------------------------------------------------------------------------------- */

static void schedule(struct cyclic *c)
{
    c->due = c->base + hako_whole_steps((int64_t)c->cfg->phase_us + c->fired * (int64_t)c->cfg->period_us);
    c->event_order = ++events_set;
}

static ER start_cyclic(struct cyclic *c)
{
    HAKO_SERVICE;
    if (c == NULL)
        return E_ID;
    c->active = true;
    c->base = hako_tick();
    c->fired = 0;
    schedule(c);
    return E_OK;
}

static ER stop_cyclic(struct cyclic *c)
{
    HAKO_SERVICE;
    if (c == NULL)
        return E_ID;
    c->active = false;
    return E_OK;
}

ER sta_cyc(ID cycid) { return start_cyclic(cyclic_of(cycid, false)); }

ER stp_cyc(ID cycid) { return stop_cyclic(cyclic_of(cycid, false)); }

ER ev3_sta_cyc(ID ev3cycid) { return start_cyclic(cyclic_of(ev3cycid, true)); }

ER ev3_stp_cyc(ID ev3cycid) { return stop_cyclic(cyclic_of(ev3cycid, true)); }

static void fire(struct cyclic *c)
{
    const hako_notify *n = &c->cfg->notify;
    c->fired++;
    schedule(c);
    ER ercd = E_OK;
    if (n->mode == TNFY_HANDLER)
        n->handler(n->arg);
    else if (n->mode == TNFY_ACTTSK)
        ercd = act_tsk((ID)n->arg);
    else if (n->mode == TNFY_WUPTSK)
        ercd = wup_tsk((ID)n->arg);
    if (ercd != E_OK)
        hako_log("cyclic handler %s: notification failed, ercd %d", c->cfg->name, ercd);
}

/* -- the scheduler ------------------------------------------------------------------------------------ */

static bool earlier(int64_t due, uint64_t order, int64_t best_due, uint64_t best_order)
{
    return due < best_due || (due == best_due && order < best_order);
}

/* Handle the first time event due by now; false if there is none. */
static bool handle_due_event(void)
{
    struct task *task = NULL;
    struct cyclic *cyclic = NULL;
    int64_t due = INT64_MAX, now = hako_tick();
    uint64_t order = UINT64_MAX;
    for (long i = 0; i < task_count; i++) {
        struct task *t = tasks[i];
        if (t != NULL && t->state == WAITING && t->timed && t->due <= now &&
            earlier(t->due, t->event_order, due, order))
            task = t, due = t->due, order = t->event_order;
    }
    for (uint_t i = 0; i < hako_cyclic_count; i++) {
        struct cyclic *c = &cyclics[i];
        if (c->active && c->due <= now && earlier(c->due, c->event_order, due, order))
            cyclic = c, task = NULL, due = c->due, order = c->event_order;
    }
    if (cyclic != NULL) {
        fire(cyclic);
    } else if (task != NULL) {
        task->wait_result = task->wait == WAIT_SLEEP ? E_TMOUT : task->wait == WAIT_OBJECT ? ETIMEDOUT : E_OK;
        make_ready(task, false);
    }
    return cyclic != NULL || task != NULL;
}

static const hako_device *const *devices_begin(void) { return __start_hako_devices; }
static const hako_device *const *devices_end(void) { return __start_hako_devices ? __stop_hako_devices : NULL; }

static int64_t next_event(void)
{
    int64_t next = HAKO_NEVER_WAKES, now = hako_tick();
    for (long i = 0; i < task_count; i++)
        if (tasks[i] != NULL && tasks[i]->state == WAITING && tasks[i]->timed && tasks[i]->due < next)
            next = tasks[i]->due;
    for (uint_t i = 0; i < hako_cyclic_count; i++)
        if (cyclics[i].active && cyclics[i].due < next)
            next = cyclics[i].due;
    int64_t passive = HAKO_NEVER_WAKES;
    for (const hako_device *const *d = devices_begin(); d != devices_end(); d++) {
        int64_t due = (*d)->next_due ? (*d)->next_due(now) : HAKO_FOREVER;
        if ((*d)->passive && due < passive)
            passive = due;
        else if (!(*d)->passive && due < next)
            next = due;
    }
    return next == HAKO_NEVER_WAKES || next < passive ? next : passive;
}

static struct task *next_ready(void)
{
    struct task *best = NULL;
    for (long i = 0; i < task_count; i++) {
        struct task *t = tasks[i];
        if (t != NULL && t->state == READY &&
            (best == NULL || t->priority < best->priority ||
             (t->priority == best->priority && t->ready_order < best->ready_order)))
            best = t;
    }
    return best;
}

static void task_entry(void)
{
    struct task *self = running;
    if (self->thread)
        self->result = self->thread_entry(self->thread_arg);
    else
        self->entry(self->exinf);
    in_service = 1;
    end_running();
}

extern char __executable_start[], etext[];

static bool in_program_code(const ucontext_t *uc)
{
#if defined(__x86_64__)
    uintptr_t pc = (uintptr_t)uc->uc_mcontext.gregs[REG_RIP];
#elif defined(__aarch64__)
    uintptr_t pc = (uintptr_t)uc->uc_mcontext.pc;
#else
    uintptr_t pc = 0;
    (void)uc;
#endif
    return pc >= (uintptr_t)__executable_start && pc < (uintptr_t)etext;
}

static void on_spin_tick(int sig, siginfo_t *info, void *context)
{
    (void)sig, (void)info;
    struct task *self = running;
    if (self == NULL || in_service || !in_program_code(context))
        return;
    make_ready(self, false);
    self->spun_at = hako_tick();
    running = NULL;
    swapcontext(&self->context, &kernel_context); /* resumed here when dispatched again */
}

static void start_spin_clock(void)
{
    struct sigaction sa = {.sa_sigaction = on_spin_tick, .sa_flags = SA_SIGINFO | SA_RESTART};
    sigemptyset(&sa.sa_mask);
    if (hako_real()->sigaction(SIGVTALRM, &sa, NULL) != 0)
        hako_bench_fault("cannot start the kernel's CPU clock");
}

/* A fresh slice of CPU time for the task about to run: then one slice after, once a slice. */
static void start_slice(void)
{
    struct itimerval slice = {{0, HAKO_SPIN_SLICE_US}, {0, HAKO_SPIN_SLICE_US}};
    if (hako_real()->setitimer(ITIMER_VIRTUAL, &slice, NULL) != 0)
        hako_bench_fault("cannot start the kernel's CPU clock");
}

/* What each task keeps of the process's per-thread state, swapped in and out with it. */
static void swap_thread_state(struct task *t, bool in)
{
    int *eh = __cxa_get_globals ? (int *)__cxa_get_globals() : NULL;
    if (in) {
        errno = t->saved_errno;
        if (eh != NULL)
            memcpy(eh, t->eh_globals, sizeof t->eh_globals);
    } else {
        t->saved_errno = errno;
        if (eh != NULL)
            memcpy(t->eh_globals, eh, sizeof t->eh_globals);
    }
}

static void dispatch(struct task *t)
{
    if (t->fresh) {
        t->fresh = false;
        stack_t stack = t->context.uc_stack;
        getcontext(&t->context);
        t->context.uc_stack = stack;
        t->context.uc_link = NULL;
        makecontext(&t->context, task_entry, 0);
    }
    t->state = RUNNING;
    running = t;
    swap_thread_state(t, true);
    in_service = 0;
    start_slice();
    swapcontext(&kernel_context, &t->context);
    in_service = 1;
    swap_thread_state(t, false);
    running = NULL;
}

/* Devices served at each snapshot, before any task: EV3RT's button cyclic, SPIKE-RT's motors. */
static void serve_devices(void)
{
    for (const hako_device *const *d = devices_begin(); d != devices_end(); d++)
        if ((*d)->serve)
            (*d)->serve();
}

void hako_kernel_exit(void)
{
    in_service = 1;
    hako_window_flush();
    hako_publish(hako_tick(), HAKO_NEVER_WAKES);
    exit(0); /* the outputs stay as they are */
}

void hako_kernel_start(int64_t start_us)
{
    in_service = 1;
    hako_time_set_tick(start_us);
    for (uint_t i = 0; i < hako_task_count; i++) {
        const hako_task_cfg *cfg = &hako_task_table[i];
        struct task *t = new_task();
        if (t == NULL || !give_stack(t, cfg->stack_size))
            hako_bench_fault("no memory for the stack of task %s", cfg->name);
        snprintf(t->name, sizeof t->name, "%s", cfg->name);
        t->priority = cfg->priority;
        t->entry = cfg->entry;
        t->exinf = cfg->exinf;
        if (cfg->attr & TA_ACT)
            activate(t);
    }
    cyclics = calloc(hako_cyclic_count + 1, sizeof *cyclics);
    if (cyclics == NULL)
        hako_bench_fault("no memory for the kernel's tables");
    for (uint_t i = 0; i < hako_cyclic_count; i++) {
        cyclics[i].cfg = &hako_cyclic_table[i];
        if (cyclics[i].cfg->attr & TA_STA)
            start_cyclic(&cyclics[i]);
    }
    for (const hako_device *const *d = devices_begin(); d != devices_end(); d++)
        if ((*d)->start)
            (*d)->start();
    in_service = 0; /* the program's objects are constructed next, as a task's code */
}

void hako_kernel_run(void)
{
    in_service = 1;
    serve_devices();
    start_spin_clock();
    for (;;) {
        while (handle_due_event())
            ;
        reap();
        int64_t now = hako_tick();
        struct task *t = next_ready();
        hako_window_flush();
        if (t != NULL && t->spun_at != now && step_used_at != now) {
            dispatch(t);
            continue;
        }
        int64_t wake = next_event();
        if (step_used_at == now)
            wake = now + HAKO_PHYSICS_STEP_US; /* a task spent the step: the next one, whatever is due */
        else if (t != NULL && wake > now + HAKO_SPIN_TIME_US)
            wake = now + HAKO_SPIN_TIME_US; /* a spinning task: the spin took that long */
        if (wake == HAKO_NEVER_WAKES) {
            if (hako_tasks_stuck() > 0)
                hako_log("every task and thread waits for another, and nothing is left to wake one (a deadlock)");
            hako_kernel_exit(); /* every task has ended and nothing is left to fire */
        }
        hako_publish(now, wake);
        hako_wait_snapshot(wake);
        hako_window_load();
        hako_time_set_tick(wake);
        serve_devices();
    }
}
