#ifdef __cplusplus
extern "C" {
#endif
#include "ev3api.h"
#ifndef TOPPERS_MACRO_ONLY
extern void main_task(intptr_t exinf);
#endif
#ifdef __cplusplus
}
#endif
