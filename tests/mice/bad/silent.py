"""Asks one question, then never sends another command."""
import sys
import time

print("wallFront", flush=True)
sys.stdin.readline()
print("answered; silent from now on", file=sys.stderr, flush=True)
time.sleep(60)
