/*
 * ev3_serial_open_file: the serial ports (Bluetooth SPP, the UART, the default port) as a FILE*, unbuffered
 * as EV3RT makes it. What the program writes goes to serial-<port>.log in the run directory; what it reads is
 * the scenario's [[serial]] input (serial-input.txt, written by the physics process: "<at_us> <port> <hex>"
 * per line), each text available from its simulated time on. A read with nothing available blocks the task
 * in simulated time, as the real driver blocks: until the next input is due, or for good when none is left.
 */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ev3api.h"
#include "real.h"
#include "runtime.h"

struct input {
    int64_t at_us;
    char *bytes;
    size_t size;
};

struct port {
    FILE *file;
    FILE *log;
    struct input *inputs;
    size_t count, next, offset; /* the input being read, and how much of it is taken */
};

static const char *const port_names[] = {HAKO_SERIAL_PORT_NAMES};
#define SERIAL_PORTS ((int)(sizeof port_names / sizeof port_names[0]))
static struct port ports[SERIAL_PORTS];

static int hex_digit(int c) { return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1; }

static void load_inputs(struct port *p, int which)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", hako_run_dir(), HAKO_SERIAL_INPUT);
    FILE *f = hako_real()->fopen(path, "r");
    if (f == NULL)
        return;
    long long at;
    char name[16];
    char hex[8192];
    while (fscanf(f, "%lld %15s %8191s", &at, name, hex) == 3) {
        if (strcmp(name, port_names[which]) != 0)
            continue;
        struct input *grown = realloc(p->inputs, (p->count + 1) * sizeof *grown);
        size_t n = strlen(hex) / 2;
        char *bytes = malloc(n + 1);
        if (grown == NULL || bytes == NULL)
            hako_bench_fault("no memory for the serial input");
        p->inputs = grown;
        for (size_t i = 0; i < n; i++)
            bytes[i] = (char)(hex_digit(hex[2 * i]) * 16 + hex_digit(hex[2 * i + 1]));
        p->inputs[p->count++] = (struct input){at, bytes, n};
    }
    fclose(f);
}

static ssize_t port_read(void *cookie, char *buf, size_t size)
{
    struct port *p = cookie;
    for (;;) {
        while (p->next < p->count && p->offset == p->inputs[p->next].size) {
            p->next++;
            p->offset = 0;
        }
        if (p->next == p->count) {
            if (slp_tsk() != E_OK) /* nothing will ever arrive: blocked until the task is terminated */
                return 0;
            continue;
        }
        const struct input *in = &p->inputs[p->next];
        if (in->at_us > hako_now()) {
            if (dly_tsk((RELTIM)(in->at_us - hako_now())) != E_OK)
                return 0; /* not in a task (a handler cannot block): nothing yet */
            continue;
        }
        size_t n = in->size - p->offset < size ? in->size - p->offset : size;
        memcpy(buf, in->bytes + p->offset, n);
        p->offset += n;
        return (ssize_t)n;
    }
}

static ssize_t port_write(void *cookie, const char *buf, size_t size)
{
    struct port *p = cookie;
    if (p->log != NULL) {
        fwrite(buf, 1, size, p->log);
        fflush(p->log);
    }
    return (ssize_t)size;
}

FILE *ev3_serial_open_file(serial_port_t port)
{
    if ((int)port < 0 || (int)port >= SERIAL_PORTS) {
        hako_log("API %s() error: Invalid port id %d.", __func__, (int)port); /* API_ERROR */
        return NULL;
    }
    struct port *p = &ports[port];
    if (p->file != NULL)
        return p->file;
    char path[4096], name[64];
    snprintf(name, sizeof name, HAKO_SERIAL_LOG, port_names[port]);
    snprintf(path, sizeof path, "%s/%s", hako_run_dir(), name);
    p->log = hako_real()->fopen(path, "w");
    load_inputs(p, (int)port);
    p->file = fopencookie(p, "r+", (cookie_io_functions_t){.read = port_read, .write = port_write});
    if (p->file != NULL)
        setbuf(p->file, NULL); /* as EV3RT does */
    return p->file;
}

/* EV3RT for Athrill answers E_OK (0, false) here whatever the connection (ev3api_fs.c). */
bool_t ev3_bluetooth_is_connected(void) { return E_OK; }
