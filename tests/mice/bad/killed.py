"""Senses a little, then dies of a signal (as a segfaulting C mouse would)."""
import os
import signal
import sys

print("moveForward", flush=True)  # into cell (0, 1), whose walls nobody knows yet
sys.stdin.readline()
for query in ("wallFront", "wallLeft", "wallRight"):
    print(query, flush=True)
    sys.stdin.readline()
os.kill(os.getpid(), signal.SIGKILL)
