/*
 * The hub's status as RasPike-ART delivers it: every HAKO_RASPIKE_STATUS_PERIOD_US (raspike.cfg 11) the hub
 * sends each port's readings (raspike.c, notify_status and update_port_devices), and libraspike-art's getters
 * return the last status received (raspike_internal.h, GET_AND_RET_SENSOR_COMMON and DELAYED_SENSOR_COMMON).
 * Here the status is taken at each multiple of that period, from that instant's snapshot: what SPIKE-RT's
 * drivers answer, which the physics process computes as the hub (hakoniwa/physics/spike_hub.py), and the speed
 * and stall that pbio measures (motor.c). The kernel wakes at every such instant while the program will run again.
 */
#include "../../src/devices.h"
#include "spike.h"

#define MOTORS ((int)HAKO_MOTOR_PORTS)

static spike_hub_status status;
static int64_t next_status; /* the next instant a status comes */
static enum spike_reading carried[SPIKE_PORTS]; /* what the status carries for each colour port (0: none yet) */

const spike_hub_status *spike_status(void) { return &status; }

void spike_status_count_reset(int index)
{
    if (index < MOTORS)
        status.motors[index].count = 0;
}

static pup_color_hsv_t read_hsv(uint32_t offset)
{
    return (pup_color_hsv_t){(uint16_t)spike_read_u32(offset), (uint8_t)spike_read_u32(offset + 4),
                             (uint8_t)spike_read_u32(offset + 8)};
}

static void take_status(int64_t now)
{
    for (int i = 0; i < MOTORS; i++)
        spike_motor_status(i, now, &status.motors[i]);
    status.rgb = (pup_color_rgb_t){(uint16_t)spike_read_u32(HAKO_RX_COLOR0_RGB),
                                   (uint16_t)spike_read_u32(HAKO_RX_COLOR0_RGB + 4),
                                   (uint16_t)spike_read_u32(HAKO_RX_COLOR0_RGB + 8)};
    status.reflection = (int32_t)spike_read_u32(HAKO_RX_COLOR0_REFLECT);
    status.ambient = (int32_t)spike_read_u32(HAKO_RX_COLOR0_AMBIENT);
    status.hsv = read_hsv(HAKO_RX_SPIKE_HSV);
    status.ambient_hsv = read_hsv(HAKO_RX_SPIKE_SHSV);
    status.color = read_hsv(HAKO_RX_SPIKE_COLOR);
}

/* At each snapshot, before any task runs at that instant (the kernel's device hook): pbio's work, then a
 * status if one is due. */
static void serve_hub(void)
{
    int64_t now = hako_tick();
    spike_motors_serve(now);
    if (now >= next_status) {
        take_status(now);
        next_status = (now / HAKO_RASPIKE_STATUS_PERIOD_US + 1) * HAKO_RASPIKE_STATUS_PERIOD_US;
    }
}

/* libraspike-art reads a colour sensor from the status (DELAYED_SENSOR_COMMON, raspike_internal.h 47-52), and one
 * of another reading than the status carries it asks the hub for (raspike_port_com_change_if_needed,
 * raspike_protocol.c 401-414): after the handshake its commands are buffered (176) until the next status comes
 * in (333), the hub takes the new reading up at its following status (raspike.c 325-330), and the call waits
 * for that one: 10 to 20 ms. After the sensor is set up the status carries none (the hub's port cmd is 0), so
 * the first reading waits too. Where no task runs (a handler) the call cannot wait, and reads at once. */
void spike_status_await(const pup_device_t *pdev, enum spike_reading reading)
{
    if (pdev == NULL || pdev->port_id >= SPIKE_PORTS || carried[pdev->port_id] == reading)
        return;
    hako_block_on(&carried[pdev->port_id], next_status + HAKO_RASPIKE_STATUS_PERIOD_US);
    carried[pdev->port_id] = reading;
}

/* The next status: a wake only while the program will run again. */
static int64_t status_next_due(int64_t now_us)
{
    (void)now_us;
    return next_status;
}

HAKO_DEVICE(hub_device) = {.serve = serve_hub, .next_due = status_next_due, .passive = true};
