/*
 * EV3RT's C API, the subset the native mock provides (docs/NATIVE.md), with EV3RT's names, signatures and
 * error codes; the semantics mirror athrill_sim/ev3api.py. Functions under "Not provided" are declared with
 * EV3RT's signatures so that calling one is a link error naming it, never a silent no-op.
 */
#ifndef HAKO_EV3API_H
#define HAKO_EV3API_H

#include "kernel.h"
#include "t_syslog.h"
#include "ev3.h"

#ifndef TOPPERS_MACRO_ONLY

#include "hako_layout.h"
#include "kernel_cfg.h"

typedef enum { EV3_PORT_1 = 0, EV3_PORT_2, EV3_PORT_3, EV3_PORT_4, TNUM_SENSOR_PORT } sensor_port_t;

typedef enum {
    NONE_SENSOR = 0,
    ULTRASONIC_SENSOR,
    GYRO_SENSOR,
    TOUCH_SENSOR,
    COLOR_SENSOR,
    INFRARED_SENSOR,
    HT_NXT_ACCEL_SENSOR,
    NXT_TEMP_SENSOR,
    TNUM_SENSOR_TYPE
} sensor_type_t;

typedef enum { EV3_PORT_A = 0, EV3_PORT_B, EV3_PORT_C, EV3_PORT_D, TNUM_MOTOR_PORT } motor_port_t;

typedef enum { NONE_MOTOR = 0, MEDIUM_MOTOR, LARGE_MOTOR, UNREGULATED_MOTOR, TNUM_MOTOR_TYPE } motor_type_t;

typedef enum {
    COLOR_NONE = HAKO_COLOR_NONE,
    COLOR_BLACK = HAKO_COLOR_BLACK,
    COLOR_BLUE = HAKO_COLOR_BLUE,
    COLOR_GREEN = HAKO_COLOR_GREEN,
    COLOR_YELLOW = HAKO_COLOR_YELLOW,
    COLOR_RED = HAKO_COLOR_RED,
    COLOR_WHITE = HAKO_COLOR_WHITE,
    COLOR_BROWN = HAKO_COLOR_BROWN,
    TNUM_COLOR
} colorid_t;

typedef struct {
    uint16_t r;
    uint16_t g;
    uint16_t b;
} rgb_raw_t;

typedef enum { LED_OFF = 0, LED_RED = 1, LED_GREEN = 2, LED_ORANGE = LED_RED | LED_GREEN } ledcolor_t;

typedef enum {
    LEFT_BUTTON = 0,
    RIGHT_BUTTON,
    UP_BUTTON,
    DOWN_BUTTON,
    ENTER_BUTTON,
    BACK_BUTTON,
    TNUM_BUTTON
} button_t;

typedef enum { EV3_FONT_SMALL, EV3_FONT_MEDIUM } lcdfont_t;
typedef enum { EV3_LCD_WHITE = 0, EV3_LCD_BLACK = 1 } lcdcolor_t;

/* Sensors. */
ER ev3_sensor_config(sensor_port_t port, sensor_type_t type);
ER_UINT ev3_sensor_get_type(sensor_port_t port);
colorid_t ev3_color_sensor_get_color(sensor_port_t port);
uint8_t ev3_color_sensor_get_reflect(sensor_port_t port);
uint8_t ev3_color_sensor_get_ambient(sensor_port_t port);
void ev3_color_sensor_get_rgb_raw(sensor_port_t port, rgb_raw_t *val);
int16_t ev3_gyro_sensor_get_angle(sensor_port_t port);
int16_t ev3_gyro_sensor_get_rate(sensor_port_t port);
ER ev3_gyro_sensor_reset(sensor_port_t port);
int16_t ev3_ultrasonic_sensor_get_distance(sensor_port_t port);
bool_t ev3_touch_sensor_is_pressed(sensor_port_t port);

/* Motors. */
ER ev3_motor_config(motor_port_t port, motor_type_t type);
ER_UINT ev3_motor_get_type(motor_port_t port);
int32_t ev3_motor_get_counts(motor_port_t port);
ER ev3_motor_reset_counts(motor_port_t port);
ER ev3_motor_set_power(motor_port_t port, int power);
int ev3_motor_get_power(motor_port_t port);
ER ev3_motor_stop(motor_port_t port, bool_t brake);
ER ev3_motor_steer(motor_port_t left_motor, motor_port_t right_motor, int power, int turn_ratio);

/* LED, buttons, EV3 cyclic handlers (EV3_CRE_CYC). */
ER ev3_led_set_color(ledcolor_t color);
bool_t ev3_button_is_pressed(button_t button);
ER ev3_sta_cyc(ID ev3cycid);
ER ev3_stp_cyc(ID ev3cycid);

/* Not provided. */
bool_t ev3_ultrasonic_sensor_listen(sensor_port_t port);
int8_t ev3_infrared_sensor_get_distance(sensor_port_t port);
ER ev3_motor_rotate(motor_port_t port, int degrees, uint32_t speed_abs, bool_t blocking);
ER ev3_lcd_set_font(lcdfont_t font);
ER ev3_lcd_draw_string(const char *str, int32_t x, int32_t y);
ER ev3_lcd_fill_rect(int32_t x, int32_t y, int32_t w, int32_t h, lcdcolor_t color);
ER ev3_speaker_set_volume(uint8_t volume);
ER ev3_speaker_play_tone(uint16_t frequency, int32_t duration);
ER ev3_speaker_stop(void);
int ev3_battery_current_mA(void);
int ev3_battery_voltage_mV(void);
bool_t ev3_bluetooth_is_connected(void);

#endif /* TOPPERS_MACRO_ONLY */
#endif /* HAKO_EV3API_H */
