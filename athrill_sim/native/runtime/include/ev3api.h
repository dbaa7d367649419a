/*
 * EV3RT's C API with EV3RT's names, signatures, types and constants (sdk/common/ev3api/include/ev3api.h and the
 * ev3api_*.h it includes); the semantics mirror athrill_sim/mock/ev3api.py and EV3RT's sources (docs/NATIVE.md).
 * As EV3RT's does, it includes <kernel.h>, <t_syslog.h>, <t_stdlib.h> and <stdio.h> first and kernel_cfg.h
 * last, which programs rely on (FILE, fprintf, assert, act_tsk with no include of their own). Everything EV3RT
 * declares is declared here; what the bench does not provide is a link error naming it, never a silent no-op.
 */
#ifndef HAKO_EV3API_H
#define HAKO_EV3API_H

#include "kernel.h"
#include "t_syslog.h"
#include "t_stdlib.h"
#include "ev3.h"

#ifndef TOPPERS_MACRO_ONLY

#include <stdio.h>

#include "hako_layout.h"

#ifdef __cplusplus
extern "C" {
#endif
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
    uint16_t padding;
} rgb_raw_t;
typedef struct {
    int8_t heading[4];
    int8_t distance[4];
} ir_seek_t;
typedef struct {
    uint8_t channel[4];
} ir_remote_t;
#define IR_RED_UP_BUTTON 1
#define IR_RED_DOWN_BUTTON 2
#define IR_BLUE_UP_BUTTON 4
#define IR_BLUE_DOWN_BUTTON 8
#define IR_BEACON_BUTTON 16

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
#define EV3_LCD_WIDTH (178)
#define EV3_LCD_HEIGHT (128)
typedef struct {
    void *buffer;
    uint32_t filesz;
    uint32_t buffersz;
} memfile_t;
#define TMAX_FILENAME_LEN (255)
typedef struct {
    uint32_t size;
    uint16_t date;
    uint16_t time;
    bool_t is_dir;
    bool_t is_readonly;
    bool_t is_hidden;
    char name[TMAX_FILENAME_LEN + 1];
} fileinfo_t;
typedef enum { EV3_SERIAL_DEFAULT = 0, EV3_SERIAL_UART = 1, EV3_SERIAL_BT = 2 } serial_port_t;
typedef struct {
    int32_t width;
    int32_t height;
    void *data;
} image_t;
typedef void (*ISR)(intptr_t exinf);
#include "hako_notes.h"

/* Sensors (ev3api_sensor.h). */
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
bool_t ev3_ultrasonic_sensor_listen(sensor_port_t port);
bool_t ev3_touch_sensor_is_pressed(sensor_port_t port);
/* Not provided: the bench has no infrared, accelerometer or temperature sensor. */
int8_t ev3_infrared_sensor_get_distance(sensor_port_t port);
ir_seek_t ev3_infrared_sensor_seek(sensor_port_t port);
ir_remote_t ev3_infrared_sensor_get_remote(sensor_port_t port);
bool_t ht_nxt_accel_sensor_measure(sensor_port_t port, int16_t axes[3]);
bool_t nxt_temp_sensor_measure(sensor_port_t port, float *temp);

/* Motors (ev3api_motor.h). */
ER ev3_motor_config(motor_port_t port, motor_type_t type);
ER_UINT ev3_motor_get_type(motor_port_t port);
int32_t ev3_motor_get_counts(motor_port_t port);
ER ev3_motor_reset_counts(motor_port_t port);
ER ev3_motor_set_power(motor_port_t port, int power);
int ev3_motor_get_power(motor_port_t port);
ER ev3_motor_stop(motor_port_t port, bool_t brake);
ER ev3_motor_rotate(motor_port_t port, int degrees, uint32_t speed_abs, bool_t blocking);
ER ev3_motor_steer(motor_port_t left_motor, motor_port_t right_motor, int power, int turn_ratio);

/* LED, buttons (ev3api_led.h, ev3api_button.h). */
ER ev3_led_set_color(ledcolor_t color);
bool_t ev3_button_is_pressed(button_t button);
ER ev3_button_set_on_clicked(button_t button, ISR handler, intptr_t exinf);

/* LCD (ev3api_lcd.h). */
ER ev3_lcd_set_font(lcdfont_t font);
ER ev3_font_get_size(lcdfont_t font, int32_t *p_width, int32_t *p_height);
ER ev3_image_load(const memfile_t *p_memfile, image_t *p_image);
ER ev3_image_free(image_t *p_image);
ER ev3_lcd_draw_string(const char *str, int32_t x, int32_t y);
ER ev3_lcd_draw_line(int32_t x0, int32_t y0, int32_t x1, int32_t y1);
ER ev3_lcd_fill_rect(int32_t x, int32_t y, int32_t w, int32_t h, lcdcolor_t color);
ER ev3_lcd_draw_image(const image_t *p_image, int32_t x, int32_t y);

/* Files, serial, Bluetooth (ev3api_fs.h). */
ER_ID ev3_sdcard_opendir(const char *path);
ER ev3_sdcard_readdir(ID dirid, fileinfo_t *p_fileinfo);
ER ev3_sdcard_closedir(ID dirid);
ER ev3_memfile_load(const char *path, memfile_t *p_memfile);
ER ev3_memfile_free(memfile_t *p_memfile);
FILE *ev3_serial_open_file(serial_port_t port);
bool_t ev3_bluetooth_is_connected(void);

/* Speaker, battery, EV3 cyclic handlers (ev3api_speaker.h, ev3api_battery.h, ev3api_rtos.h). */
ER ev3_speaker_set_volume(uint8_t volume);
ER ev3_speaker_play_tone(uint16_t frequency, int32_t duration);
ER ev3_speaker_play_file(const memfile_t *p_memfile, int32_t duration);
ER ev3_speaker_stop(void);
int ev3_battery_current_mA(void);
int ev3_battery_voltage_mV(void);
ER ev3_sta_cyc(ID ev3cycid);
ER ev3_stp_cyc(ID ev3cycid);

extern void _app_init_task(intptr_t unused);
#ifdef __cplusplus
}
#endif
#include "kernel_cfg.h"
#endif /* TOPPERS_MACRO_ONLY */
#endif /* HAKO_EV3API_H */
