/*
 * The Pi's side of RasPike-ART, as asp runs it, without the kernel: libraspike-art (compiled natively with
 * this file) opens the serial port, shakes hands, and a thread receives the hub's frames, as RasPike-ART's
 * vdev_com_usb.c and vdev_prot_raspike_art.c do. Then it asks what sample_c5_spike and teams' programs ask,
 * and prints what libraspike-art answers, one "name value..." line each, for tests/physics/test_raspike_hub.py.
 */
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <unistd.h>

#include "raspike_com.h"
#include "raspike_protocol_api.h"
#include "spike/hub/battery.h"
#include "spike/hub/button.h"
#include "spike/hub/imu.h"
#include "spike/pup/colorsensor.h"
#include "spike/pup/forcesensor.h"
#include "spike/pup/motor.h"

static void *receive(void *unused)
{
    (void)unused;
    for (;;)
        raspike_prot_receive();
    return NULL;
}

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    RPComDescriptor *desc = raspike_open_usb_communication(argv[1]);
    if (desc == NULL)
        return 3;
    raspike_prot_init(desc);
    pthread_t thread;
    pthread_create(&thread, NULL, receive, NULL);

    pup_device_t *force = pup_force_sensor_get_device(PBIO_PORT_ID_D);
    pup_motor_t *left = pup_motor_get_device(PBIO_PORT_ID_B);
    pup_motor_t *right = pup_motor_get_device(PBIO_PORT_ID_A);
    pup_device_t *color = pup_color_sensor_get_device(PBIO_PORT_ID_E);
    pup_motor_t *nothing = pup_motor_get_device(PBIO_PORT_ID_C);
    printf("devices %d %d %d %d %d\n", force != NULL, left != NULL, right != NULL, color != NULL, nothing != NULL);
    printf("setup %d %d\n", pup_motor_setup(left, PUP_DIRECTION_COUNTERCLOCKWISE, true),
           pup_motor_setup(right, PUP_DIRECTION_CLOCKWISE, true));
    pup_motor_set_power(left, 50);
    pup_motor_set_power(right, -30);
    usleep(300000); /* 30 statuses: long enough to stall (200 ms) */
    printf("count %d %d\n", pup_motor_get_count(left), pup_motor_get_count(right));
    printf("speed %d %d\n", pup_motor_get_speed(left), pup_motor_get_speed(right));
    printf("stalled %d %d\n", pup_motor_is_stalled(left), pup_motor_is_stalled(right));
    printf("reflection %d\n", pup_color_sensor_reflection(color));
    pup_color_rgb_t rgb = pup_color_sensor_rgb(color);
    printf("rgb %d %d %d\n", rgb.r, rgb.g, rgb.b);
    pup_color_hsv_t hsv = pup_color_sensor_hsv(color, true);
    printf("hsv %d %d %d\n", hsv.h, hsv.s, hsv.v);
    pup_color_hsv_t col = pup_color_sensor_color(color, true);
    printf("color %d %d %d\n", col.h, col.s, col.v);
    printf("force %.1f %.1f %d\n", pup_force_sensor_force(force), pup_force_sensor_distance(force),
           pup_force_sensor_touched(force));
    float accel[3], angv[3];
    hub_imu_get_acceleration(accel);
    hub_imu_get_angular_velocity(angv);
    printf("imu %.1f %.1f %.1f %.1f %.1f %.1f\n", accel[0], accel[1], accel[2], angv[0], angv[1], angv[2]);
    hub_button_t buttons;
    hub_button_is_pressed(&buttons);
    printf("hub %d %d %d\n", hub_battery_get_voltage(), hub_battery_get_current(), (int)buttons);
    printf("reset %d\n", pup_motor_reset_count(left));
    usleep(30000);
    printf("after_reset %d\n", pup_motor_get_count(left));
    printf("stop %d\n", pup_motor_stop(right));
    fflush(stdout);
    return 0;
}
