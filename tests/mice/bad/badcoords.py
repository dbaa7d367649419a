"""Marks a cell far outside the maze, senses, then asks a question with a malformed argument."""
import sys

print("moveForward", flush=True)  # into cell (0, 1), whose walls nobody knows yet
sys.stdin.readline()

print("setColor 99 99 r", flush=True)
print("wallFront", flush=True)
sys.stdin.readline()
print("wallFront x", flush=True)
sys.stdin.readline()
