// The tracer's task for app.cfg. spikeapi.h guards its own C declarations; only main_task needs C linkage here.
#include "spikeapi.h"

#define MAIN_PRIORITY (TMIN_APP_TPRI + 1)
#define STACK_SIZE 8192

#ifndef TOPPERS_MACRO_ONLY
#ifdef __cplusplus
extern "C" {
#endif
void main_task(intptr_t exinf);
#ifdef __cplusplus
}
#endif
#endif
