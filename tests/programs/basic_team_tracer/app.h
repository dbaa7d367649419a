#ifndef APP_H
#define APP_H

#ifdef __cplusplus
extern "C" {
#endif

#include <kernel.h>

#define MAIN_PRIORITY    5
#define TRACER_PRIORITY  6

#define TRACER_PERIOD    (10 * 1000)   /* us: the tracer runs every 10 ms */

#ifndef STACK_SIZE
#define STACK_SIZE       (4096)
#endif

#ifndef TOPPERS_MACRO_ONLY
void main_task(intptr_t exinf);
void tracer_task(intptr_t exinf);
#endif

#ifdef __cplusplus
}
#endif

#endif
