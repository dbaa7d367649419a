/* SPIKE-RT's force sensor API (spike/pup/forcesensor.h); semantics in docs/NATIVE.md, "SPIKE". */
#ifndef _PUP_FORCE_SENSOR_H_
#define _PUP_FORCE_SENSOR_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>
#include <spike/pup_device.h>

pup_device_t *pup_force_sensor_get_device(pbio_port_id_t port);
float pup_force_sensor_force(pup_device_t *pdev);
bool pup_force_sensor_pressed(pup_device_t *pdev, float force);
bool pup_force_sensor_touched(pup_device_t *pdev);
/* Not provided: the bench's force sensor is pressed or not, with no travel to measure (a link error). */
float pup_force_sensor_distance(pup_device_t *pdev);

#ifdef __cplusplus
}
#endif
#endif /* _PUP_FORCE_SENSOR_H_ */
