"""Senses a little, then fails with exit status 3."""
import sys

print("moveForward", flush=True)  # into cell (0, 1), whose walls nobody knows yet
sys.stdin.readline()

for query in ("wallFront", "wallLeft", "wallRight"):
    print(query, flush=True)
    sys.stdin.readline()
sys.stderr.write("my mouse: out of memory\n")
sys.exit(3)
