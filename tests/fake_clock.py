"""A clock for tests (:class:`hipsim.clock.Clock`): time moves only when the code under test sleeps or waits.

What a test checks then does not depend on the machine's speed or load: a
sleep or a wait advances the time at once, and a wait first runs the test's
next step (``steps``), so that a loop that polls sees the world change between
its rounds exactly as the test scripts it. A timer fires, in the caller's
thread, when the time it waits for is passed.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable


class FakeClock:
    """Monotonic and wall time that start at ``start`` [s] and move by what is slept and waited.

    Args:
        start: the wall time at the start in [s] (the monotonic time starts at 0).
        steps: called one at a time, each at a :meth:`wait`, with the clock; when they are done, ``done``
            (called at each later wait) says when to set the event and end the waiting loop.
    """

    def __init__(
        self,
        start: float = 1.0e9,
        steps: Iterable[Callable[[FakeClock], None]] = (),
        done: Callable[[], bool] = lambda: True,
    ) -> None:
        self.elapsed = 0.0
        self.start = start
        self.steps = list(steps)
        self.done = done
        self.waits = 0
        self.timers: list[_Timer] = []

    def monotonic(self) -> float:
        return self.elapsed

    def time(self) -> float:
        return self.start + self.elapsed

    def sleep(self, seconds: float) -> None:
        assert seconds >= 0.0, seconds
        self.advance(seconds)

    def advance(self, seconds: float) -> None:
        """Time that passes in the code under test's calls (a slow frame), not in a sleep; due timers fire."""
        self.elapsed += seconds
        for timer in [t for t in self.timers if t.due <= self.elapsed and not t.cancelled]:
            timer.cancelled = True
            timer.function()

    def timer(self, seconds: float, function: Callable[[], None]) -> _Timer:
        timer = _Timer(self.elapsed + seconds, function)
        self.timers.append(timer)
        return timer

    def wait(self, event: threading.Event, seconds: float) -> bool:
        self.waits += 1
        self.advance(seconds)
        if self.steps:
            self.steps.pop(0)(self)
        elif self.done():
            event.set()
        return event.is_set()


class _Timer:
    """A call due at a time of a :class:`FakeClock`."""

    def __init__(self, due: float, function: Callable[[], None]) -> None:
        self.due, self.function, self.cancelled = due, function, False

    def cancel(self) -> None:
        self.cancelled = True
