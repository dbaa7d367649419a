/*
 * SPIKE-RT's ultrasonic sensor, as ET Robocon's SDK reads it (raspike_ultrasonicsensor.c): the EV3 ultrasonic
 * slot, in millimetres (SPIKE-RT's unit). Nothing on the bench emits ultrasound, so `presence` is false. Its
 * lights change nothing the bench measures: each light call is a line in the log.
 */
#include "spike/pup/ultrasonicsensor.h"
#include "spike.h"

pup_device_t *pup_ultrasonic_sensor_get_device(pbio_port_id_t port)
{
    return spike_take_port(port, DEVICE_ULTRASONIC, __func__);
}

int32_t pup_ultrasonic_sensor_distance(pup_device_t *pdev)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    (void)pdev;
    return (int32_t)spike_read_u32(HAKO_RX_ULTRASONIC_MM);
}

bool pup_ultrasonic_sensor_presence(pup_device_t *pdev)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    (void)pdev;
    return false;
}

pbio_error_t pup_ultrasonic_sensor_light_set(pup_device_t *pdev, int32_t bv1, int32_t bv2, int32_t bv3, int32_t bv4)
{
    (void)pdev;
    hako_log("ultrasonic sensor: lights %d %d %d %d", (int)bv1, (int)bv2, (int)bv3, (int)bv4);
    return PBIO_SUCCESS;
}

pbio_error_t pup_ultrasonic_sensor_light_on(pup_device_t *pdev)
{
    return pup_ultrasonic_sensor_light_set(pdev, 100, 100, 100, 100);
}

pbio_error_t pup_ultrasonic_sensor_light_off(pup_device_t *pdev)
{
    return pup_ultrasonic_sensor_light_set(pdev, 0, 0, 0, 0);
}
