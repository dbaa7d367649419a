"""The mms-python template's API module, as it behaves: one command per line on stdout, the answer read from
stdin for the commands that have one."""

import sys


class MouseCrashedError(Exception):
    pass


def _send(words, answer=None):
    sys.stdout.write(" ".join(str(w) for w in words) + "\n")
    sys.stdout.flush()
    if answer is None:
        return None
    reply = sys.stdin.readline().strip()
    if answer is bool:
        return reply == "true"
    return answer(reply)


def mazeWidth():
    return _send(["mazeWidth"], int)


def mazeHeight():
    return _send(["mazeHeight"], int)


def wallFront():
    return _send(["wallFront"], bool)


def wallRight():
    return _send(["wallRight"], bool)


def wallLeft():
    return _send(["wallLeft"], bool)


def moveForward():
    if _send(["moveForward"], str) == "crash":
        raise MouseCrashedError()


def turnRight():
    _send(["turnRight"], str)


def turnLeft():
    _send(["turnLeft"], str)


def setWall(x, y, direction):
    _send(["setWall", x, y, direction])


def clearWall(x, y, direction):
    _send(["clearWall", x, y, direction])


def setColor(x, y, color):
    _send(["setColor", x, y, color])


def clearColor(x, y):
    _send(["clearColor", x, y])


def clearAllColor():
    _send(["clearAllColor"])


def setText(x, y, text):
    _send(["setText", x, y, text])


def clearText(x, y):
    _send(["clearText", x, y])


def clearAllText():
    _send(["clearAllText"])


def wasReset():
    return _send(["wasReset"], bool)


def ackReset():
    _send(["ackReset"], str)
