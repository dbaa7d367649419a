/*
 * SPIKE-RT's force sensor, as ET Robocon's SDK reads it (raspike_forcesensor.c): the EV3's first touch slot
 * (RX TOUCH0, whatever port the sensor is on). Its force is the slot's value (the SDK's scaling: the bench
 * writes 4095 while pressed), touched is a value above 0. Where the SDK is incomplete, SPIKE-RT's: `pressed`
 * is touched with at least `force`. The device is never looked at.
 */
#include "spike/pup/forcesensor.h"
#include "spike.h"

pup_device_t *pup_force_sensor_get_device(pbio_port_id_t port) { return spike_take_port(port, DEVICE_FORCE, __func__); }

float pup_force_sensor_force(pup_device_t *pdev)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    (void)pdev;
    return (float)spike_read_u32(HAKO_RX_TOUCH0);
}

bool pup_force_sensor_touched(pup_device_t *pdev)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    (void)pdev;
    return spike_read_u32(HAKO_RX_TOUCH0) > 0;
}

bool pup_force_sensor_pressed(pup_device_t *pdev, float force)
{
    (void)pdev;
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    uint32_t value = spike_read_u32(HAKO_RX_TOUCH0);
    return value > 0 && (float)value >= force;
}
