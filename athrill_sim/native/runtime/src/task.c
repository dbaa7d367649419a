/*
 * The tasks of app.cfg and the program's threads as the kernel keeps them: their records and stacks, their
 * states, and ASP3's task management services (act_tsk, ext_tsk, ter_tsk, get_pri, get_tid).
 */
#define _GNU_SOURCE
#include "kernel_impl.h"

struct task *hako_task_of(ID id)
{
    if (id == TSK_SELF)
        return hako_k.running;
    return id >= 1 && (uint_t)id <= hako_task_count ? hako_k.tasks[id - 1] : NULL;
}

void hako_make_ready(struct task *t, bool at_head)
{
    t->state = READY;
    t->timed = false;
    t->wait_on = NULL;
    t->ready_order = at_head ? --hako_k.ready_head : ++hako_k.ready_tail;
}

void hako_activate(struct task *t)
{
    t->fresh = true;
    t->wakeups = 0;
    hako_make_ready(t, false);
}

/* Called after `t` became ready: a running task of lower priority lets it run first. */
void hako_yield_if_outranked(const struct task *t)
{
    if (hako_k.running == NULL || t->priority >= hako_k.running->priority)
        return;
    struct task *self = hako_k.running;
    hako_make_ready(self, true);
    hako_switch_to_kernel(self);
}

/* An act_tsk or wup_tsk for a task that cannot take it now: remembered, up to `max`. */
ER hako_queue_request(uint_t *queued, uint_t max)
{
    if (*queued >= max)
        return E_QOVR;
    (*queued)++;
    return E_OK;
}

int hako_block(enum wait_kind wait, const void *object, bool timed, int64_t due)
{
    struct task *self = hako_k.running;
    self->state = WAITING;
    self->wait = wait;
    self->wait_on = object;
    self->timed = timed;
    self->due = due;
    self->event_order = ++hako_k.events_set;
    hako_switch_to_kernel(self);
    return self->wait_result;
}

/* -- task services ------------------------------------------------------------------------------------ */

ER act_tsk(ID tskid)
{
    HAKO_SERVICE;
    struct task *t = hako_task_of(tskid);
    if (t == NULL || t->thread)
        return E_ID;
    if (t->state != DORMANT)
        return hako_queue_request(&t->activations, TMAX_ACTCNT);
    hako_activate(t);
    hako_yield_if_outranked(t);
    return E_OK;
}

void hako_end_running(void)
{
    struct task *self = hako_k.running;
    if (self->thread) {
        self->state = ENDED;
        hako_wake(self, INT32_MAX); /* its joiners */
    } else if (self->activations > 0) {
        self->activations--;
        hako_activate(self);
    } else {
        self->state = DORMANT;
    }
    setcontext(&hako_k.kernel_context);
    abort(); /* not reached */
}

ER ext_tsk(void)
{
    HAKO_SERVICE;
    if (hako_k.running == NULL)
        return E_CTX;
    hako_end_running();
}

ER ter_tsk(ID tskid)
{
    HAKO_SERVICE;
    struct task *t = hako_task_of(tskid);
    if (t == NULL)
        return E_ID;
    if (t == hako_k.running)
        return E_ILUSE;
    if (t->state == DORMANT)
        return E_OBJ;
    t->state = DORMANT;
    t->timed = false;
    if (t->activations > 0) { /* ASP3: a queued activation starts it again */
        t->activations--;
        hako_activate(t);
        hako_yield_if_outranked(t);
    }
    return E_OK;
}

ER get_pri(ID tskid, PRI *p_tskpri)
{
    struct task *t = hako_task_of(tskid);
    if (t == NULL)
        return E_ID;
    if (t->state == DORMANT)
        return E_OBJ;
    *p_tskpri = t->priority;
    return E_OK;
}

ER get_tid(ID *p_tskid)
{
    *p_tskid = hako_k.running != NULL ? (ID)hako_k.running->number : TSK_NONE;
    return E_OK;
}

/* A stack with a guard page below it: an overflow faults instead of corrupting its neighbour. */
bool hako_give_stack(struct task *t, size_t wanted)
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

struct task *hako_new_task(void)
{
    if (hako_k.task_count == hako_k.task_capacity) {
        long capacity = hako_k.task_capacity ? hako_k.task_capacity * 2 : 16;
        struct task **grown = realloc(hako_k.tasks, (size_t)capacity * sizeof *grown);
        if (grown == NULL)
            return NULL;
        hako_k.tasks = grown;
        hako_k.task_capacity = capacity;
    }
    struct task *t = calloc(1, sizeof *t);
    if (t == NULL)
        return NULL;
    t->number = hako_k.task_count + 1;
    t->spun_at = -1;
    hako_k.tasks[hako_k.task_count++] = t;
    return t;
}
