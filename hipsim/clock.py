"""Time as the library reads it: the system's clocks, or a clock a test injects.

The code that paces or ages things (the live viewer playing in real time, the
monitor's watch polling a folder and waiting for files to settle) takes a
:class:`Clock` argument whose default is :data:`SYSTEM_CLOCK`. A test passes its
own, which moves time only when asked to, so that what it checks does not
depend on how fast or busy the machine is.
"""

from __future__ import annotations

import threading
import time
from typing import Protocol

__all__ = ["SYSTEM_CLOCK", "Clock", "SystemClock"]


class Clock(Protocol):
    """The four ways the library reads or spends time."""

    def monotonic(self) -> float:
        """Seconds from an arbitrary start, never going back: for intervals, in [s]."""
        ...

    def time(self) -> float:
        """Seconds since the Unix epoch, in [s]: the time files are stamped with (``st_mtime``)."""
        ...

    def sleep(self, seconds: float) -> None:
        """Wait ``seconds`` [s]."""
        ...

    def wait(self, event: threading.Event, seconds: float) -> bool:
        """Wait ``seconds`` [s] or until ``event`` is set, whichever comes first; whether it is set."""
        ...


class SystemClock:
    """The system's clocks: :func:`time.monotonic`, :func:`time.time`, :func:`time.sleep` and :meth:`threading.Event.wait`."""

    def monotonic(self) -> float:
        return time.monotonic()

    def time(self) -> float:
        return time.time()

    def sleep(self, seconds: float) -> None:
        time.sleep(seconds)

    def wait(self, event: threading.Event, seconds: float) -> bool:
        return event.wait(seconds)


#: The clock every function uses unless given another.
SYSTEM_CLOCK: Clock = SystemClock()
