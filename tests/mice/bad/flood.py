"""Prints bytes without ever ending a line."""
import sys

sys.stdout.buffer.write(b"moveForward\n")
sys.stdout.flush()
sys.stdin.readline()
while True:
    sys.stdout.buffer.write(b"\x00\xff" * 4096)
    sys.stdout.flush()
