"""A Linux program's clocks, threads and waits on the native runtime's simulated time (docs/NATIVE.md, "Linux
programs"), played against a scripted physics side: every expected time follows from the documented rules
(a clock or device read takes CALL_COST_US, a relative wait counts from its tick in whole steps, an absolute one
wakes at the first tick at or after its time), not from what the runtime printed."""

from __future__ import annotations

import os
import signal
import subprocess
import time
from pathlib import Path

import pytest

from hakoniwa.wire.timebase import CALL_COST_US, CLOCK_EPOCH_S, PHYSICS_STEP_US
from tests.helpers.native_fixtures import FakePhysics, build, finish

STEP = PHYSICS_STEP_US
CFG = """#include "app.h"
CRE_TSK(MAIN_TASK, { TA_ACT, 0, main_task, TMIN_APP_TPRI + 1, 4096, NULL });
"""
HEADER = """#define _GNU_SOURCE
#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <semaphore.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/select.h>
#include <time.h>
#include <unistd.h>
#include "ev3api.h"
#include "app.h"
static long long mono_us(void) { struct timespec t; clock_gettime(CLOCK_MONOTONIC, &t);
                                 return t.tv_sec * 1000000LL + t.tv_nsec / 1000; }
"""


def build_program(tmp_path, body: str, extra: str = "") -> Path:
    """A program whose main_task is `body`, after `extra` (its own includes and functions), built."""
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "app.h").write_text("#include \"ev3api.h\"\nvoid main_task(intptr_t exinf);\n")
    return build(folder, HEADER + extra + "void main_task(intptr_t unused) {\n" + body + "\n}\n", CFG)


def run_program(tmp_path, body: str, until_us: int, extra: str = "") -> tuple[list[int], str]:
    """Build a program whose main_task is `body`, run it in lockstep until `until_us`; its wake-ups and log."""
    exe = build_program(tmp_path, body, extra)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    wakes = bench.wakes(proc, until_us)
    return wakes, finish(proc, stdout=True)


def lines_with(log: str, prefix: str) -> list[str]:
    return [line.split(prefix, 1)[1].strip() for line in log.splitlines() if prefix in line]


def test_every_clock_reads_the_kernel_clock_each_read_taking_its_microsecond(tmp_path):
    body = r"""
    struct timespec m, r, b, c; struct timeval tv; SYSTIM s;
    get_tim(&s);
    clock_gettime(CLOCK_MONOTONIC, &m); clock_gettime(CLOCK_REALTIME, &r);
    clock_gettime(CLOCK_BOOTTIME, &b); clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &c);
    gettimeofday(&tv, NULL);
    time_t t = time(NULL);
    printf("= %lld %lld.%09ld %lld.%09ld %lld.%09ld %lld.%09ld %lld.%06ld %lld\n", (long long)s,
           (long long)m.tv_sec, m.tv_nsec, (long long)r.tv_sec, r.tv_nsec, (long long)b.tv_sec, b.tv_nsec,
           (long long)c.tv_sec, c.tv_nsec, (long long)tv.tv_sec, (long)tv.tv_usec, (long long)t);
    struct tm when; localtime_r(&t, &when);
    char text[32]; strftime(text, sizeof text, "%Y-%m-%d %H:%M:%S", &when);
    printf("= %s\n", text);
    usleep(2500);
    printf("= %lld\n", mono_us());
    slp_tsk();
    """
    wakes, log = run_program(tmp_path, body, 3 * STEP)
    c = CALL_COST_US
    first = lines_with(log, "= ")
    assert first[0].split() == [
        "0",  # get_tim at the tick reads the tick
        f"0.{c * 1000:09d}", f"{CLOCK_EPOCH_S}.{2 * c * 1000:09d}", f"0.{3 * c * 1000:09d}", f"0.{4 * c * 1000:09d}",
        f"{CLOCK_EPOCH_S}.{5 * c:06d}", f"{CLOCK_EPOCH_S}"]
    assert first[1] == "2026-01-01 00:00:00"  # TZ=UTC0 is the bench's (the test runs the process directly)
    assert wakes[0] == 3 * STEP  # 2.5 ms from tick 0, in whole steps
    assert first[2] == str(3 * STEP)  # the first read at a tick reads the tick


def test_threads_run_in_a_fixed_order_and_each_sleep_counts_from_its_tick(tmp_path):
    extra = r"""
    static void *worker(void *arg) {
        long period = (long)arg;
        for (int i = 0; i < 3; i++) {
            struct timespec d = {0, period * 1000000L};
            nanosleep(&d, NULL);
            printf("= %ld at %lld\n", period, mono_us());
        }
        return (void *)(period * 10);
    }
    """
    body = r"""
    pthread_t a, b; void *ra, *rb;
    pthread_create(&a, NULL, worker, (void *)3L);
    pthread_create(&b, NULL, worker, (void *)5L);
    pthread_join(a, &ra); pthread_join(b, &rb);
    printf("= joined %ld %ld at %lld\n", (long)ra, (long)rb, mono_us());
    slp_tsk();
    """
    wakes, log = run_program(tmp_path, body, 20 * STEP, extra)
    assert wakes[:6] == [3000, 5000, 6000, 9000, 10000, 15000]
    assert lines_with(log, "= ") == ["3 at 3000", "5 at 5000", "3 at 6000", "3 at 9000", "5 at 10000",
                                     "5 at 15000", "joined 30 50 at 15001"]


def test_a_timed_wait_on_a_condition_ends_at_the_first_tick_after_its_time_or_when_signalled(tmp_path):
    extra = r"""
    static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
    static pthread_cond_t ready = PTHREAD_COND_INITIALIZER;
    static int value;
    static void *producer(void *unused) {
        usleep(7000);
        pthread_mutex_lock(&lock); value = 42; pthread_cond_signal(&ready); pthread_mutex_unlock(&lock);
        return NULL;
    }
    """
    body = r"""
    pthread_t p;
    pthread_create(&p, NULL, producer, NULL);
    pthread_mutex_lock(&lock);
    struct timespec until; clock_gettime(CLOCK_REALTIME, &until);
    until.tv_nsec += 2500000;  /* 2.5 ms: times out at the tick of 3 ms */
    int first = pthread_cond_timedwait(&ready, &lock, &until);
    printf("= %s at %lld, value %d\n", first == ETIMEDOUT ? "timeout" : "signal", mono_us(), value);
    until.tv_sec += 1;
    int second = pthread_cond_timedwait(&ready, &lock, &until);
    printf("= %s at %lld, value %d\n", second == ETIMEDOUT ? "timeout" : "signal", mono_us(), value);
    pthread_mutex_unlock(&lock);
    pthread_join(p, NULL);
    slp_tsk();
    """
    _, log = run_program(tmp_path, body, 10 * STEP, extra)
    assert lines_with(log, "= ") == ["timeout at 3000, value 0", "signal at 7000, value 42"]


def test_a_loop_spinning_on_the_clock_moves_time_a_step_per_step_of_reads(tmp_path):
    body = r"""
    long long start = mono_us(), now, reads = 1;
    while ((now = mono_us()) < start + 2500) reads++;
    printf("= %lld after %lld reads\n", now, reads);
    slp_tsk();
    """
    wakes, log = run_program(tmp_path, body, 3 * STEP)
    assert wakes[:2] == [STEP, 2 * STEP]  # the spin is preempted at each step it spends whole
    reads_per_step = STEP // CALL_COST_US  # the read that reads 2500 ends the loop uncounted
    assert lines_with(log, "= ") == [f"2500 after {2 * reads_per_step + 500} reads"]


def test_a_sensor_poll_that_never_sleeps_advances_time_too(tmp_path):
    body = r"""
    ev3_sensor_config(EV3_PORT_1, TOUCH_SENSOR);
    while (!ev3_touch_sensor_is_pressed(EV3_PORT_1)) { }
    printf("= pressed at %lld\n", mono_us());
    slp_tsk();
    """
    exe = build_program(tmp_path, body)
    from hakoniwa.wire.protocol import Rx
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    for tick in (1, 2, 3):
        assert bench.next_wake(proc) == tick * STEP
        if tick == 3:
            bench.unity.write_i32(Rx.TOUCH0, 4095)
        bench.answer(tick * STEP)
    bench.next_wake(proc)
    assert lines_with(finish(proc, stdout=True), "= ") == [f"pressed at {3 * STEP}"]


def test_a_future_and_a_semaphore_wait_in_simulated_time(tmp_path):
    body = r"""
    sem_t s; sem_init(&s, 0, 0);
    struct timespec until; clock_gettime(CLOCK_REALTIME, &until); until.tv_nsec += 4000000;
    int r = sem_timedwait(&s, &until);
    printf("= sem %d %s at %lld\n", r, r ? strerror(errno) : "", mono_us());
    struct pollfd none; (void)none;
    poll(NULL, 0, 3);
    printf("= poll at %lld\n", mono_us());
    struct timeval tv = {0, 2000};
    select(0, NULL, NULL, NULL, &tv);
    printf("= select at %lld\n", mono_us());
    slp_tsk();
    """
    _, log = run_program(tmp_path, body, 12 * STEP)
    assert lines_with(log, "= ") == ["sem -1 Connection timed out at 4000", "poll at 7000", "select at 9000"]


def test_a_call_the_bench_does_not_cover_says_so_in_one_line_and_fails(tmp_path):
    body = r"""
    timer_t t;
    int r = timer_create(CLOCK_MONOTONIC, NULL, &t);
    printf("= timer_create %d %s\n", r, strerror(errno));
    alarm(1);
    int fd = open("/dev/video0", 0);
    printf("= open %d %s\n", fd, strerror(errno));
    slp_tsk();
    """
    _, log = run_program(tmp_path, body, STEP)
    assert lines_with(log, "= ") == ["timer_create -1 Function not implemented", "open -1 No such file or directory"]
    assert ("athrill-native: timer_create() is not covered by the bench's simulated clock and devices: it fails "
            "with ENOSYS (docs/NATIVE.md)") in log
    assert "alarm() is not covered" in log and "the alarm never fires" in log
    assert 'open("/dev/video0"): the bench has no camera: it fails with ENOENT' in log


def test_threads_that_wait_for_each_other_for_ever_are_said_to_be_deadlocked(tmp_path):
    extra = r"""
    static pthread_mutex_t m = PTHREAD_MUTEX_INITIALIZER;
    static pthread_cond_t never = PTHREAD_COND_INITIALIZER;
    static void *waiter(void *unused) { pthread_mutex_lock(&m); pthread_cond_wait(&never, &m); return NULL; }
    """
    body = "pthread_t t; pthread_create(&t, NULL, waiter, NULL); pthread_join(t, NULL);"
    exe = build_program(tmp_path, body, extra)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    from hakoniwa.wire.protocol import NEVER_WAKES
    assert bench.next_wake(proc) == NEVER_WAKES
    assert proc.wait(timeout=10) == 0
    assert "nothing is left to wake one (a deadlock)" in proc.communicate()[1]


@pytest.mark.parametrize("handler", [True, False])
def test_the_tests_end_interrupts_the_program_whose_handler_then_ends_it_in_simulated_time(tmp_path, handler):
    extra = r"""
    static volatile sig_atomic_t stop;
    static void on_interrupt(int sig) { (void)sig; stop = 1; }
    """
    body = (r"signal(SIGINT, on_interrupt);" if handler else "") + r"""
    FILE *log = fopen("loop.csv", "w");
    long n = 0;
    while (!stop) { fprintf(log, "%ld,%lld\n", n++, mono_us()); usleep(10000); }
    fprintf(log, "stopped at %lld\n", mono_us());
    fclose(log);
    """
    exe = build_program(tmp_path, body, extra)
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    bench.wakes(proc, 30 * STEP)  # the test ends while the program waits for 40 ms
    started = time.monotonic()
    proc.send_signal(signal.SIGINT)
    status = proc.wait(timeout=10)
    written = (tmp_path / "run" / "sdcard" / "loop.csv").read_text()
    if handler:
        assert status == 0 and time.monotonic() - started < 2
        assert written.endswith("stopped at 40000\n")  # its loop saw the flag at its next wake, then closed
    else:
        assert status == -signal.SIGINT and "stopped" not in written


def test_system_runs_the_command_in_the_working_folder_and_stops_it_past_its_bound(tmp_path):
    body = r"""
    int quick = system("echo hello from $(basename $PWD) > said.txt; cat said.txt");
    int slow = system("sleep 30");
    printf("= %d %d at %lld\n", WEXITSTATUS(quick), WIFSIGNALED(slow) ? WTERMSIG(slow) : -1, mono_us());
    slp_tsk();
    """
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "app.h").write_text("#include \"ev3api.h\"\nvoid main_task(intptr_t exinf);\n")
    exe = build(folder, HEADER + "#include <sys/wait.h>\nvoid main_task(intptr_t unused) {\n" + body + "\n}\n", CFG)
    bench = FakePhysics(tmp_path / "run")
    os.environ["HAKO_CHILD_BOUND_S"] = "0.5"
    try:
        started = time.monotonic()
        proc = bench.start(exe)
        bench.next_wake(proc)
        elapsed = time.monotonic() - started
    finally:
        del os.environ["HAKO_CHILD_BOUND_S"]
    log = finish(proc, stdout=True)
    assert lines_with(log, "= ") == ["0 9 at 0"]  # simulated time stood still
    assert "hello from sdcard" in log and 'system: sh -c "sleep 30"' in log
    assert '"sleep 30" ran past 0.5 s of wall time, the bench\'s bound: stopped' in log
    assert elapsed < 10
    assert subprocess.run(["pgrep", "-f", "sleep 30"], capture_output=True).returncode != 0


CXX_PROGRAM = r"""
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <future>
#include <mutex>
#include <shared_mutex>
#include <thread>
#include "ev3api.h"
#include "app.h"
using namespace std::chrono;
static long long ms() { return duration_cast<milliseconds>(steady_clock::now().time_since_epoch()).count(); }
void main_task(intptr_t unused)
{
    auto answer = std::async(std::launch::async, [] { std::this_thread::sleep_for(milliseconds(30)); return 42; });
    bool early = answer.wait_for(milliseconds(10)) == std::future_status::timeout;
    long long first = ms();
    int value = answer.get();
    std::printf("= future %s at %lld, then %d at %lld\n", early ? "pending" : "ready", first, value, ms());

    std::recursive_mutex r;
    std::shared_mutex s;
    std::condition_variable_any cv;
    bool go = false;
    std::thread reader([&] {
        std::shared_lock<std::shared_mutex> shared(s);
        std::unique_lock<std::recursive_mutex> lock(r);
        cv.wait_for(lock, seconds(1), [&] { return go; });
        std::printf("= reader saw go at %lld\n", ms());
    });
    std::this_thread::sleep_until(system_clock::now() + milliseconds(20));
    { std::lock_guard<std::recursive_mutex> a(r); std::lock_guard<std::recursive_mutex> b(r); go = true; }
    cv.notify_all();
    reader.join();
    std::unique_lock<std::shared_mutex> writer(s);
    std::printf("= joined at %lld in thread %s\n", ms(),
                std::this_thread::get_id() == reader.get_id() ? "?" : "main");
    slp_tsk();
}
"""


def test_the_cxx_standard_librarys_threads_futures_and_locks_run_on_simulated_time(tmp_path):
    folder = tmp_path / "app"
    folder.mkdir()
    (folder / "app.h").write_text("#include \"ev3api.h\"\n#ifdef __cplusplus\nextern \"C\"\n#endif\n"
                                  "void main_task(intptr_t exinf);\n")
    (folder / "Makefile.inc").write_text("SRCLANG := c++\n")
    exe = build(folder, CXX_PROGRAM, CFG, name="app.cpp")
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    bench.wakes(proc, 100 * STEP)
    assert lines_with(finish(proc, stdout=True), "= ") == [
        "future pending at 10, then 42 at 30",  # wait_for times out at 10 ms; get() waits for the thread's 30
        # the main thread's sleep_until 20 ms after 30 and a few us: libstdc++ sleeps for the difference on a
        # system_clock (relative, to the step at 50), reads the clock and sleeps again for the microseconds
        # its reads took, which end at the next step
        "reader saw go at 51",
        "joined at 51 in thread main"]


def test_a_forked_child_goes_on_alone_and_detached_and_never_reaches_the_bench(tmp_path):
    extra = r"""
    #include <sys/wait.h>
    static void *ticker(void *unused) { for (;;) { usleep(1000); printf("= ticker %lld\n", mono_us()); } }
    """
    body = r"""
    pthread_t t; pthread_create(&t, NULL, ticker, NULL);
    usleep(2500);
    pid_t child = fork();
    if (child == 0) {
        ev3_motor_config(EV3_PORT_A, LARGE_MOTOR);
        ev3_motor_set_power(EV3_PORT_A, 77);  /* never reaches the TX file */
        usleep(50000);
        printf("= child at %lld\n", mono_us());
        _exit(5);
    }
    int status; waitpid(child, &status, 0);
    printf("= parent saw %d at %lld\n", WEXITSTATUS(status), mono_us());
    slp_tsk();
    """
    exe = build_program(tmp_path, body, extra)
    from hakoniwa.wire.protocol import Tx
    bench = FakePhysics(tmp_path / "run")
    proc = bench.start(exe)
    bench.wakes(proc, 4 * STEP)
    log = finish(proc, stdout=True)
    said = lines_with(log, "= ")
    assert said[:2] == ["ticker 1000", "ticker 2000"]
    assert "child at 53000" in said  # 50 ms of its own after the fork at the tick of 3 ms, its ticker gone
    assert "parent saw 5 at 3000" in said  # the parent's clock stood still while it waited for the child
    assert bench.athrill.read_i32(Tx.MOTOR_POWER) == 0


def test_popen_hands_the_program_a_commands_output_and_a_command_what_it_wrote(tmp_path):
    body = r"""
    char line[64] = "";
    FILE *in = popen("echo from the shell; exit 3", "r");
    fgets(line, sizeof line, in);
    int status = pclose(in);
    printf("= read %s", line);
    printf("= status %d\n", WEXITSTATUS(status));
    FILE *out = popen("cat > piped.txt", "w");
    fprintf(out, "to the shell\n");
    printf("= wrote %d\n", WEXITSTATUS(pclose(out)));
    FILE *back = fopen("piped.txt", "r");
    fgets(line, sizeof line, back);
    printf("= file %s", line);
    slp_tsk();
    """
    _, log = run_program(tmp_path, body, STEP, "#include <sys/wait.h>\n")
    assert lines_with(log, "= ") == ["read from the shell", "status 3", "wrote 0", "file to the shell"]


def test_poll_looks_at_descriptors_once_a_step_until_its_timeout(tmp_path):
    body = r"""
    int p[2]; pipe(p);
    struct pollfd fd = {p[0], POLLIN, 0};
    int none = poll(&fd, 1, 5);
    printf("= %d at %lld\n", none, mono_us());
    write(p[1], "x", 1);
    int one = poll(&fd, 1, 5);
    printf("= %d at %lld\n", one, mono_us());
    slp_tsk();
    """
    _, log = run_program(tmp_path, body, 6 * STEP)
    assert lines_with(log, "= ") == ["0 at 5000", "1 at 5001"]


def test_a_network_peer_beyond_this_machine_fails_at_once_and_says_so(tmp_path):
    body = r"""
    struct addrinfo *found;
    int lookup = getaddrinfo("robot-server.example", "80", NULL, &found);
    int s = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in far = {.sin_family = AF_INET, .sin_port = htons(8080)};
    inet_pton(AF_INET, "203.0.113.7", &far.sin_addr);
    int r = connect(s, (struct sockaddr *)&far, sizeof far);
    printf("= lookup %s, connect %d %s at %lld\n", gai_strerror(lookup), r, strerror(errno), mono_us());
    slp_tsk();
    """
    extra = "#include <arpa/inet.h>\n#include <netdb.h>\n#include <sys/socket.h>\n"
    _, log = run_program(tmp_path, body, STEP, extra)
    assert lines_with(log, "= ") == [
        "lookup Temporary failure in name resolution, connect -1 Network is unreachable at 0"]
    assert 'getaddrinfo("robot-server.example"): the bench has no network' in log
    assert "connect(203.0.113.7 port 8080): the bench has no network: it fails with ENETUNREACH" in log
