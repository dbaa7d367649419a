/* A RasPike-ART program as a team writes one: see app.c. */
#ifdef __cplusplus
extern "C" {
#endif

#include "spikeapi.h"

#define MAIN_PRIORITY (TMIN_APP_TPRI + 1)
#define TRACER_PRIORITY (TMIN_APP_TPRI + 2)
#define TRACER_PERIOD_US (10 * 1000)

#ifndef STACK_SIZE
#define STACK_SIZE (4096)
#endif

#ifndef TOPPERS_MACRO_ONLY
extern void main_task(intptr_t exinf);
extern void tracer_task(intptr_t exinf);
#endif

#ifdef __cplusplus
}
#endif
