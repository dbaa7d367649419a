"""Talks a lot on stderr (a debug print per step, as a chatty mouse does), senses a little, then fails with its last
words on stderr."""
import sys

sys.stderr.write("first words\n")
for i in range(5000):
    sys.stderr.write(f"debug line {i}: still thinking\n")
print("moveForward", flush=True)
sys.stdin.readline()
sys.stderr.write("last words\n")
sys.exit(3)
