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
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Protocol

__all__ = ["SYSTEM_CLOCK", "Cancel", "Clock", "SystemClock", "note_if_slow"]


class Cancel(Protocol):
    """What :meth:`Clock.timer` returns: a call to come, cancelled unless it has been made."""

    def cancel(self) -> None: ...


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

    def timer(self, seconds: float, function: Callable[[], None]) -> Cancel:
        """Call ``function`` once ``seconds`` [s] have passed, unless cancelled first (in another thread)."""
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

    def timer(self, seconds: float, function: Callable[[], None]) -> Cancel:
        timer = threading.Timer(seconds, function)
        timer.daemon = True  # never keeps the process alive
        timer.start()
        return timer


#: The clock every function uses unless given another.
SYSTEM_CLOCK: Clock = SystemClock()


@contextmanager
def note_if_slow(
    message: str, notify: Callable[[str], None] | None, after_s: float = 1.0, clock: Clock | None = None
) -> Iterator[None]:
    """Call ``notify(message)`` if the block is still running ``after_s`` [s] after it starts (once, from a timer).

    What a first run's numba compilation is announced by: the note comes while the user waits, and a quick
    block (the kernels loaded from the cache) says nothing. ``notify`` None: nothing is said.
    """
    pending = None if notify is None else (clock or SYSTEM_CLOCK).timer(after_s, lambda: notify(message))
    try:
        yield
    finally:
        if pending is not None:
            pending.cancel()
