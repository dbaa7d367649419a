"""The brick's other devices for the Python mock, as the C runtime has them (runtime/src/brick.c): button click
handlers, the speaker (each call a line in the log; there is no sound) and the battery.

A click is EV3RT's (brick_dri.c, brick_button_cyc): a button that was down and is now up. Its handler runs at
the first snapshot that shows it up, before the task goes on, as the C runtime's kernel runs it before any
task. The battery is read from its RX slots, as uart_dri_get_data_battery reads it.
"""

from __future__ import annotations

from collections.abc import Callable

from athrill_sim.mock.bus import MemoryBus
from athrill_sim.mock.ev3types import BACK_BUTTON, E_ID, E_OK, E_PAR, LEFT_BUTTON, TNUM_BUTTON, MemFile
from athrill_sim.mock.kernel import Kernel
from hakoniwa.wire.protocol import RX_GUEST_BASE, Rx


class BrickApi:
    """EV3RT's ev3_button_set_on_clicked, ev3_speaker_* and ev3_battery_* (the Ev3Api's part that owns them)."""

    bus: MemoryBus
    kernel: Kernel
    syslog: Callable[[str], None]

    def __init__(self) -> None:
        self._handlers: list[tuple[Callable[[int], None], int] | None] = [None] * TNUM_BUTTON
        self._buttons_before = self._buttons()
        self.kernel.on_snapshot.append(self._call_click_handlers)
        self.kernel.watch_buttons = lambda: any(h is not None for h in self._handlers)

    def _buttons(self) -> int:
        return int(self.bus.read("I", RX_GUEST_BASE + Rx.BUTTONS))

    def _call_click_handlers(self) -> None:
        now = self._buttons()
        released, self._buttons_before = self._buttons_before & ~now, now
        for button, handler in enumerate(self._handlers):
            if released >> button & 1 and handler is not None:
                handler[0](handler[1])

    def ev3_button_set_on_clicked(self, button: int, handler: Callable[[int], None] | None, exinf: int = 0) -> int:
        if not LEFT_BUTTON <= button <= BACK_BUTTON:
            return E_ID
        self._handlers[button] = None if handler is None else (handler, exinf)
        return E_OK

    def ev3_speaker_set_volume(self, volume: int) -> int:
        self.syslog(f"speaker: volume {volume & 0xFF}")  # uint8_t
        return E_OK

    def ev3_speaker_play_tone(self, frequency: int, duration: int) -> int:
        self.syslog(f"speaker: tone {int(frequency) & 0xFFFF} Hz for {int(duration)} ms")  # uint16_t, int32_t
        return E_OK

    def ev3_speaker_play_file(self, memfile: MemFile | None, duration: int) -> int:
        if memfile is None or memfile.buffer is None:
            return E_PAR
        self.syslog(f"speaker: {memfile.filesz}-byte file for {int(duration)} ms")
        return E_OK

    def ev3_speaker_stop(self) -> int:
        self.syslog("speaker: stop")
        return E_OK

    def ev3_battery_current_mA(self) -> int:
        self.kernel.spend_call()  # a device read takes its time
        return int(self.bus.read("i", RX_GUEST_BASE + Rx.BATTERY_CURRENT))

    def ev3_battery_voltage_mV(self) -> int:
        self.kernel.spend_call()  # a device read takes its time
        return int(self.bus.read("i", RX_GUEST_BASE + Rx.BATTERY_VOLTAGE))
