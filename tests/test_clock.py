"""hipsim.clock: a note said once when a block outlasts its time (at its boundary too), nothing for a quick block or
without a listener, and the system clock's wait ending on its event."""

from __future__ import annotations

import threading

from fake_clock import FakeClock

from hipsim.clock import SYSTEM_CLOCK, note_if_slow


def test_a_slow_block_is_announced_once():
    clock, said = FakeClock(), list[str]()
    with note_if_slow("compiling", said.append, after_s=1.0, clock=clock):
        clock.advance(0.999)
        assert said == []
        clock.advance(0.001)  # 1.0 s: due
        clock.advance(5.0)
    assert said == ["compiling"]


def test_a_quick_block_says_nothing_even_later():
    clock, said = FakeClock(), list[str]()
    with note_if_slow("compiling", said.append, after_s=1.0, clock=clock):
        clock.advance(0.5)
    clock.advance(10.0)  # the timer was cancelled when the block ended
    assert said == []


def test_without_a_listener_no_timer_is_set():
    clock = FakeClock()
    with note_if_slow("compiling", None, clock=clock):
        clock.advance(2.0)
    assert clock.timers == []


def test_the_system_clocks_wait_ends_on_its_event():
    event = threading.Event()
    event.set()
    assert SYSTEM_CLOCK.wait(event, 10.0) is True  # returns at once: the event is set
    assert SYSTEM_CLOCK.wait(threading.Event(), 0.0) is False
    assert SYSTEM_CLOCK.monotonic() <= SYSTEM_CLOCK.monotonic()
