"""Work in batches, in this process or on a dask cluster (a local one of worker processes, or an existing scheduler's).

``hipsim sweep`` (its variants) and ``hipsim monitor`` (its snapshots) share
this: :func:`batch_size` (about eight batches a worker, so they stay busy to
the end), :func:`run_batches` (one worker and no scheduler: the batches in
this process; else :func:`map_batches`), each batch's result yielded as it
completes, the same function on either path so the results are the same to
the last bit. The set-up every batch needs is sent to the workers once
(``scatter``, broadcast). An error a batch raises on a worker is raised here
with its type and its place (file, line, column: a :class:`~hipsim.exceptions.HipsimError`'s
attributes do not survive pickling by its message alone, so they travel beside it). A local cluster keeps its scratch space (lock files,
spilled data) in a folder of this run's, removed once its worker processes
are gone, also on Ctrl-C or SIGTERM: not dask's shared
``/tmp/dask-scratch-space``, which dask leaves behind.
"""

from __future__ import annotations

import atexit
import contextlib
import logging
import math
import shutil
import signal
import tempfile
import threading
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

from ..exceptions import ArgumentError, HipsimError, MissingDependencyError

__all__ = ["Raised", "batch_size", "distributed_module", "map_batches", "run_batches"]


def batch_size(count: int, workers: int, most: int) -> int:
    """Items per batch: about eight batches a worker (so they stay busy to the end), 1 to ``most`` items each.

    Args:
        count: items to do.
        workers: worker processes.
        most: the largest batch (a batch's cost should stay small next to the whole).
    """
    return max(1, min(most, math.ceil(count / (8 * max(workers, 1)))))


@dataclass(frozen=True)
class Raised:
    """A :class:`~hipsim.exceptions.HipsimError` as it travels from a worker: its type, arguments and attributes.

    Pickling an exception keeps its type and message but calls its constructor again with the message alone, so
    a :class:`~hipsim.exceptions.FileRowError`'s file, line and column would come back as None.
    """

    kind: type[HipsimError]
    args: tuple
    attributes: dict

    @classmethod
    def of(cls, error: HipsimError) -> Raised:
        return cls(type(error), error.args, dict(vars(error)))

    def error(self) -> HipsimError:
        """The error again: its type, message and attributes."""
        error = self.kind.__new__(self.kind)
        Exception.__init__(error, *self.args)
        vars(error).update(self.attributes)
        return error


def _guarded(batch: Any, function: Callable[..., Any], setup: Any) -> Any:
    """``function(batch, setup=setup)`` on a worker, a HipsimError returned as :class:`Raised` (raised again by the caller)."""
    try:
        return function(batch, setup=setup)
    except HipsimError as error:
        return Raised.of(error)


def run_batches(
    function: Callable[..., Any],
    batches: Sequence[Any],
    setup: Any,
    workers: int,
    scheduler: str | None,
    what: str,
) -> Iterator[Any]:
    """``function(batch, setup=setup)`` for each batch, the results as they complete: in this process for one worker
    and no scheduler (in order), else on a dask cluster (:func:`map_batches`).

    Raises:
        HipsimError: what a batch raised, with its type and attributes, wherever it ran.
    """
    if not batches:
        return
    if scheduler is None and workers == 1:
        for batch in batches:
            yield function(batch, setup=setup)
        return
    yield from map_batches(function, batches, setup, workers, scheduler, what)


def distributed_module(what: str):
    """dask.distributed, imported now.

    Args:
        what: what needs it, for the message (e.g. "hipsim sweep").

    Raises:
        MissingDependencyError: not installed (``pip install 'hipsim[sweep]'``).
    """
    try:
        import distributed
    except ImportError:
        raise MissingDependencyError("distributed", "sweep", what) from None
    return distributed


def map_batches(
    function: Callable[..., Any],
    batches: Sequence[Any],
    setup: Any,
    workers: int,
    scheduler: str | None,
    what: str,
) -> Iterator[Any]:
    """``function(batch, setup=setup)`` for each batch on a dask cluster, the results as they complete.

    Args:
        function: a module-level function the workers can import (pickled by reference).
        batches: the work, one task a batch.
        setup: what every batch needs, sent once to every worker.
        workers: worker processes of the local cluster (one thread each); ignored with ``scheduler``.
        scheduler: a running dask scheduler's address, or None for a local cluster.
        what: the command, for messages and the scratch folder's name (e.g. "hipsim sweep").

    Raises:
        MissingDependencyError: dask.distributed is not installed.
        ArgumentError: a scheduler that cannot be reached.
    """
    distributed = distributed_module(what)
    scratch = tempfile.mkdtemp(prefix=what.replace(" ", "-") + "-") if scheduler is None else None
    try:
        with contextlib.ExitStack() as stack:
            if scheduler is not None:
                try:
                    client = stack.enter_context(distributed.Client(scheduler, timeout="20s"))
                except (OSError, TimeoutError, ValueError) as error:
                    raise ArgumentError(
                        "scheduler",
                        scheduler,
                        f"the address of a running dask scheduler ({' '.join(str(error).split())})",
                    ) from None
            else:
                import dask

                stack.enter_context(
                    dask.config.set({"temporary-directory": scratch})
                )  # the scheduler and nannies read it
                # Ctrl-C or SIGTERM while the cluster starts is held until it has started and will be closed on the way
                # out: a cluster half started goes on starting nannies (and making their locks) after the clean-up.
                with _signals_held():
                    cluster = stack.enter_context(
                        distributed.LocalCluster(
                            n_workers=workers,
                            threads_per_worker=1,
                            processes=True,
                            dashboard_address=None,
                            silence_logs=logging.CRITICAL,
                            local_directory=scratch,
                        )
                    )
                    client = stack.enter_context(distributed.Client(cluster))
            shared = client.scatter(setup, broadcast=True, hash=False)
            futures = client.map(_guarded, batches, function=function, setup=shared, pure=False)
            try:
                for future in distributed.as_completed(futures):
                    result = future.result()
                    future.release()
                    if isinstance(result, Raised):
                        raise result.error()
                    yield result
            finally:
                client.cancel(futures)
    finally:
        if scratch is not None:
            _remove_scratch(scratch)


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Within the body, SIGINT and SIGTERM are noted, not acted on; the first noted is raised again on leaving it.

    Only in the main thread (where Python runs signal handlers); elsewhere the body runs as it is.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []
    previous = {signum: signal.getsignal(signum) for signum in (signal.SIGINT, signal.SIGTERM)}
    for signum in previous:
        signal.signal(signum, lambda number, frame: held.append(number))
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        if held:
            signal.raise_signal(
                held[0]
            )  # now, to the handlers in force: KeyboardInterrupt, or SystemExit under exit_on_terminate


def _remove_scratch(folder: str) -> None:
    """Remove the cluster's scratch folder once its worker processes have ended (they write their locks until then)."""
    import multiprocessing

    for child in multiprocessing.active_children():
        child.join(timeout=10.0)
    shutil.rmtree(folder, ignore_errors=True)
    # A cluster interrupted while it started may still have a worker starting, which makes its locks again: once more at exit.
    atexit.register(shutil.rmtree, folder, True)
