/*
 * ASP3's and EV3RT's cyclic handlers: started, stopped, and fired when their time event falls due.
 */
#define _GNU_SOURCE
#include "kernel_impl.h"

/* EV3RT's cyclic handlers (EV3_CRE_CYC) and ASP3's (CRE_CYC) are numbered apart, each from 1 in app.cfg's
 * order: ev3_sta_cyc takes the first kind's IDs only and answers E_ID for any other, as EV3RT's does
 * (ev3cyclic_dri.c, CHECK_EV3CYCID), and sta_cyc the second's. */
static struct cyclic *cyclic_of(ID id, bool ev3)
{
    ID seen = 0;
    for (uint_t i = 0; i < hako_cyclic_count; i++)
        if (hako_k.cyclics[i].cfg->ev3 == ev3 && ++seen == id)
            return &hako_k.cyclics[i];
    return NULL;
}

/* -- cyclic handlers ---------------------------------------------------------------------------------- */

static void schedule(struct cyclic *c)
{
    c->due = c->base + hako_whole_steps((int64_t)c->cfg->phase_us + c->fired * (int64_t)c->cfg->period_us);
    c->event_order = ++hako_k.events_set;
}

ER hako_start_cyclic(struct cyclic *c)
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

ER sta_cyc(ID cycid) { return hako_start_cyclic(cyclic_of(cycid, false)); }

ER stp_cyc(ID cycid) { return stop_cyclic(cyclic_of(cycid, false)); }

ER ev3_sta_cyc(ID ev3cycid) { return hako_start_cyclic(cyclic_of(ev3cycid, true)); }

ER ev3_stp_cyc(ID ev3cycid) { return stop_cyclic(cyclic_of(ev3cycid, true)); }

void hako_fire(struct cyclic *c)
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
