/*
 * The hub's buttons, IMU, status light, battery and power, as ET Robocon's SDK maps them onto the EV3 slots
 * (raspike_hub.c): the buttons from the EV3 button byte (LEFT, RIGHT, ENTER as CENTER, BACK as BT), the IMU
 * from its f32 words (RX SPIKE_IMU_*), the light as the SDK's whole-byte write of one LED bit. Where the SDK
 * is incomplete, SPIKE-RT's: the battery is the bench's battery slots in mV and mA (the SDK answers 50 and
 * 50), an HSV light is the named colour of the nearest hue, and shutting down ends the program.
 */
#include <stdlib.h>
#include <string.h>

#include "ev3api.h"
#include "spike.h"
#include "spike/hub/battery.h"
#include "spike/hub/button.h"
#include "spike/hub/imu.h"
#include "spike/hub/light.h"
#include "spike/hub/system.h"

uint16_t hub_battery_get_voltage(void)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return (uint16_t)spike_read_u32(HAKO_RX_BATTERY_VOLTAGE);
}

uint16_t hub_battery_get_current(void)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    return (uint16_t)spike_read_u32(HAKO_RX_BATTERY_CURRENT);
}

pbio_error_t hub_button_is_pressed(hub_button_t *pressed)
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    static const struct {
        button_t ev3;
        hub_button_t hub;
    } map[] = {{LEFT_BUTTON, HUB_BUTTON_LEFT},
               {RIGHT_BUTTON, HUB_BUTTON_RIGHT},
               {ENTER_BUTTON, HUB_BUTTON_CENTER},
               {BACK_BUTTON, HUB_BUTTON_BT}};
    uint8_t buttons = *(volatile const uint8_t *)spike_rx(HAKO_RX_BUTTONS);
    int bits = 0;
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
        if (buttons >> map[i].ev3 & 1)
            bits |= map[i].hub;
    *pressed = (hub_button_t)bits;
    return PBIO_SUCCESS;
}

pbio_error_t hub_imu_init(void) { return PBIO_SUCCESS; } /* SPIKE-RT initializes it at start-up */

bool hub_imu_is_ready(void) { return true; } /* the bench's IMU has no bias to learn at rest */

static void read_floats(uint32_t rx_offset, float out[3])
{
    for (int axis = 0; axis < 3; axis++) {
        uint32_t word = spike_read_u32(rx_offset + 4 * axis);
        memcpy(&out[axis], &word, sizeof word);
    }
}

void hub_imu_get_acceleration(float accel[3])
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    read_floats(HAKO_RX_SPIKE_IMU_ACCEL_X, accel);
}

void hub_imu_get_angular_velocity(float angv[3])
{
    hako_spend_call(); /* a device read takes time (sim_time.h) */
    read_floats(HAKO_RX_SPIKE_IMU_ANGVEL_X, angv);
}

/* The SDK's: the one LED bit of the four named colours, the byte written whole; any other colour is off. */
pbio_error_t hub_light_on_color(pbio_color_t color)
{
    uint8_t led = color == PBIO_COLOR_BLUE     ? HAKO_LED_BLUE
                  : color == PBIO_COLOR_GREEN  ? HAKO_LED_GREEN
                  : color == PBIO_COLOR_RED    ? HAKO_LED_RED
                  : color == PBIO_COLOR_YELLOW ? HAKO_LED_YELLOW
                                               : 0;
    *(volatile uint8_t *)spike_tx(HAKO_TX_LED) = led;
    return PBIO_SUCCESS;
}

pbio_error_t hub_light_off(void) { return hub_light_on_color(PBIO_COLOR_BLACK); }

/* The named colour whose hue is nearest (a grey or black, with no saturation or value, lights nothing). */
pbio_error_t hub_light_on_hsv(const pbio_color_hsv_t *hsv)
{
    static const struct {
        int hue;
        pbio_color_t color;
    } hues[] = {{PBIO_COLOR_HUE_RED, PBIO_COLOR_RED},
                {PBIO_COLOR_HUE_ORANGE, PBIO_COLOR_ORANGE},
                {PBIO_COLOR_HUE_YELLOW, PBIO_COLOR_YELLOW},
                {PBIO_COLOR_HUE_GREEN, PBIO_COLOR_GREEN},
                {PBIO_COLOR_HUE_SPRING_GREEN, PBIO_COLOR_SPRING_GREEN},
                {PBIO_COLOR_HUE_CYAN, PBIO_COLOR_CYAN},
                {PBIO_COLOR_HUE_BLUE, PBIO_COLOR_BLUE},
                {PBIO_COLOR_HUE_VIOLET, PBIO_COLOR_VIOLET},
                {PBIO_COLOR_HUE_MAGENTA, PBIO_COLOR_MAGENTA},
                {PBIO_COLOR_HUE_MODULO, PBIO_COLOR_RED}};
    if (hsv->s == 0 || hsv->v == 0)
        return hub_light_off();
    int hue = hsv->h % PBIO_COLOR_HUE_MODULO;
    size_t best = 0;
    for (size_t i = 1; i < sizeof hues / sizeof hues[0]; i++)
        if (abs(hues[i].hue - hue) < abs(hues[best].hue - hue))
            best = i;
    return hub_light_on_color(hues[best].color);
}

void hub_system_shutdown(void)
{
    hako_log("hub_system_shutdown(): the program ends");
    spike_motors_off();
    hako_kernel_exit();
}
