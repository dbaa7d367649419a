/* SPIKE-RT's ultrasonic sensor API (spike/pup/ultrasonicsensor.h); semantics in docs/NATIVE.md, "SPIKE". */
#ifndef _PUP_ULTRASONIC_SENSOR_H_
#define _PUP_ULTRASONIC_SENSOR_H_
#ifdef __cplusplus
extern "C" {
#endif
#include <stdint.h>
#include <spike/pup_device.h>

pup_device_t *pup_ultrasonic_sensor_get_device(pbio_port_id_t port);
int32_t pup_ultrasonic_sensor_distance(pup_device_t *pdev);
bool pup_ultrasonic_sensor_presence(pup_device_t *pdev);
pbio_error_t pup_ultrasonic_sensor_light_set(pup_device_t *pdev, int32_t bv1, int32_t bv2, int32_t bv3, int32_t bv4);
pbio_error_t pup_ultrasonic_sensor_light_on(pup_device_t *pdev);
pbio_error_t pup_ultrasonic_sensor_light_off(pup_device_t *pdev);

#ifdef __cplusplus
}
#endif
#endif /* _PUP_ULTRASONIC_SENSOR_H_ */
