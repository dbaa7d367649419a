"""What an Athrill process prints, copied into `athrill.log` with a cap per process (one process per test).

A program that prints 64 KB per control loop wrote 1.1 GB in 3.7 s when the log had no cap. Each process's
output now comes through a pipe: its first half-cap of bytes goes to the log as it arrives, the last half-cap
is kept in memory, and at the end the log gets a line saying how much of the middle was left out, then the
tail, so the start-up and the last words (a traceback) both survive. The tail is also what a crashed
program's last lines are read from (`last_lines`), to show the user the program's own error. mazelog copies a
user mouse's stderr the same way (a chatty mouse wrote 200 MB).
"""

from __future__ import annotations

import io
import threading
from typing import IO, cast

LOG_CAP_BYTES = 10 * 1024 * 1024  # per process (a test's Athrill, a mouse): the head and the tail, half each
_CHUNK = 64 * 1024
DRAIN_TIMEOUT_S = 5.0  # how long a process's last output is waited for after it ended


class CappedOutput:
    """Copies one process's output pipe into `log` in a thread of its own, capped at `cap` bytes; the note on a
    cut names the log (`log_name`) and what the cap is kept for (`per`)."""

    def __init__(self, pipe: IO[bytes], log: IO[bytes], write_lock: threading.Lock, label: str,
                 cap: int = LOG_CAP_BYTES, log_name: str = "athrill.log", per: str = " per test") -> None:
        self._pipe = cast(io.BufferedReader, pipe)  # Popen's pipes are buffered: read1 returns what is there
        self._log, self._write_lock, self._label, self._cap = log, write_lock, label, cap
        self._log_name, self._per = log_name, per
        self._head_left = cap // 2  # bytes the log still takes as they come
        self._after_head = 0  # bytes that came after the head
        self._recent = bytearray()  # the last cap - cap // 2 bytes of all the output
        self._thread = threading.Thread(target=self._pump, daemon=True)
        self._thread.start()

    def _pump(self) -> None:
        try:
            while chunk := self._pipe.read1(_CHUNK):
                head = chunk[:self._head_left]
                if head:
                    self._head_left -= len(head)
                    self._write(head)
                self._after_head += len(chunk) - len(head)
                self._recent += chunk
                del self._recent[:max(0, len(self._recent) - (self._cap - self._cap // 2))]
        except (OSError, ValueError):  # the pipe was closed under us: the process is being thrown away
            pass
        finally:
            self._pipe.close()
            self._finish()

    def _finish(self) -> None:
        tail = bytes(self._recent[len(self._recent) - min(self._after_head, len(self._recent)):])
        cut = self._after_head - len(tail)
        if cut:
            self._write(f"\n[{self._log_name}: {self._label} printed {self._cap // 2 + self._after_head} bytes, "
                        f"more than the {self._cap} kept{self._per}: {cut} bytes in the middle were left out, the last "
                        f"{len(tail)} follow]\n".encode())
        if tail:
            self._write(tail)

    def _write(self, data: bytes) -> None:
        with self._write_lock:
            self._log.write(data)
            self._log.flush()

    @property
    def running(self) -> bool:
        return self._thread.is_alive()

    def join(self) -> None:
        """Wait (briefly) until the process's output has ended and is in the log."""
        self._thread.join(DRAIN_TIMEOUT_S)

    def last_lines(self, n: int) -> list[str]:
        """The process's last `n` non-empty lines, once its output has ended."""
        self.join()
        text = bytes(self._recent).decode("utf-8", errors="replace")
        return [line for line in text.splitlines() if line.strip()][-n:]
