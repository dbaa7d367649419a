/* SPIKE-RT's hub battery API (spike/hub/battery.h): the bench's battery slots, in mV and mA. */
#ifndef _HUB_BATTERY_H_
#define _HUB_BATTERY_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>

uint16_t hub_battery_get_voltage(void);
uint16_t hub_battery_get_current(void);

#ifdef __cplusplus
}
#endif
#endif /* _HUB_BATTERY_H_ */
