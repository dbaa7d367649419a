"""The mms-python template's Main.py, as it behaves: log to stderr, mark the start cell, then follow the left
wall for ever (the simulator ends the run)."""

import sys

import API


def log(text):
    sys.stderr.write(f"{text}\n")
    sys.stderr.flush()


def main():
    log("Running...")
    API.setColor(0, 0, "G")
    API.setText(0, 0, "abc")
    while True:
        if not API.wallLeft():
            API.turnLeft()
        while API.wallFront():
            API.turnRight()
        API.moveForward()


if __name__ == "__main__":
    main()
