"""Sends commands and never reads an answer (mms would buffer the answers; a pipe fills up)."""
import sys

sys.stdout.write("moveForward\n")  # into cell (0, 1): its walls are sensed by the queries below
sys.stdout.flush()
while True:
    sys.stdout.write("wallFront\nwallLeft\nwallRight\n" * 1000)
    sys.stdout.flush()
