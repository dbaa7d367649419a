/*
 * The two bench files, opened and checked as hakoniwa/protocol.py's check_file does (size, magic, layout
 * version), then mapped shared. A file that cannot be used is the bench's fault, never the program's: the
 * process says why on stderr, writes the bench-fault marker (HAKO_BENCH_FAULT_MARKER + its pid, in the run
 * directory, holding the reason) and exits with HAKO_EXIT_BENCH_FAULT. The marker, not the status, is what
 * the physics process reads, since the user's program may exit with any status of its own.
 */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "real.h"
#include "runtime.h"

static uint8_t *rx_file;
static uint8_t *tx_file;
static const char *bench_run_dir; /* where the marker goes; NULL before the files are opened */

void hako_bench_fault(const char *format, ...)
{
    va_list args;
    va_start(args, format);
    hako_vline("athrill-native: bench fault: ", format, args);
    va_end(args);
    if (bench_run_dir != NULL) {
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s%d", bench_run_dir, HAKO_BENCH_FAULT_MARKER, (int)getpid());
        FILE *marker = hako_real()->fopen(path, "w");
        if (marker != NULL) {
            va_start(args, format);
            vfprintf(marker, format, args);
            va_end(args);
            fputc('\n', marker);
            fclose(marker);
        }
    }
    exit(HAKO_EXIT_BENCH_FAULT);
}

void hako_leave(const char *format, ...)
{
    va_list args;
    va_start(args, format);
    hako_vline("athrill-native: ", format, args);
    va_end(args);
    exit(0);
}

static void printable(char out[5], const uint8_t *bytes)
{
    for (int i = 0; i < 4; i++)
        out[i] = bytes[i] >= 0x20 && bytes[i] < 0x7F ? (char)bytes[i] : '?';
    out[4] = '\0';
}

static uint8_t *open_checked(const char *run_dir, const char *name, const char *magic)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", run_dir, name);
    int fd = hako_real()->open(path, O_RDWR);
    if (fd < 0)
        hako_bench_fault("%s: %s (is the physics process running?)", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0)
        hako_bench_fault("%s: %s", path, strerror(errno));
    if (st.st_size != HAKO_FILE_SIZE)
        hako_bench_fault("%s: size %lld bytes, expected %u", path, (long long)st.st_size, HAKO_FILE_SIZE);
    uint8_t *map = mmap(NULL, HAKO_FILE_SIZE, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    close(fd);
    if (map == MAP_FAILED)
        hako_bench_fault("%s: cannot map it: %s", path, strerror(errno));
    if (memcmp(map + HAKO_HDR_MAGIC, magic, 4) != 0) {
        char got[5];
        printable(got, map + HAKO_HDR_MAGIC);
        hako_bench_fault("%s: magic %s, expected %s", path, got, magic);
    }
    uint32_t version;
    memcpy(&version, map + HAKO_HDR_VERSION, sizeof version);
    if (version != HAKO_LAYOUT_VERSION)
        hako_bench_fault("%s: layout version %u, expected %u", path, version, HAKO_LAYOUT_VERSION);
    return map;
}

void hako_files_open(const char *run_dir)
{
    bench_run_dir = run_dir;
    rx_file = open_checked(run_dir, HAKO_UNITY_FILE, HAKO_UNITY_MAGIC);
    tx_file = open_checked(run_dir, HAKO_ATHRILL_FILE, HAKO_ATHRILL_MAGIC);
}

uint8_t *hako_rx_body(void) { return rx_file + HAKO_HEADER_SIZE; }

uint8_t *hako_tx_body(void) { return tx_file + HAKO_HEADER_SIZE; }

uint8_t *hako_tx_file(void) { return tx_file; }

uint8_t *hako_rx_file(void) { return rx_file; }

uint64_t hako_rx_unity_time(void)
{
    /* Acquire: the physics process writes the snapshot first and its time last. */
    return __atomic_load_n((const uint64_t *)(rx_file + HAKO_HDR_UNITY_TIME), __ATOMIC_ACQUIRE);
}

uint32_t hako_rx_u32(unsigned offset)
{
    return __atomic_load_n((const uint32_t *)(hako_rx_body() + offset), __ATOMIC_ACQUIRE);
}
