"""Prints a line that is no mms command."""
import sys

sys.stdout.write("wallFront\n")
sys.stdout.flush()
sys.stdin.readline()
print("hello simulator", flush=True)
sys.stdin.readline()
