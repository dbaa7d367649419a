"""A process under `testctl.interrupts`, for tests/cli/test_interrupts.py: it stops itself with a signal at a
chosen bad moment and says on stdout how far it got. Usage: python interrupt_child.py MOMENT SIGNAL."""

from __future__ import annotations

import gc
import os
import subprocess
import sys
import threading
import time

from testctl.interrupts import interrupts, on_stop_say, stopped_by


def spin(seconds: float) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        pass


def main(moment: str, signum: int) -> None:
    def in_gc(phase: str, info: dict) -> None:  # as distributed's gc diagnosis hooks itself in
        if phase == "start" and not sent:
            sent.append(True)
            os.kill(os.getpid(), signum)
            spin(0.1 if moment == "gc-callback" else 30)  # the signal's handler runs here, in the callback
            print("callback finished", flush=True)

    class Finalized:
        def __del__(self) -> None:
            if not sent:
                sent.append(True)
                os.kill(os.getpid(), signum)
                spin(0.1)
                print("finalizer finished", flush=True)

    sent: list[bool] = []
    with interrupts():
        on_stop_say("the hint")  # said also when the deadline ends the process before the interrupt unwinds
        try:
            if moment.startswith("gc"):
                gc.callbacks.append(in_gc)
                while True:
                    gc.collect()
                    time.sleep(0.01)  # where our own loop waits: where the interrupt is raised
            elif moment == "finalizer":
                while True:
                    Finalized()
                    time.sleep(0.01)
            elif moment == "dask-gc":  # distributed's own gc hook, the one the Ctrl-C landed in
                from distributed.gc import enable_gc_diagnosis

                enable_gc_diagnosis()
                threading.Timer(float(os.environ.get("DELAY_S", "0.1")), os.kill, (os.getpid(), signum)).start()
                while True:
                    for _ in range(200):
                        cycle: list = []
                        cycle.append(cycle)
                    gc.collect()
            elif moment == "forked-child":  # the group's signal lands in a child between fork and exec
                child = subprocess.Popen([sys.executable, "-c", "print('exec reached')"],
                                         preexec_fn=lambda: os.kill(os.getpid(), signum))
                print("child", child.wait(), flush=True)
            elif moment == "second-signal":  # the user will not wait for a slow cleanup
                try:
                    print(f"first at {time.time()}", flush=True)
                    os.kill(os.getpid(), signum)
                    time.sleep(30)
                finally:
                    os.kill(os.getpid(), signum)
                    spin(30)
            elif moment == "slow-cleanup":
                try:
                    os.kill(os.getpid(), signum)
                    time.sleep(30)
                finally:
                    print("cleaning up", flush=True)
                    time.sleep(30)  # a cluster that takes its time to close
        except KeyboardInterrupt as e:
            print("raised", flush=True)
            stopped_by(e, "the hint")


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]))
