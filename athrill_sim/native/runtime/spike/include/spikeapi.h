/*
 * ET Robocon's spikeapi.h (raspike-athrill-v850e2m, sdk/common/spikeapi/include): what a SPIKE program's app.h
 * includes. As theirs, it brings the TOPPERS API (kernel.h, t_syslog.h, t_stdlib.h), <stdio.h> and, last, the
 * kernel object IDs of app.cfg (kernel_cfg.h); the pup_* and hub_* calls come from spike/pup/... and
 * spike/hub/..., which programs include themselves. ev3.h gives app.h its priorities (TMIN_APP_TPRI).
 */
#ifndef HAKO_SPIKEAPI_H
#define HAKO_SPIKEAPI_H

#include "kernel.h"
#include "t_syslog.h"
#include "t_stdlib.h"
#include "ev3.h"

#ifndef TOPPERS_MACRO_ONLY
#include <stdio.h>
#ifdef __cplusplus
extern "C" {
#endif
#include "kernel_cfg.h"
extern void _app_init_task(intptr_t unused);
#ifdef __cplusplus
}
#endif
#endif /* TOPPERS_MACRO_ONLY */
#endif /* HAKO_SPIKEAPI_H */
