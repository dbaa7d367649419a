/* SPIKE-RT's hub IMU API (spike/hub/imu.h): acceleration [mm/s^2] and angular velocity [deg/s] from the
 * SDK's RX slots. The calls after libraspike-art's are SPIKE-RT's on the hub itself (spike-rt-hub
 * drivers/include/spike/hub/imu.h), which the Basic class's libcpp/spike/IMU.h calls. */
#ifndef _HUB_IMU_H_
#define _HUB_IMU_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdbool.h>
#include <stdint.h>
#include <pbio/error.h>

pbio_error_t hub_imu_init(void);
void hub_imu_get_acceleration(float accel[3]);
void hub_imu_get_angular_velocity(float angv[3]);
/* Not provided: the bench has no temperature (a link error naming it). */
float hub_imu_get_temperature(void);

/* SPIKE-RT on the hub: ready at once (pbio waits for the hub to rest while it learns the gyro's bias; the
 * bench's IMU has none to learn). */
bool hub_imu_is_ready(void);
/* Not provided: pbio's rest detection, tilt and heading. */
bool hub_imu_is_stationary(void);
void hub_imu_set_tilt(float angle);
float hub_imu_get_heading(void);
void hub_imu_reset_heading(void);

#ifdef __cplusplus
}
#endif
#endif /* _HUB_IMU_H_ */
