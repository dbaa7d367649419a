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
 * its priority, as on ASP3. A program with one task therefore runs exactly as athrill_sim/mock/kernel.py.
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
 *
 * The kernel's modules, as TOPPERS' kernel has them: task.c (the task services), task_sync.c (sleeping, waking
 * and the POSIX layer's waits), thread.c (the program's threads), cyclic.c, time_event.c and, here, dispatching.
 */
#define _GNU_SOURCE
#include "kernel_impl.h"

struct hako_kernel hako_k = {.step_used_at = -1};

int hako_enter_service(void)
{
    int was = hako_k.in_service;
    hako_k.in_service = 1;
    return was;
}

void hako_leave_service(int *was) { hako_k.in_service = *was; }

/* The C++ runtime's per-thread exception record, where the program is C++ (libstdc++'s __cxa_get_globals). */
extern void *__cxa_get_globals(void) __attribute__((weak));

/* Back to the kernel from the running task, which resumes here when dispatched again (still in a service). */
void hako_switch_to_kernel(struct task *self)
{
    swapcontext(&self->context, &hako_k.kernel_context);
    hako_k.in_service = 1;
}

/* -- the scheduler ------------------------------------------------------------------------------------ */

static struct task *next_ready(void)
{
    struct task *best = NULL;
    for (long i = 0; i < hako_k.task_count; i++) {
        struct task *t = hako_k.tasks[i];
        if (t != NULL && t->state == READY &&
            (best == NULL || t->priority < best->priority ||
             (t->priority == best->priority && t->ready_order < best->ready_order)))
            best = t;
    }
    return best;
}

static void task_entry(void)
{
    struct task *self = hako_k.running;
    if (self->thread)
        self->result = self->thread_entry(self->thread_arg);
    else
        self->entry(self->exinf);
    hako_k.in_service = 1;
    hako_end_running();
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
    struct task *self = hako_k.running;
    if (self == NULL || hako_k.in_service || !in_program_code(context))
        return;
    hako_make_ready(self, false);
    self->spun_at = hako_tick();
    hako_k.running = NULL;
    swapcontext(&self->context, &hako_k.kernel_context); /* resumed here when dispatched again */
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
    hako_k.running = t;
    swap_thread_state(t, true);
    hako_k.in_service = 0;
    start_slice();
    swapcontext(&hako_k.kernel_context, &t->context);
    hako_k.in_service = 1;
    swap_thread_state(t, false);
    hako_k.running = NULL;
}

/* Devices served at each snapshot, before any task: EV3RT's button cyclic, SPIKE-RT's motors. */
static void serve_devices(void)
{
    for (const hako_device *const *d = hako_devices_begin(); d != hako_devices_end(); d++)
        if ((*d)->serve)
            (*d)->serve();
}

void hako_kernel_exit(void)
{
    hako_k.in_service = 1;
    hako_window_flush();
    hako_publish(hako_tick(), HAKO_NEVER_WAKES);
    exit(0); /* the outputs stay as they are */
}

void hako_kernel_start(int64_t start_us)
{
    hako_k.in_service = 1;
    hako_time_set_tick(start_us);
    for (uint_t i = 0; i < hako_task_count; i++) {
        const hako_task_cfg *cfg = &hako_task_table[i];
        struct task *t = hako_new_task();
        if (t == NULL || !hako_give_stack(t, cfg->stack_size))
            hako_bench_fault("no memory for the stack of task %s", cfg->name);
        snprintf(t->name, sizeof t->name, "%s", cfg->name);
        t->priority = cfg->priority;
        t->entry = cfg->entry;
        t->exinf = cfg->exinf;
        if (cfg->attr & TA_ACT)
            hako_activate(t);
    }
    hako_k.cyclics = calloc(hako_cyclic_count + 1, sizeof *hako_k.cyclics);
    if (hako_k.cyclics == NULL)
        hako_bench_fault("no memory for the kernel's tables");
    for (uint_t i = 0; i < hako_cyclic_count; i++) {
        hako_k.cyclics[i].cfg = &hako_cyclic_table[i];
        if (hako_k.cyclics[i].cfg->attr & TA_STA)
            hako_start_cyclic(&hako_k.cyclics[i]);
    }
    for (const hako_device *const *d = hako_devices_begin(); d != hako_devices_end(); d++)
        if ((*d)->start)
            (*d)->start();
    hako_k.in_service = 0; /* the program's objects are constructed next, as a task's code */
}

void hako_kernel_run(void)
{
    hako_k.in_service = 1;
    serve_devices();
    start_spin_clock();
    for (;;) {
        while (hako_handle_due_event())
            ;
        hako_reap();
        int64_t now = hako_tick();
        struct task *t = next_ready();
        hako_window_flush();
        if (t != NULL && t->spun_at != now && hako_k.step_used_at != now) {
            dispatch(t);
            continue;
        }
        int64_t wake = hako_next_event();
        if (hako_k.step_used_at == now)
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
