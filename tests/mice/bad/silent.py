"""Asks one question, then never sends another command."""
import sys
import time

print("wallFront", flush=True)
sys.stdin.readline()
time.sleep(60)
