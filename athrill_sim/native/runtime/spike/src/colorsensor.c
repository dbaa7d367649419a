/*
 * SPIKE-RT's colour sensor, as ET Robocon's SDK reads it (raspike_color.c): the EV3 colour slots of the first
 * sensor (RX COLOR0_*: reflection and ambient as whole words, r, g, b into 16 bits) and the SDK's HSV slots
 * (RX SPIKE_HSV_*), the `surface` flag ignored (the bench has one reading, of the lit floor). The device is
 * never looked at, so a NULL one reads as well as any.
 *
 * Where the SDK is incomplete, SPIKE-RT's (drivers/spike/pup/colorsensor.c, after Pybricks' pb_color_map.c):
 * `color` is the detectable colour nearest to the HSV reading by Pybricks' cost, and `detectable_colors`
 * chooses them. The lights change nothing the bench measures: each light call is a line in the log.
 */
#include <stddef.h>

#include "spike.h"
#include "spike/pup/colorsensor.h"

#define MAX_DETECTABLE 30 /* SPIKE-RT's CB_COLOR_MAP_SIZE */

static pup_color_hsv_t detectable[MAX_DETECTABLE] = {
    {PBIO_COLOR_HUE_RED, 100, 100},  {PBIO_COLOR_HUE_YELLOW, 100, 100}, {PBIO_COLOR_HUE_GREEN, 100, 100},
    {PBIO_COLOR_HUE_BLUE, 100, 100}, {0, 0, 100} /* white */,           {0, 0, 0} /* none */,
};
static int32_t detectable_count = 6;

pup_device_t *pup_color_sensor_get_device(pbio_port_id_t port) { return spike_take_port(port, DEVICE_COLOR, __func__); }

pup_color_rgb_t pup_color_sensor_rgb(pup_device_t *pdev)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    (void)pdev;
    return (pup_color_rgb_t){(uint16_t)spike_read_u32(HAKO_RX_COLOR0_RGB),
                             (uint16_t)spike_read_u32(HAKO_RX_COLOR0_RGB + 4),
                             (uint16_t)spike_read_u32(HAKO_RX_COLOR0_RGB + 8)};
}

static pup_color_hsv_t read_hsv(void)
{
    return (pup_color_hsv_t){(uint16_t)spike_read_u32(HAKO_RX_SPIKE_HSV_H),
                             (uint8_t)spike_read_u32(HAKO_RX_SPIKE_HSV_S),
                             (uint8_t)spike_read_u32(HAKO_RX_SPIKE_HSV_V)};
}

pup_color_hsv_t pup_color_sensor_hsv(pup_device_t *pdev, bool surface)
{
    (void)pdev, (void)surface;
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return read_hsv();
}

static int32_t distance(int32_t a, int32_t b) { return a > b ? a - b : b - a; }

/* Pybricks' cost of reading `x` as colour `c`: hue (ignored against a grey), saturation (with a penalty for a
 * pale colour) and value errors, squared and weighted 1, 5 and 2. */
static int32_t cost(const pup_color_hsv_t *x, const pup_color_hsv_t *c)
{
    int32_t hue = 0;
    if (c->s > 5 && x->s > 5) {
        hue = distance(c->h, x->h);
        if (hue > 180)
            hue = 360 - hue;
    }
    int32_t saturation = distance(x->s, c->s) + (100 - c->s) / 2;
    int32_t value = distance(x->v, c->v);
    return hue * hue + 5 * saturation * saturation + 2 * value * value;
}

pup_color_hsv_t pup_color_sensor_color(pup_device_t *pdev, bool surface)
{
    (void)pdev, (void)surface;
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    pup_color_hsv_t hsv = read_hsv();
    pup_color_hsv_t best = detectable[0];
    int32_t best_cost = INT32_MAX;
    for (int32_t i = 0; i < detectable_count; i++) {
        int32_t c = cost(&hsv, &detectable[i]);
        if (c < best_cost)
            best_cost = c, best = detectable[i];
    }
    return best;
}

int32_t pup_color_sensor_reflection(pup_device_t *pdev)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    (void)pdev;
    return (int32_t)spike_read_u32(HAKO_RX_COLOR0_REFLECT);
}

int32_t pup_color_sensor_ambient(pup_device_t *pdev)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    (void)pdev;
    return (int32_t)spike_read_u32(HAKO_RX_COLOR0_AMBIENT);
}

pbio_error_t pup_color_sensor_light_set(pup_device_t *pdev, int32_t bv1, int32_t bv2, int32_t bv3)
{
    (void)pdev;
    hako_log("colour sensor: lights %d %d %d (the bench's readings do not depend on them)", (int)bv1, (int)bv2,
             (int)bv3);
    return PBIO_SUCCESS;
}

pbio_error_t pup_color_sensor_light_on(pup_device_t *pdev) { return pup_color_sensor_light_set(pdev, 100, 100, 100); }

pbio_error_t pup_color_sensor_light_off(pup_device_t *pdev) { return pup_color_sensor_light_set(pdev, 0, 0, 0); }

/* SPIKE-RT's: 1..30 colours replace the set (NULL returned); any other size changes nothing and returns the
 * set in use. */
pup_color_hsv_t *pup_color_sensor_detectable_colors(int32_t size, pup_color_hsv_t *colors)
{
    if (size < 1 || size > MAX_DETECTABLE)
        return detectable;
    for (int32_t i = 0; i < size; i++)
        detectable[i] = colors[i];
    detectable_count = size;
    return NULL;
}
