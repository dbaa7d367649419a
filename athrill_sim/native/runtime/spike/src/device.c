/*
 * ET Robocon's device table (raspike_device.c): each get_device call takes its port's entry. A port outside
 * A..F, or one already taken, gives NULL, the SDK's error value and SPIKE-RT's; SPIKE-RT also logs it, and so
 * do we. As in the SDK, the table marks a taken port by its index, which for port A is 0, the mark of a free
 * entry: port A can be taken again (by any kind of device), every other port once.
 */
#include <ctype.h>
#include <stddef.h>

#include "spike.h"

static pup_device_t table[SPIKE_PORTS];

pup_device_t *spike_take_port(pbio_port_id_t port, unsigned char device_type, const char *caller)
{
    unsigned char index = (unsigned char)(port - PBIO_PORT_ID_A);
    if (index >= SPIKE_PORTS) {
        if (isprint((int)port))
            hako_log("%s(): port %c is not one of the hub's ports A..F", caller, (int)port);
        else
            hako_log("%s(): port %d is not one of the hub's ports A..F", caller, (int)port);
        return NULL;
    }
    if (table[index].port_id != 0) {
        hako_log("%s(): port %c already has a device", caller, (int)port);
        return NULL;
    }
    table[index].port_id = index;
    table[index].device_type = device_type;
    return &table[index];
}

pup_device_t *spike_port(int index) { return &table[index]; }
