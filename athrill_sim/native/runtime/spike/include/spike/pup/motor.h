/*
 * SPIKE-RT's motor API (spike/pup/motor.h), with its names and signatures; what each call does on the bench
 * is ET Robocon's SDK for Athrill, or SPIKE-RT's where that SDK is incomplete (docs/NATIVE.md, "SPIKE").
 */
#ifndef _PUP_MOTOR_H_
#define _PUP_MOTOR_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <pbio/port.h>
#include <pbio/servo.h>

typedef pbio_servo_t pup_motor_t;
typedef enum {
    PUP_DIRECTION_CLOCKWISE = PBIO_DIRECTION_CLOCKWISE,
    PUP_DIRECTION_COUNTERCLOCKWISE = PBIO_DIRECTION_COUNTERCLOCKWISE,
} pup_direction_t;

pup_motor_t *pup_motor_get_device(pbio_port_id_t port);
pbio_error_t pup_motor_setup(pup_motor_t *motor, pup_direction_t positive_direction, bool reset_count);
pbio_error_t pup_motor_reset_count(pup_motor_t *motor);
int32_t pup_motor_get_count(pup_motor_t *motor);
int32_t pup_motor_get_speed(pup_motor_t *motor);
pbio_error_t pup_motor_set_speed(pup_motor_t *motor, int speed);
int32_t pup_motor_get_power(pup_motor_t *motor);
pbio_error_t pup_motor_set_power(pup_motor_t *motor, int power);
pbio_error_t pup_motor_stop(pup_motor_t *motor);
pbio_error_t pup_motor_brake(pup_motor_t *motor);
pbio_error_t pup_motor_hold(pup_motor_t *motor);
bool pup_motor_is_stalled(pup_motor_t *motor);
int32_t pup_motor_set_duty_limit(pup_motor_t *motor, int duty_limit);
void pup_motor_restore_duty_limit(pup_motor_t *motor, int old_value);

#ifdef __cplusplus
}
#endif
#endif /* _PUP_MOTOR_H_ */
