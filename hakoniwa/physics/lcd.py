"""The EV3's screen at the end of a test, drawn from what the program drew.

The native runtime keeps every LCD call of the test in the run directory's lcd.txt, in order (`<time_us>
string <font> <x> <y> <text>`, `line x0 y0 x1 y1`, `fill x y w h <1 black | 0 white>`, `image x y w h`),
because its process is killed at the test's end and could not write a picture then. The physics process
replays them here into a 178x128 PNG. Text is drawn with Pillow's built-in bitmap font, one character per
cell of EV3RT's font size (6x8 small, 10x16 medium): where the text is, not EV3RT's glyphs.
"""

from __future__ import annotations

from pathlib import Path

from hakoniwa.wire.rundir import LCD_LOG, LCD_PNG

WIDTH, HEIGHT = 178, 128
FONT_CELLS = ((6, 8), (10, 16))  # EV3_FONT_SMALL, EV3_FONT_MEDIUM


def draw_screen(run_dir: Path) -> Path | None:
    """Write lcd.png from lcd.txt; None when the program drew nothing."""
    log = Path(run_dir) / LCD_LOG
    if not log.is_file():
        return None
    from PIL import Image, ImageDraw, ImageFont

    image = Image.new("1", (WIDTH, HEIGHT), 1)
    pen = ImageDraw.Draw(image)
    font = ImageFont.load_default()
    for line in log.read_text(errors="replace").splitlines():
        parts = line.split(" ", 6)
        if len(parts) < 2:
            continue
        kind, args = parts[1], parts[2:]
        try:
            if kind == "string" and len(args) >= 3:
                width, height = FONT_CELLS[int(args[0]) == 1]
                x, y = int(args[1]), int(args[2])
                text = line.split(" ", 5)[5] if len(line.split(" ", 5)) > 5 else ""
                for i, ch in enumerate(text):
                    pen.text((x + i * width, y + (height - 11) // 2), ch, fill=0, font=font)
            elif kind == "line":
                x0, y0, x1, y1 = map(int, args[:4])
                pen.line((x0, y0, x1, y1), fill=0)
            elif kind == "fill":
                x, y, w, h, black = map(int, args[:5])
                if w > 0 and h > 0:
                    pen.rectangle((x, y, x + w - 1, y + h - 1), fill=0 if black else 1)
        except ValueError:
            continue  # a line cut short by the process being killed mid-write
    out = Path(run_dir) / LCD_PNG
    image.save(out)
    return out


def forget_screen(run_dir: Path) -> None:
    """A new test starts with a blank screen: the last test's drawing goes."""
    for name in (LCD_LOG, LCD_PNG):
        (Path(run_dir) / name).unlink(missing_ok=True)
