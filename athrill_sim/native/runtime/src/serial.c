/*
 * Athrill's serial helpers, without a serial device: readline finds no line (it returns 0 at once instead of
 * blocking as the real driver does while nothing arrives) and send drops its text. Each says so once in the
 * log, not on every call of a program that polls them every period.
 */
#include <string.h>

#include "athrill_serial_driver.h"
#include "runtime.h"

int athrill_serial_readline(DrvInt32Type channel, char *bufferp, DrvInt32Type bufflen)
{
    static int said;
    if (!said++)
        hako_log("athrill_serial_readline(%d): no serial device in the native mock; no line ever arrives",
                 (int)channel);
    if (bufflen > 0)
        bufferp[0] = '\0';
    return 0;
}

int athrill_serial_send(DrvInt32Type channel, const char *at_cmd)
{
    static int said;
    if (!said++)
        hako_log("athrill_serial_send(%d, \"%s\"): no serial device in the native mock; output dropped", (int)channel,
                 at_cmd);
    return (int)strlen(at_cmd);
}
