/*
 * What the SPIKE-RT runtime's parts share: ET Robocon's device table (raspike_device.c), guest memory access
 * by the layout header's offsets, the hub's status (status.c) and the motors' service at each snapshot. The
 * slots are those ET Robocon's SDK for Athrill reads or writes (its ev3_vdev.h addresses), and ours for what
 * the hub answers beyond them (RX SPIKE_SHSV, SPIKE_COLOR, SPIKE_MOTOR_POWER; TX SPIKE_DIRECTION).
 */
#ifndef HAKO_SPIKE_H
#define HAKO_SPIKE_H

#include <stdint.h>

#include "../../src/runtime.h"
#include "../../src/scheduler.h"
#include "spike/pup/colorsensor.h"
#include "spike/pup_device.h"

#define SPIKE_PORTS 6 /* A..F: RP_PORT_NUMBER */

/* The SDK's device kinds (raspike_device.h); the table does not check them, and neither does anything here. */
enum { DEVICE_MOTOR = 1, DEVICE_COLOR, DEVICE_ULTRASONIC, DEVICE_FORCE };

/* raspike_device.h's device, field for field: the motor calls use direction and power. */
struct _pup_device_t {
    unsigned char port_id; /* 0 = A .. 5 = F; the SDK also takes 0 as "free", so port A is never taken */
    unsigned char device_type;
    unsigned char direction; /* pup_direction_t */
    int32_t power; /* the power last set, in the program's direction */
};

/* create_device_by_portid: the port's entry, or NULL (logged, as SPIKE-RT logs it) for a port outside A..F
 * or one already taken. `caller` names the get_device call in the log. */
pup_device_t *spike_take_port(pbio_port_id_t port, unsigned char device_type, const char *caller);
pup_device_t *spike_port(int index); /* the entry of port index 0 (A) .. 5 (F) */

static inline uintptr_t spike_rx(uint32_t offset) { return (uintptr_t)HAKO_RX_GUEST_BASE + offset; }
static inline uintptr_t spike_tx(uint32_t offset) { return (uintptr_t)HAKO_TX_GUEST_BASE + offset; }
static inline uint32_t spike_read_u32(uint32_t rx_offset) { return *(volatile const uint32_t *)spike_rx(rx_offset); }
static inline void spike_write_u32(uint32_t tx_offset, uint32_t value)
{
    *(volatile uint32_t *)spike_tx(tx_offset) = value;
}

/* What one motor port reads in the hub's status (raspike.c update_port_device_motor). */
typedef struct {
    int32_t count, speed, power;
    bool stalled;
} spike_motor_reading;

/* The hub's status as the program reads it, as of the last HAKO_RASPIKE_STATUS_PERIOD_US instant (status.c). */
typedef struct {
    spike_motor_reading motors[HAKO_MOTOR_PORTS];
    pup_color_rgb_t rgb;
    int32_t reflection, ambient;
    pup_color_hsv_t hsv, ambient_hsv, color;
} spike_hub_status;

/* status.c: the status last delivered; a count reset shows in it at once, as libraspike-art clears it. */
const spike_hub_status *spike_status(void);
void spike_status_count_reset(int index);

/* The readings of a colour sensor, one of which the hub's status carries for its port at a time: libraspike-art's
 * commands (raspike_protocol_com.h), `color` for both surfaces as libraspike-art asks. */
enum spike_reading {
    READING_RGB = 1,
    READING_COLOR,
    READING_HSV,
    READING_HSV_SUR_OFF,
    READING_REFLECTION,
    READING_AMBIENT
};

/* status.c: wait, as libraspike-art does, until the status carries `reading` for the device's port. */
void spike_status_await(const pup_device_t *pdev, enum spike_reading reading);

/* motor.c: the motors' powers to zero (the hub shutting down); pbio's sampling and regulation at each
 * snapshot; a motor port's reading for the status. */
void spike_motors_off(void);
void spike_motors_serve(int64_t now);
void spike_motor_status(int index, int64_t now, spike_motor_reading *out);

#endif /* HAKO_SPIKE_H */
