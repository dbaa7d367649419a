/* A look-alike of ET Robocon's HackEV sample (sample_c4 in its etrobo environment), written for the bench:
 * the same behaviour, calibration and wiring, not its code. It waits for the touch sensor on port 1 (or '1'
 * on the Bluetooth serial port), then every 4 ms steers hard left on white and hard right on black, so that it
 * runs along the line's right edge, and stops while the ultrasonic sensor sees something within 30 cm. Its
 * light values are those ET Robocon's simulator reads: white 23, black 0. */
#include "ev3api.h"
#include "app.h"
#include "etroboc_ext.h"

#define LIGHT_WHITE 23
#define LIGHT_BLACK 0
#define ALERT_CM 30
#define FORWARD 30
#define TURN 80
#define PERIOD_US (4 * 1000)

static const sensor_port_t touch = EV3_PORT_1, color = EV3_PORT_2, sonar = EV3_PORT_3;
static const motor_port_t left = EV3_PORT_C, right = EV3_PORT_B;
static FILE *bt;
static volatile int remote_start;

/* Whether something is within ALERT_CM, looked at every 40 ms as the sample does (the sensor's own pace). */
static int obstacle(void)
{
    static int ticks, seen;
    if (++ticks == 40 * 1000 / PERIOD_US) {
        int cm = ev3_ultrasonic_sensor_get_distance(sonar);
        seen = cm >= 0 && cm <= ALERT_CM;
        ticks = 0;
    }
    return seen;
}

void main_task(intptr_t unused)
{
    ev3_sensor_config(sonar, ULTRASONIC_SENSOR);
    ev3_sensor_config(color, COLOR_SENSOR);
    ev3_sensor_config(touch, TOUCH_SENSOR);
    ev3_motor_config(left, LARGE_MOTOR);
    ev3_motor_config(right, LARGE_MOTOR);
    bt = ev3_serial_open_file(EV3_SERIAL_BT);
    act_tsk(BT_TASK);
    syslog(LOG_NOTICE, "HackEV line tracer: tap the touch sensor or send '1' to start");
    while (!remote_start && !ev3_touch_sensor_is_pressed(touch))
        tslp_tsk(10 * 1000);
    ev3_motor_reset_counts(left);
    ev3_motor_reset_counts(right);
    ev3_led_set_color(LED_GREEN);
    while (!ev3_button_is_pressed(BACK_BUTTON)) {
        int power = FORWARD, turn;
        if (obstacle())
            power = turn = 0;
        else
            turn = ev3_color_sensor_get_reflect(color) >= (LIGHT_WHITE + LIGHT_BLACK) / 2 ? -TURN : TURN;
        ev3_motor_steer(left, right, power, turn);
        tslp_tsk(PERIOD_US);
    }
    ev3_motor_stop(left, false);
    ev3_motor_stop(right, false);
    ext_tsk();
}

void bt_task(intptr_t unused)
{
    for (;;) {
        int c = fgetc(bt);
        if (c == '1')
            remote_start = 1;
    }
}
