/*
 * SPIKE-RT's colour sensor as a HackSPi program reads it through RasPike-ART (libraspike-art's
 * raspike_color.c): each call returns what the hub's last status carries (status.c), which is what SPIKE-RT's
 * colorsensor.c answers on the hub, computed by the physics process as the hub (hakoniwa/physics/spike_hub.py):
 * the 10-bit RGB and its reflection in ET Robocon's SDK slots (RX COLOR0_RGB, COLOR0_REFLECT, COLOR0_AMBIENT),
 * hsv(surface = true) in the SDK's HSV slots (RX SPIKE_HSV), hsv(surface = false) and the colour in ours (RX
 * SPIKE_SHSV, SPIKE_COLOR). `color` ignores `surface`, as libraspike-art does (it always asks the hub for
 * RP_CMD_ID_COL_COL, surface true). A reading of another kind than the last waits for the hub to switch, as
 * under libraspike-art (status.c); a NULL device reads at once, as well as any. The lights change nothing the
 * bench measures: each light call is a line in the log.
 */
#include <stddef.h>

#include "spike.h"
#include "spike/pup/colorsensor.h"

pup_device_t *pup_color_sensor_get_device(pbio_port_id_t port) { return spike_take_port(port, DEVICE_COLOR, __func__); }

/* A reading takes a call's time (sim_time.h), and waits while the hub switches to it (status.c). */
static const spike_hub_status *read_as(const pup_device_t *pdev, enum spike_reading reading)
{
    hako_spend_call();
    spike_status_await(pdev, reading);
    return spike_status();
}

pup_color_rgb_t pup_color_sensor_rgb(pup_device_t *pdev) { return read_as(pdev, READING_RGB)->rgb; }

pup_color_hsv_t pup_color_sensor_hsv(pup_device_t *pdev, bool surface)
{
    return surface ? read_as(pdev, READING_HSV)->hsv : read_as(pdev, READING_HSV_SUR_OFF)->ambient_hsv;
}

pup_color_hsv_t pup_color_sensor_color(pup_device_t *pdev, bool surface)
{
    (void)surface;
    return read_as(pdev, READING_COLOR)->color;
}

int32_t pup_color_sensor_reflection(pup_device_t *pdev) { return read_as(pdev, READING_REFLECTION)->reflection; }

int32_t pup_color_sensor_ambient(pup_device_t *pdev) { return read_as(pdev, READING_AMBIENT)->ambient; }

pbio_error_t pup_color_sensor_light_set(pup_device_t *pdev, int32_t bv1, int32_t bv2, int32_t bv3)
{
    (void)pdev;
    hako_log("colour sensor: lights %d %d %d (the bench's readings do not depend on them)", (int)bv1, (int)bv2,
             (int)bv3);
    return PBIO_SUCCESS;
}

pbio_error_t pup_color_sensor_light_on(pup_device_t *pdev) { return pup_color_sensor_light_set(pdev, 100, 100, 100); }

pbio_error_t pup_color_sensor_light_off(pup_device_t *pdev) { return pup_color_sensor_light_set(pdev, 0, 0, 0); }

/* libraspike-art's (raspike_color.c 73-84): not passed on to the hub (its code is #if 0), NULL returned;
 * the hub keeps SPIKE-RT's default detectable colours. */
pup_color_hsv_t *pup_color_sensor_detectable_colors(int32_t size, pup_color_hsv_t *colors)
{
    (void)size, (void)colors;
    hako_log("colour sensor: detectable_colors is not passed on to the hub (libraspike-art); the default set stays");
    return NULL;
}
