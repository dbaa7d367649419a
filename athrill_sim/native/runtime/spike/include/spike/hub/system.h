/* SPIKE-RT's hub system API (spike/hub/system.h): shutting down ends the program. */
#ifndef _HUB_SYSTEM_H_
#define _HUB_SYSTEM_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>

void hub_system_shutdown(void);

#ifdef __cplusplus
}
#endif
#endif /* _HUB_SYSTEM_H_ */
