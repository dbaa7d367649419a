/* The tutorial's two tasks, with C linkage: EV3RT's kernel_cfg.c (C) calls them. */
#include "ev3api.h"

#define TRACER_PERIOD_US (4 * 1000)

#if defined(__cplusplus) && !defined(TOPPERS_MACRO_ONLY)
extern "C" void main_task(intptr_t exinf);
extern "C" void tracer_task(intptr_t exinf);
#elif !defined(TOPPERS_MACRO_ONLY)
extern void main_task(intptr_t exinf);
extern void tracer_task(intptr_t exinf);
#endif
