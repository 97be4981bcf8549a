"""Work in batches on a dask cluster: a local one of worker processes, or an existing scheduler's.

``hipsim sweep`` (its variants) and ``hipsim monitor`` (its snapshots) hand
their batches to :func:`map_batches`, which yields each batch's result as it
completes. The set-up every batch needs is sent to the workers once
(``scatter``, broadcast). A local cluster keeps its scratch space (lock files,
spilled data) in a folder of this run's, removed once its worker processes
are gone, also on Ctrl-C or SIGTERM: not dask's shared
``/tmp/dask-scratch-space``, which dask leaves behind.
"""

from __future__ import annotations

import atexit
import contextlib
import logging
import shutil
import signal
import tempfile
import threading
from collections.abc import Callable, Iterator, Sequence
from typing import Any

from ..exceptions import ArgumentError, MissingDependencyError

__all__ = ["distributed_module", "map_batches"]


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
            futures = client.map(function, batches, setup=shared, pure=False)
            try:
                for future in distributed.as_completed(futures):
                    result = future.result()
                    future.release()
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
