/* SPIKE-RT's hub IMU API (spike/hub/imu.h): acceleration [mm/s^2] and angular velocity [deg/s] from the
 * SDK's RX slots. */
#ifndef _HUB_IMU_H_
#define _HUB_IMU_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>
#include <pbio/error.h>

pbio_error_t hub_imu_init(void);
void hub_imu_get_acceleration(float accel[3]);
void hub_imu_get_angular_velocity(float angv[3]);
/* Not provided: the bench has no temperature (a link error naming it). */
float hub_imu_get_temperature(void);

#ifdef __cplusplus
}
#endif
#endif /* _HUB_IMU_H_ */
