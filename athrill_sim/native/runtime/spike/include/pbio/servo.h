/* pbio's servo, which SPIKE-RT's pup_motor_t is; opaque to programs. */
#ifndef _PBIO_SERVO_H_
#define _PBIO_SERVO_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <pbio/dcmotor.h>
#include <pbio/error.h>

struct _pbio_servo_t;
typedef struct _pbio_servo_t pbio_servo_t;

#ifdef __cplusplus
}
#endif
#endif /* _PBIO_SERVO_H_ */
