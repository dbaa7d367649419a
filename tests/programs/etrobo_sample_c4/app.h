#include "ev3api.h"

#define MAIN_PRIORITY (TMIN_APP_TPRI + 1)
#define BT_PRIORITY (TMIN_APP_TPRI + 2)

#ifndef STACK_SIZE
#define STACK_SIZE 4096
#endif

#ifndef TOPPERS_MACRO_ONLY
extern void main_task(intptr_t exinf);
extern void bt_task(intptr_t exinf);
#endif
