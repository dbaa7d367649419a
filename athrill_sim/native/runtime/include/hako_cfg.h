/* The tables kernel_cfg.c (generated from app.cfg) fills in and the kernel runs. */
#ifndef HAKO_CFG_H
#define HAKO_CFG_H

#include "kernel.h"

#ifdef __cplusplus
extern "C" {
#endif
typedef struct {
    const char *name;
    ATR attr;
    intptr_t exinf;
    void (*entry)(intptr_t exinf);
    PRI priority;
    size_t stack_size; /* what app.cfg asks for; a host task gets at least HAKO_MIN_STACK */
} hako_task_cfg;

typedef struct {
    uint_t mode; /* TNFY_HANDLER, TNFY_ACTTSK or TNFY_WUPTSK */
    intptr_t arg; /* the handler's exinf, or the task to activate or wake */
    void (*handler)(intptr_t exinf);
} hako_notify;

typedef struct {
    const char *name;
    ATR attr;
    hako_notify notify;
    RELTIM period_us;
    RELTIM phase_us;
    bool ev3; /* EV3_CRE_CYC (ev3_sta_cyc's IDs), else CRE_CYC (sta_cyc's) */
} hako_cyclic_cfg;

extern const hako_task_cfg hako_task_table[];
extern const uint_t hako_task_count;
extern const hako_cyclic_cfg hako_cyclic_table[];
extern const uint_t hako_cyclic_count;
#ifdef __cplusplus
}
#endif

#endif /* HAKO_CFG_H */
