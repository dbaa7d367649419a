/*
 * What the SPIKE-RT runtime's parts share: ET Robocon's device table (raspike_device.c), guest memory access
 * by the layout header's offsets, and the motors' service at each snapshot. Every slot is the one ET Robocon's
 * SDK for Athrill reads or writes (its ev3_vdev.h addresses), so a program does here what it does in the real
 * emulator running the SDK's image.
 */
#ifndef HAKO_SPIKE_H
#define HAKO_SPIKE_H

#include <stdint.h>

#include "../../src/runtime.h"
#include "../../src/scheduler.h"
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

/* motor.c: the motors' powers to zero (the hub shutting down). */
void spike_motors_off(void);

#endif /* HAKO_SPIKE_H */
