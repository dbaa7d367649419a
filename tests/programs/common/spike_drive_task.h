/* HackSPi look-alikes' tasks: a main task that waits for the start, and a drive task a 10 ms cyclic handler
 * activates (TNFY_ACTTSK), as teams' RasPike-ART programs are laid out. */
#ifdef __cplusplus
extern "C" {
#endif

#include "spikeapi.h"

#define MAIN_PRIORITY (TMIN_APP_TPRI + 1)
#define DRIVE_PRIORITY (TMIN_APP_TPRI + 2)
#define DRIVE_PERIOD_US (10 * 1000)

#ifndef STACK_SIZE
#define STACK_SIZE (4096)
#endif

#ifndef TOPPERS_MACRO_ONLY
extern void main_task(intptr_t exinf);
extern void drive_task(intptr_t exinf);
#endif

#ifdef __cplusplus
}
#endif
