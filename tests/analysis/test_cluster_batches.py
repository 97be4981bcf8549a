"""The batch runner sweep and monitor share: batch sizes, and a worker's error raised with its type and place."""

from __future__ import annotations

import pickle
import sys

import pytest

from hipsim.analysis.cluster import Raised, _guarded, batch_size, run_batches
from hipsim.exceptions import HipsimError, PoseError


@pytest.mark.parametrize(
    ("count", "workers", "most", "size"),
    [(1000, 2, 50, 50), (100, 2, 50, 7), (3, 4, 50, 1), (0, 1, 200, 1), (1600, 1, 200, 200), (1601, 1, 200, 200)],
)
def test_about_eight_batches_a_worker_within_one_and_most(count, workers, most, size):
    # 100 items on 2 workers: ceil(100 / 16) = 7 a batch; 1000: ceil(1000/16) = 63, held at 50.
    assert batch_size(count, workers, most) == size


def _fails(batch, setup):
    raise PoseError("the platform cannot reach this pose", time=1.25, index=5, source="snap.csv", line=12)


def test_a_typed_error_keeps_its_type_and_place_through_pickling():
    # Pickled as it is, an error whose constructor takes more than its message does not come back at all.
    error = PoseError("the platform cannot reach this pose", time=1.25, index=5, source="snap.csv", line=12)
    if "dask.multiprocessing" not in sys.modules:  # its import installs tblib's exception pickling process-wide
        with pytest.raises(TypeError):
            pickle.loads(pickle.dumps(error))
    returned = pickle.loads(pickle.dumps(_guarded([1], function=_fails, setup=None)))
    assert isinstance(returned, Raised)
    again = returned.error()
    assert type(again) is PoseError and (again.time, again.index, again.line) == (1.25, 5, 12)
    assert str(again) == str(error) == "snap.csv, t = 1.25 s, line 12: the platform cannot reach this pose"


def test_in_this_process_the_batches_run_in_order_and_errors_propagate():
    assert list(run_batches(lambda batch, setup: [b * setup for b in batch], [[1, 2], [3]], 10, 1, None, "t")) == [
        [10, 20],
        [30],
    ]
    with pytest.raises(HipsimError, match="line 12"):
        list(run_batches(_fails, [[1]], None, 1, None, "t"))
