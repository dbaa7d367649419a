/*
 * The kernel: the tasks and cyclic handlers of app.cfg, run by a deterministic cooperative scheduler in
 * simulated time.
 *
 * Simulated time passes only while no task is ready: the earliest time event (a task's timeout or a cyclic
 * handler's next firing) is published to the physics process as the wake-up time, and the kernel waits for
 * the sensor snapshot of exactly that instant. Computation takes no simulated time. At one instant, time
 * events are handled in the order they fall due (ties: the order they were set); cyclic handlers run before
 * any task, as a time-event handler preempts tasks on ASP3; tasks run highest priority (lowest number)
 * first, FIFO within a priority. A task is never interrupted: it runs until it blocks or ends, or until it
 * activates or wakes a task of higher priority, which then runs first while the caller waits at the head of
 * its priority, as on ASP3. A program with one task therefore runs exactly as athrill_sim/kernel.py.
 *
 * Times are rounded up to whole physics steps, as the mock kernel does: tslp_tsk(d) wakes at
 * now + ceil(d / step) * step.
 *
 * A task that computes without end (EV3RT programs end in `while (1) {}`, or poll a sensor without sleeping)
 * would stop simulated time, where on the real emulator its instructions take time and interrupts still
 * come. So a task that has run for HAKO_SPIN_SLICE_US of CPU time since it was dispatched is preempted (in
 * its own code): it stays ready at the head of its priority, and simulated time may pass by up to
 * HAKO_SPIN_TIME_US (less if a time event falls due sooner), as if the spin had taken that long. The slice
 * is counted from each dispatch, never from the process's start: a task that computes for less than a slice
 * before it blocks is never preempted, whatever the machine and its load, so its results do not depend on
 * where a periodic CPU timer happened to fire. A spin never interrupts a kernel service or the C library
 * (the signal only preempts the program's own code), and how many iterations a spin makes per step depends
 * on the machine, as on the real emulator.
 */
#define _GNU_SOURCE
#include <signal.h>
#include <stdbool.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/time.h>
#include <ucontext.h>
#include <unistd.h>

#include "ev3api.h"
#include "hako_cfg.h"
#include "runtime.h"

#define HAKO_MIN_STACK (256 * 1024) /* host code (printf, libm) needs more than a v850 task's 4 KiB */
#define HAKO_SPIN_SLICE_US 2000 /* CPU time since its dispatch after which a computing task is preempted */
#define HAKO_SPIN_TIME_US 10000 /* the simulated time a preempted spin is taken to have used */

enum task_state { DORMANT, READY, RUNNING, WAITING };
enum wait_kind { WAIT_SLEEP, WAIT_DELAY }; /* slp_tsk / tslp_tsk (wup_tsk ends it), or dly_tsk */

struct task {
    const hako_task_cfg *cfg;
    enum task_state state;
    enum wait_kind wait;
    bool timed; /* waiting with a timeout: a time event at `due` */
    int64_t due;
    uint64_t event_order;
    int64_t ready_order; /* FIFO within a priority; a preempted task gets a smaller one than everyone */
    ER wait_result;
    uint_t activations; /* queued act_tsk calls */
    uint_t wakeups; /* queued wup_tsk calls */
    bool fresh; /* starts from its entry function when next dispatched */
    int64_t spun_at; /* the simulated time it was last preempted for spinning; -1: never */
    ucontext_t context;
    void *stack;
    size_t stack_size;
};

struct cyclic {
    const hako_cyclic_cfg *cfg;
    bool active;
    int64_t base; /* when it was started */
    int64_t fired;
    int64_t due;
    uint64_t event_order;
};

static struct task *tasks;
static struct cyclic *cyclics;
static struct task *running; /* NULL while the kernel or a cyclic handler runs */
static ucontext_t kernel_context;
static int64_t now_us;
static uint64_t events_set;
static int64_t ready_tail, ready_head;
static volatile sig_atomic_t in_service; /* a kernel service is changing the kernel's state: never preempted */

static int enter_service(void) { return in_service = 1; }
static void leave_service(int *unused) { (void)unused, in_service = 0; }
/* Marks a kernel service for the rest of its scope (GCC's cleanup runs on every return). */
#define SERVICE __attribute__((cleanup(leave_service))) int service_guard_ = enter_service(); (void)service_guard_

int64_t hako_now(void) { return now_us; }

static int64_t whole_steps(int64_t us)
{
    return (us + HAKO_PHYSICS_STEP_US - 1) / HAKO_PHYSICS_STEP_US * HAKO_PHYSICS_STEP_US;
}

static struct task *task_of(ID id)
{
    if (id == TSK_SELF)
        return running;
    return id >= 1 && (uint_t)id <= hako_task_count ? &tasks[id - 1] : NULL;
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
    t->ready_order = at_head ? --ready_head : ++ready_tail;
}

static void activate(struct task *t)
{
    t->fresh = true;
    t->wakeups = 0;
    make_ready(t, false);
}

/* Called after `t` became ready: a running task of lower priority lets it run first. */
static void yield_if_outranked(const struct task *t)
{
    if (running == NULL || t->cfg->priority >= running->cfg->priority)
        return;
    struct task *self = running;
    make_ready(self, true);
    swapcontext(&self->context, &kernel_context);
}

/* An act_tsk or wup_tsk for a task that cannot take it now: remembered, up to `max`. */
static ER queue_request(uint_t *queued, uint_t max)
{
    if (*queued >= max)
        return E_QOVR;
    (*queued)++;
    return E_OK;
}

static ER block(enum wait_kind wait, bool timed, int64_t due)
{
    struct task *self = running;
    self->state = WAITING;
    self->wait = wait;
    self->timed = timed;
    self->due = due;
    self->event_order = ++events_set;
    swapcontext(&self->context, &kernel_context);
    return self->wait_result;
}

/* -- task services ------------------------------------------------------------------------------------ */

ER act_tsk(ID tskid)
{
    SERVICE;
    struct task *t = task_of(tskid);
    if (t == NULL)
        return E_ID;
    if (t->state != DORMANT)
        return queue_request(&t->activations, TMAX_ACTCNT);
    activate(t);
    yield_if_outranked(t);
    return E_OK;
}

ER ext_tsk(void)
{
    SERVICE;
    struct task *self = running;
    if (self == NULL)
        return E_CTX;
    if (self->activations > 0) {
        self->activations--;
        activate(self);
    } else {
        self->state = DORMANT;
    }
    setcontext(&kernel_context);
    return E_SYS; /* not reached */
}

ER ter_tsk(ID tskid)
{
    SERVICE;
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
    *p_tskpri = t->cfg->priority;
    return E_OK;
}

ER get_tid(ID *p_tskid)
{
    *p_tskid = running != NULL ? (ID)(running - tasks + 1) : TSK_NONE;
    return E_OK;
}

ER slp_tsk(void)
{
    SERVICE;
    if (running == NULL)
        return E_CTX;
    if (running->wakeups > 0) {
        running->wakeups--;
        return E_OK;
    }
    return block(WAIT_SLEEP, false, 0);
}

ER tslp_tsk(TMO tmout)
{
    SERVICE;
    if (running == NULL)
        return E_CTX;
    if (running->wakeups > 0) {
        running->wakeups--;
        return E_OK;
    }
    if (tmout == TMO_FEVR) /* ASP3: no timeout, the task sleeps until woken */
        return block(WAIT_SLEEP, false, 0);
    if (tmout <= 0) /* TMO_POL: polling, times out at once */
        return E_TMOUT;
    return block(WAIT_SLEEP, true, now_us + whole_steps(tmout));
}

ER dly_tsk(RELTIM dlytim)
{
    SERVICE;
    if (running == NULL)
        return E_CTX;
    if (dlytim == 0)
        return E_OK;
    return block(WAIT_DELAY, true, now_us + whole_steps(dlytim));
}

ER wup_tsk(ID tskid)
{
    SERVICE;
    struct task *t = task_of(tskid);
    if (t == NULL)
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
    *p_systim = (SYSTIM)now_us;
    return E_OK;
}

/* -- cyclic handlers ---------------------------------------------------------------------------------- */

static void schedule(struct cyclic *c)
{
    c->due = c->base + whole_steps((int64_t)c->cfg->phase_us + c->fired * (int64_t)c->cfg->period_us);
    c->event_order = ++events_set;
}

static ER start_cyclic(struct cyclic *c)
{
    SERVICE;
    if (c == NULL)
        return E_ID;
    c->active = true;
    c->base = now_us;
    c->fired = 0;
    schedule(c);
    return E_OK;
}

static ER stop_cyclic(struct cyclic *c)
{
    SERVICE;
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
    int64_t due = INT64_MAX;
    uint64_t order = UINT64_MAX;
    for (uint_t i = 0; i < hako_task_count; i++) {
        struct task *t = &tasks[i];
        if (t->state == WAITING && t->timed && t->due <= now_us && earlier(t->due, t->event_order, due, order))
            task = t, due = t->due, order = t->event_order;
    }
    for (uint_t i = 0; i < hako_cyclic_count; i++) {
        struct cyclic *c = &cyclics[i];
        if (c->active && c->due <= now_us && earlier(c->due, c->event_order, due, order))
            cyclic = c, task = NULL, due = c->due, order = c->event_order;
    }
    if (cyclic != NULL) {
        fire(cyclic);
    } else if (task != NULL) {
        task->wait_result = task->wait == WAIT_SLEEP ? E_TMOUT : E_OK;
        make_ready(task, false);
    }
    return cyclic != NULL || task != NULL;
}

static int64_t next_event(void)
{
    int64_t next = HAKO_NEVER_WAKES;
    for (uint_t i = 0; i < hako_task_count; i++)
        if (tasks[i].state == WAITING && tasks[i].timed && tasks[i].due < next)
            next = tasks[i].due;
    for (uint_t i = 0; i < hako_cyclic_count; i++)
        if (cyclics[i].active && cyclics[i].due < next)
            next = cyclics[i].due;
    if (hako_buttons_watched()) {
        int64_t poll = (now_us / HAKO_BUTTON_POLL_US + 1) * HAKO_BUTTON_POLL_US;
        if (poll < next)
            next = poll;
    }
    if (hako_spike_next_due && hako_spike_next_due(now_us) < next)
        next = hako_spike_next_due(now_us);
    return next;
}

static struct task *next_ready(void)
{
    struct task *best = NULL;
    for (uint_t i = 0; i < hako_task_count; i++) {
        struct task *t = &tasks[i];
        if (t->state == READY && (best == NULL || t->cfg->priority < best->cfg->priority ||
                                  (t->cfg->priority == best->cfg->priority && t->ready_order < best->ready_order)))
            best = t;
    }
    return best;
}

static void task_entry(void)
{
    running->cfg->entry(running->cfg->exinf);
    ext_tsk();
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
    make_ready(self, true);
    self->spun_at = now_us;
    running = NULL;
    swapcontext(&self->context, &kernel_context); /* resumed here when dispatched again */
}

static void start_spin_clock(void)
{
    struct sigaction sa = {.sa_sigaction = on_spin_tick, .sa_flags = SA_SIGINFO | SA_RESTART};
    sigemptyset(&sa.sa_mask);
    if (sigaction(SIGVTALRM, &sa, NULL) != 0)
        hako_bench_fault("cannot start the kernel's CPU clock");
}

/* A fresh slice of CPU time for the task about to run: then one slice after, once a slice. */
static void start_slice(void)
{
    struct itimerval slice = {{0, HAKO_SPIN_SLICE_US}, {0, HAKO_SPIN_SLICE_US}};
    if (setitimer(ITIMER_VIRTUAL, &slice, NULL) != 0)
        hako_bench_fault("cannot start the kernel's CPU clock");
}

static void dispatch(struct task *t)
{
    if (t->fresh) {
        t->fresh = false;
        getcontext(&t->context);
        t->context.uc_stack.ss_sp = t->stack;
        t->context.uc_stack.ss_size = t->stack_size;
        t->context.uc_link = NULL;
        makecontext(&t->context, task_entry, 0);
    }
    t->state = RUNNING;
    running = t;
    in_service = 0;
    start_slice();
    swapcontext(&kernel_context, &t->context);
    running = NULL;
}

/* A stack with a guard page below it: an overflow faults instead of corrupting its neighbour. */
static void give_stack(struct task *t)
{
    size_t page = (size_t)sysconf(_SC_PAGESIZE);
    size_t size = t->cfg->stack_size > HAKO_MIN_STACK ? t->cfg->stack_size : HAKO_MIN_STACK;
    size = (size + page - 1) / page * page;
    uint8_t *area = mmap(NULL, size + page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_STACK, -1, 0);
    if (area == MAP_FAILED || mprotect(area, page, PROT_NONE) != 0)
        hako_bench_fault("no memory for the stack of task %s", t->cfg->name);
    t->stack = area + page;
    t->stack_size = size;
}

/* Devices served at each snapshot, before any task: EV3RT's button cyclic, and SPIKE-RT's motors. */
static void serve_devices(void)
{
    hako_buttons_poll();
    if (hako_spike_serve)
        hako_spike_serve();
}

void hako_kernel_exit(void)
{
    hako_window_flush();
    hako_publish(now_us, HAKO_NEVER_WAKES);
    exit(0); /* the outputs stay as they are */
}

void hako_kernel_start(int64_t start_us)
{
    now_us = start_us;
    tasks = calloc(hako_task_count + 1, sizeof *tasks);
    cyclics = calloc(hako_cyclic_count + 1, sizeof *cyclics);
    if (tasks == NULL || cyclics == NULL)
        hako_bench_fault("no memory for the kernel's tables");
    for (uint_t i = 0; i < hako_task_count; i++) {
        tasks[i].cfg = &hako_task_table[i];
        tasks[i].spun_at = -1;
        give_stack(&tasks[i]);
        if (tasks[i].cfg->attr & TA_ACT)
            activate(&tasks[i]);
    }
    for (uint_t i = 0; i < hako_cyclic_count; i++) {
        cyclics[i].cfg = &hako_cyclic_table[i];
        if (cyclics[i].cfg->attr & TA_STA)
            start_cyclic(&cyclics[i]);
    }
    hako_sdcard_enter();
}

void hako_kernel_run(void)
{
    serve_devices();
    start_spin_clock();
    for (;;) {
        while (handle_due_event())
            ;
        struct task *t = next_ready();
        hako_window_flush();
        if (t != NULL && t->spun_at != now_us) {
            dispatch(t);
            continue;
        }
        int64_t wake = next_event();
        if (t != NULL && wake > now_us + HAKO_SPIN_TIME_US)
            wake = now_us + HAKO_SPIN_TIME_US; /* a spinning task: the spin took that long */
        if (wake == HAKO_NEVER_WAKES)
            hako_kernel_exit(); /* every task has ended and nothing is left to fire */
        hako_publish(now_us, wake);
        hako_wait_snapshot(wake);
        hako_window_load();
        now_us = wake;
        serve_devices();
    }
}
