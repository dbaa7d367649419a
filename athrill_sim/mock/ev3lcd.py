"""The EV3's LCD for the Python mock, written exactly as the C runtime writes it (runtime/src/lcd.c).

EV3RT on Athrill draws nothing (ev3api_lcd.c returns E_OK); every drawing call is kept, in order, as a line of
the run directory's lcd.txt stamped with the simulated time, so that the physics process draws lcd.png from
it (hakoniwa/physics/lcd.py) whichever mock ran the program. Argument checks are EV3RT's: an unknown font is
E_ID. The line format is lcd.py's, and tests/athrill/test_native_runtime.py compares the two runtimes' files.
"""

from __future__ import annotations

from pathlib import Path
from typing import IO

from athrill_sim.mock.ev3types import E_ID, E_OK, EV3_FONT_MEDIUM, EV3_FONT_SMALL, EV3_LCD_BLACK, EV3_LCD_WIDTH
from athrill_sim.mock.kernel import Kernel
from hakoniwa.wire.rundir import LCD_LOG

FONT_SIZES = {EV3_FONT_SMALL: (6, 8), EV3_FONT_MEDIUM: (10, 16)}  # EV3RT's font_w6h8 and font_w10h16


class LcdApi:
    """EV3RT's ev3_lcd_* and ev3_font_get_size (the Ev3Api's part that owns the screen)."""

    kernel: Kernel
    run_dir: Path

    def __init__(self) -> None:
        self._font = EV3_FONT_SMALL
        self._lcd_log: IO[str] | None = None

    def _draw(self, line: str) -> None:
        if self._lcd_log is None:
            self._lcd_log = open(self.run_dir / LCD_LOG, "w")
        self._lcd_log.write(f"{self.kernel.now()} {line}\n")
        self._lcd_log.flush()  # the process is killed at the test's end

    def ev3_lcd_set_font(self, font: int) -> int:
        if font not in FONT_SIZES:
            return E_ID
        self._font = font
        return E_OK

    def ev3_font_get_size(self, font: int) -> tuple[int, int, int]:
        """(ercd, width, height); on E_ID the sizes are 0 (EV3RT leaves its out-arguments alone)."""
        if font not in FONT_SIZES:
            return E_ID, 0, 0
        return (E_OK, *FONT_SIZES[font])

    def ev3_lcd_draw_string(self, text: str | None, x: int, y: int) -> int:
        """As many characters as the screen is wide can show, and line breaks would break the log's lines."""
        shown = (text or "")[:EV3_LCD_WIDTH].replace("\n", " ").replace("\r", " ")
        self._draw(f"string {self._font} {int(x)} {int(y)} {shown}")
        return E_OK

    def ev3_lcd_draw_line(self, x0: int, y0: int, x1: int, y1: int) -> int:
        self._draw(f"line {int(x0)} {int(y0)} {int(x1)} {int(y1)}")
        return E_OK

    def ev3_lcd_fill_rect(self, x: int, y: int, w: int, h: int, color: int) -> int:
        self._draw(f"fill {int(x)} {int(y)} {int(w)} {int(h)} {int(color == EV3_LCD_BLACK)}")
        return E_OK
