/*
 * Athrill's serial FIFO helpers. The native mock has no serial device: readline finds no line and send
 * drops its text (each says so once in the log). The others are declared so that a call is a link error.
 */
#ifndef HAKO_ATHRILL_SERIAL_DRIVER_H
#define HAKO_ATHRILL_SERIAL_DRIVER_H

#include <stdint.h>

typedef int32_t DrvInt32Type;
typedef uint32_t DrvUint32Type;
typedef uint8_t DrvUint8Type;

#ifdef __cplusplus
extern "C" {
#endif
int athrill_serial_readline(DrvInt32Type channel, char *bufferp, DrvInt32Type bufflen);
int athrill_serial_send(DrvInt32Type channel, const char *at_cmd);

/* Not provided. */
int athrill_serial_init(DrvInt32Type channel, DrvUint32Type baud);
int athrill_serial_send_data(DrvInt32Type channel, const char *datap, DrvInt32Type datalen);
int athrill_serial_read_data(DrvInt32Type channel, char *bufferp, DrvInt32Type bufflen);
#ifdef __cplusplus
}
#endif

#endif /* HAKO_ATHRILL_SERIAL_DRIVER_H */
