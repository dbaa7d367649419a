"""Prints a line that is no mms command."""
import sys

print("moveForward", flush=True)  # into cell (0, 1), whose walls nobody knows yet
sys.stdin.readline()

sys.stdout.write("wallFront\n")
sys.stdout.flush()
sys.stdin.readline()
print("hello simulator", flush=True)
sys.stdin.readline()
