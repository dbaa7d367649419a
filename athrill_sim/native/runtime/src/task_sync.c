/*
 * Tasks waiting and woken: ASP3's task synchronisation services (slp_tsk, tslp_tsk, dly_tsk, wup_tsk) and
 * the waits the POSIX layer builds on (scheduler.h), and the time a call spends.
 */
#define _GNU_SOURCE
#include "kernel_impl.h"

/* ASP3 (kernel/task_sync.c): slp_tsk is tslp_tsk without a timeout. */
ER slp_tsk(void) { return tslp_tsk(TMO_FEVR); }

ER tslp_tsk(TMO tmout)
{
    HAKO_SERVICE;
    if (hako_k.running == NULL)
        return E_CTX;
    if (hako_k.running->wakeups > 0) {
        hako_k.running->wakeups--;
        return E_OK;
    }
    if (tmout == TMO_FEVR) /* ASP3: no timeout, the task sleeps until woken */
        return hako_block(WAIT_SLEEP, NULL, false, 0);
    if (tmout <= 0) /* TMO_POL: polling, times out at once */
        return E_TMOUT;
    return hako_block(WAIT_SLEEP, NULL, true, hako_tick() + hako_whole_steps(tmout));
}

ER dly_tsk(RELTIM dlytim)
{
    HAKO_SERVICE;
    if (hako_k.running == NULL)
        return E_CTX;
    if (dlytim == 0)
        return E_OK;
    return hako_block(WAIT_DELAY, NULL, true, hako_tick() + hako_whole_steps(dlytim));
}

ER wup_tsk(ID tskid)
{
    HAKO_SERVICE;
    struct task *t = hako_task_of(tskid);
    if (t == NULL || t->thread)
        return E_ID;
    if (t->state == DORMANT)
        return E_OBJ;
    if (t->state != WAITING || t->wait != WAIT_SLEEP)
        return hako_queue_request(&t->wakeups, TMAX_WUPCNT);
    t->wait_result = E_OK;
    hako_make_ready(t, false);
    hako_yield_if_outranked(t);
    return E_OK;
}

void hako_spend_call(void)
{
    HAKO_SERVICE;
    if (!hako_time_spend(HAKO_CALL_COST_US) || hako_k.running == NULL)
        return; /* a handler's calls are never preempted */
    struct task *self = hako_k.running;
    hako_k.step_used_at = hako_tick();
    hako_make_ready(self, false);
    hako_switch_to_kernel(self);
}

int hako_block_on(const void *object, int64_t due)
{
    HAKO_SERVICE;
    if (hako_k.running == NULL)
        return EDEADLK;
    if (due <= hako_now())
        return ETIMEDOUT;
    bool timed = due != HAKO_FOREVER;
    return hako_block(WAIT_OBJECT, object, timed, timed ? hako_whole_steps(due) : 0);
}

hako_task *hako_wake_first(const void *object)
{
    HAKO_SERVICE;
    struct task *first = NULL;
    for (long i = 0; i < hako_k.task_count; i++) {
        struct task *t = hako_k.tasks[i];
        if (t != NULL && t->state == WAITING && t->wait == WAIT_OBJECT && t->wait_on == object &&
            (first == NULL || t->event_order < first->event_order))
            first = t;
    }
    if (first != NULL) {
        first->wait_result = 0;
        hako_make_ready(first, false);
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
    if (hako_k.running == NULL)
        return;
    struct task *self = hako_k.running;
    hako_make_ready(self, false);
    hako_switch_to_kernel(self);
}
