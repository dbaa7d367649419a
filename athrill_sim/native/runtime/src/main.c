/*
 * athrill-native: the Athrill process for a user's EV3RT program built for this machine. The physics
 * process starts one per test, one test ahead: it maps the files, waits until its test starts, and then
 * runs the program's kernel in lockstep with physics until it is killed, the program ends, or physics is
 * gone. Exit status: HAKO_EXIT_BENCH_FAULT when the files cannot be used, 2 for a bad command line, 0
 * otherwise; a crash in the program ends it by its signal, as it would end a real program.
 *
 * The runtime starts in a constructor that runs before the program's own (priority 101, the first a program
 * may not use): the program's objects with static storage (C++ globals, `static ev3api::Motor gLeft(PORT_C);`
 * as ET Robocon teams write them) are then constructed as on the robot, after the start-up and before the
 * first task, with this test started, the guest windows loaded and the SD card folder entered, so that what
 * their constructors read and write is this test's. glibc passes a constructor the program's arguments.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "runtime.h"

static char run_dir_path[4096];

const char *hako_run_dir(void) { return run_dir_path; }

static void usage(const char *problem)
{
    fprintf(stderr, "athrill-native: %s\nusage: athrill-native --run-dir DIR [--test N]\n", problem);
    exit(2);
}

__attribute__((constructor(101))) static void hako_start(int argc, char **argv)
{
    const char *run_dir = NULL;
    long long test = -1;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--run-dir") == 0 && i + 1 < argc) {
            run_dir = argv[++i];
        } else if (strcmp(argv[i], "--test") == 0 && i + 1 < argc) {
            char *end;
            errno = 0;
            test = strtoll(argv[++i], &end, 10);
            if (errno != 0 || *end != '\0' || test < 0 || test > UINT32_MAX)
                usage("--test takes a test number");
        } else {
            usage("unknown argument");
        }
    }
    if (run_dir == NULL)
        usage("--run-dir is required");
    setvbuf(stdout, NULL, _IOLBF, 0); /* a program's printf reaches the log a line at a time, as on EV3RT's
                                         console, even when the run is stopped with the process killed */
    if (realpath(run_dir, run_dir_path) == NULL)
        hako_bench_fault("run directory %s: %s", run_dir, strerror(errno));
    hako_files_open(run_dir_path);
    hako_window_map();
    if (test >= 0)
        hako_wait_for_test((uint32_t)test);
    hako_announce();
    hako_window_load();
    hako_kernel_start((int64_t)hako_rx_unity_time());
}

int main(void) { hako_kernel_run(); }
