/*
 * Time events: each task's timeout, each cyclic handler's next firing and each device's next service, handled
 * in the order they fall due (ties: the order they were set); and the system time.
 */
#define _GNU_SOURCE
#include "kernel_impl.h"

ER get_tim(SYSTIM *p_systim)
{
    *p_systim = (SYSTIM)hako_now();
    hako_spend_call(); /* after the read: a read at a tick reads the tick */
    return E_OK;
}

static bool earlier(int64_t due, uint64_t order, int64_t best_due, uint64_t best_order)
{
    return due < best_due || (due == best_due && order < best_order);
}

/* Handle the first time event due by now; false if there is none. */
bool hako_handle_due_event(void)
{
    struct task *task = NULL;
    struct cyclic *cyclic = NULL;
    int64_t due = INT64_MAX, now = hako_tick();
    uint64_t order = UINT64_MAX;
    for (long i = 0; i < hako_k.task_count; i++) {
        struct task *t = hako_k.tasks[i];
        if (t != NULL && t->state == WAITING && t->timed && t->due <= now &&
            earlier(t->due, t->event_order, due, order))
            task = t, due = t->due, order = t->event_order;
    }
    for (uint_t i = 0; i < hako_cyclic_count; i++) {
        struct cyclic *c = &hako_k.cyclics[i];
        if (c->active && c->due <= now && earlier(c->due, c->event_order, due, order))
            cyclic = c, task = NULL, due = c->due, order = c->event_order;
    }
    if (cyclic != NULL) {
        hako_fire(cyclic);
    } else if (task != NULL) {
        task->wait_result = task->wait == WAIT_SLEEP ? E_TMOUT : task->wait == WAIT_OBJECT ? ETIMEDOUT : E_OK;
        hako_make_ready(task, false);
    }
    return cyclic != NULL || task != NULL;
}

int64_t hako_next_event(void)
{
    int64_t next = HAKO_NEVER_WAKES, now = hako_tick();
    for (long i = 0; i < hako_k.task_count; i++)
        if (hako_k.tasks[i] != NULL && hako_k.tasks[i]->state == WAITING && hako_k.tasks[i]->timed &&
            hako_k.tasks[i]->due < next)
            next = hako_k.tasks[i]->due;
    for (uint_t i = 0; i < hako_cyclic_count; i++)
        if (hako_k.cyclics[i].active && hako_k.cyclics[i].due < next)
            next = hako_k.cyclics[i].due;
    int64_t passive = HAKO_NEVER_WAKES;
    for (const hako_device *const *d = hako_devices_begin(); d != hako_devices_end(); d++) {
        int64_t due = (*d)->next_due ? (*d)->next_due(now) : HAKO_FOREVER;
        if ((*d)->passive && due < passive)
            passive = due;
        else if (!(*d)->passive && due < next)
            next = due;
    }
    return next == HAKO_NEVER_WAKES || next < passive ? next : passive;
}
