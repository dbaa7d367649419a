/* EV3RT's target definitions that app.cfg and app.h use (priorities, default stack size). */
#ifndef HAKO_EV3_H
#define HAKO_EV3_H

#include "kernel.h"

#define TPRI_EV3_CYC (TMIN_TPRI + 7)
#define TMIN_APP_TPRI (TMIN_TPRI + 8)

#ifndef STACK_SIZE
#define STACK_SIZE 4096
#endif

#define ADC_RES 4096 /* a touch sensor reads as pressed above ADC_RES / 2 */

#endif /* HAKO_EV3_H */
