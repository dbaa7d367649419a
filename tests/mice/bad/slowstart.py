"""Starts slowly (as a JVM, or any program on a loaded CI runner, does), then talks at once and exits."""
import time

time.sleep(1.5)
print("mazeWidth", flush=True)
input()
