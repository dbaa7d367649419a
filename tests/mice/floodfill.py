"""A floodfill mouse for the mms protocol: to the central goal the way most mice assume it, back to the start,
then exit. It marks the walls it learns with setWall and the cells it has been in with setColor / setText; after
a reset (wasReset) it acknowledges it and carries on from the start with the walls it had."""

import sys
from collections import deque

HEADINGS = "nesw"  # clockwise from north
STEP = {"n": (0, 1), "e": (1, 0), "s": (0, -1), "w": (-1, 0)}


def ask(line):
    sys.stdout.write(line + "\n")
    sys.stdout.flush()
    return sys.stdin.readline().strip()


def tell(line):
    sys.stdout.write(line + "\n")
    sys.stdout.flush()


def main():
    n = int(ask("mazeWidth"))
    walls = set()  # (x, y, d) known to be closed, both sides
    seen = set()  # (x, y, d) known either way
    x, y, h = 0, 0, 0
    centre = {(cx, cy) for cx in ((n - 1) // 2, n // 2) for cy in ((n - 1) // 2, n // 2)}

    def learn():
        for rel, query in ((0, "wallFront"), (1, "wallRight"), (3, "wallLeft")):
            d = HEADINGS[(h + rel) % 4]
            closed = ask(query) == "true"
            dx, dy = STEP[d]
            other = (x + dx, y + dy, HEADINGS[(HEADINGS.index(d) + 2) % 4])
            seen.update({(x, y, d), other})
            if closed:
                walls.update({(x, y, d), other})
                tell(f"setWall {x} {y} {d}")

    def flood(targets):
        dist = {t: 0 for t in targets}
        queue = deque(targets)
        while queue:
            cx, cy = queue.popleft()
            for d, (dx, dy) in STEP.items():
                nx, ny = cx + dx, cy + dy
                if 0 <= nx < n and 0 <= ny < n and (cx, cy, d) not in walls and (nx, ny) not in dist:
                    dist[(nx, ny)] = dist[(cx, cy)] + 1
                    queue.append((nx, ny))
        return dist

    def go(targets):
        nonlocal x, y, h
        while (x, y) not in targets:
            if ask("wasReset") == "true":  # a crash: back to the start, keeping the map (as restored from a backup)
                tell("clearAllColor")
                ask("ackReset")
                x, y, h = 0, 0, 0
                sys.stderr.write("reset: restarting from the start with the walls kept\n")
            learn()
            tell(f"setColor {x} {y} c")
            dist = flood(targets)
            tell(f"setText {x} {y} {dist.get((x, y), -1)}")
            ways = [d for d in HEADINGS if (x, y, d) not in walls and (x + STEP[d][0], y + STEP[d][1]) in dist]
            if not ways:
                sys.stderr.write(f"no way to {sorted(targets)} from ({x}, {y})\n")
                return False
            best = min(ways, key=lambda d: (dist[(x + STEP[d][0], y + STEP[d][1])], d != HEADINGS[h]))
            turn = (HEADINGS.index(best) - h) % 4
            if turn == 1:
                ask("turnRight")
            elif turn == 3:
                ask("turnLeft")
            elif turn == 2:
                ask("turnRight")
                ask("turnRight")
            h = HEADINGS.index(best)
            if ask("moveForward") != "ack":
                sys.stderr.write(f"crashed at ({x}, {y}) heading {best}\n")
                sys.exit(2)
            x, y = x + STEP[best][0], y + STEP[best][1]
        learn()
        return True

    if go(centre):
        sys.stderr.write(f"goal reached at ({x}, {y})\n")
    if go({(0, 0)}):
        sys.stderr.write("back at the start\n")


if __name__ == "__main__":
    main()
