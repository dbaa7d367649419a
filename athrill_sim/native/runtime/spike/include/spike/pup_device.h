/* SPIKE-RT's PUP device (a sensor or motor on a hub port), opaque to programs. */
#ifndef _PUP_DEVICE_H_
#define _PUP_DEVICE_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <pbio/color.h>
#include <pbio/error.h>
#include <pbio/port.h>

struct _pup_device_t;
typedef struct _pup_device_t pup_device_t;

#ifdef __cplusplus
}
#endif
#endif /* _PUP_DEVICE_H_ */
