"""The serial ports (Bluetooth SPP, the UART, the default port) for the Python mock, as the C runtime has them
(runtime/src/serial_file.c): what the program writes goes to serial-<port>.log in the run directory; what it
reads is the scenario's [[serial]] input (serial-input.txt, which the physics process writes), each text
available from its simulated time on. A read with nothing available blocks the task in simulated time, as the
real driver blocks: until the next input is due, or for good when none is left.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import IO

from athrill_sim.mock.kernel import Kernel
from hakoniwa.wire.rundir import SERIAL_INPUT, SERIAL_LOG, SERIAL_PORTS


@dataclass(frozen=True)
class Input:
    at_us: int
    data: bytes


def parse_serial_input(text: str, port: str) -> list[Input]:
    """The inputs of one port, in file order, from serial-input.txt ("<at_us> <port> <hex bytes>" per line)."""
    inputs = []
    for line in text.splitlines():
        fields = line.split()
        if len(fields) == 3 and fields[1] == port:
            inputs.append(Input(int(fields[0]), bytes.fromhex(fields[2])))
    return inputs


class SerialFile:
    """What ev3_serial_open_file returns: EV3RT's unbuffered FILE*, with the calls a Python program makes."""

    def __init__(self, kernel: Kernel, log: IO[bytes], inputs: list[Input]) -> None:
        self._kernel = kernel
        self._log = log
        self._inputs = inputs
        self._next = 0
        self._offset = 0  # how much of the input being read is taken

    def write(self, data: str | bytes) -> int:
        raw = data.encode() if isinstance(data, str) else bytes(data)
        self._log.write(raw)
        self._log.flush()
        return len(raw)

    def read(self, size: int = 1) -> bytes:
        """Up to `size` bytes of the input being read, waiting in simulated time until one is due."""
        while True:
            while self._next < len(self._inputs) and self._offset == len(self._inputs[self._next].data):
                self._next, self._offset = self._next + 1, 0
            if self._next == len(self._inputs):
                self._kernel.sleep_forever()  # nothing will ever arrive
            due = self._inputs[self._next]
            if due.at_us > self._kernel.now_us:
                self._kernel.sleep(due.at_us - self._kernel.now_us)
                continue
            taken = due.data[self._offset:self._offset + size]
            self._offset += len(taken)
            return taken

    def readline(self) -> bytes:
        """Bytes up to and with the next newline, as fgets reads the FILE*."""
        line = b""
        while not line.endswith(b"\n"):
            line += self.read(1)
        return line


class SerialApi:
    """EV3RT's ev3_serial_open_file and ev3_bluetooth_is_connected (the Ev3Api's part that owns the ports)."""

    kernel: Kernel
    run_dir: Path
    syslog: Callable[[str], None]

    def __init__(self) -> None:
        self._ports: dict[int, SerialFile] = {}

    def ev3_serial_open_file(self, port: int) -> SerialFile | None:
        if not 0 <= port < len(SERIAL_PORTS):
            self.syslog(f"API ev3_serial_open_file() error: Invalid port id {port}.")
            return None
        if port not in self._ports:
            name = SERIAL_PORTS[port]
            source = self.run_dir / SERIAL_INPUT
            inputs = parse_serial_input(source.read_text(), name) if source.is_file() else []
            log = open(self.run_dir / SERIAL_LOG.format(port=name), "wb")
            self._ports[port] = SerialFile(self.kernel, log, inputs)
        return self._ports[port]

    def ev3_bluetooth_is_connected(self) -> bool:
        """EV3RT for Athrill answers E_OK (0, false) whatever the connection (ev3api_fs.c)."""
        return False
