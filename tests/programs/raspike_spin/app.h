/* A RasPike-ART program that busy-waits: see app.c. */
#ifdef __cplusplus
extern "C" {
#endif

#include "spikeapi.h"

#define MAIN_PRIORITY (TMIN_APP_TPRI + 1)

#ifndef STACK_SIZE
#define STACK_SIZE (4096)
#endif

#ifndef TOPPERS_MACRO_ONLY
extern void main_task(intptr_t exinf);
#endif

#ifdef __cplusplus
}
#endif
