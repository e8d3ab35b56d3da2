"""The threads' work sharing inside a rank (fortran/src/work_queues.f90, docs/theory.md).

Each thread starts on the contiguous range schedule(static) would give it, then takes what is
left of the others' ranges. Whatever the timing, every item must be handed out exactly once.
"""

from __future__ import annotations

import numpy as np
import pytest

from paradyn import _kernels as K


@pytest.mark.parametrize("n_threads", [1, 2, 3, 4])
@pytest.mark.parametrize("n_items", [1, 2, 7, 100, 1001])
def test_every_item_is_handed_out_exactly_once(n_items: int, n_threads: int) -> None:
    for hold_first in (0, 1):
        times, taken_by = K.share_items(n_items, n_threads, hold_first)
        assert np.all(times == 1), f"items handed out {set(times.tolist())} times"
        assert np.all((taken_by >= 1) & (taken_by <= n_threads))


def test_one_thread_takes_the_items_in_order_of_its_range() -> None:
    times, taken_by = K.share_items(10, 1, 0)
    assert np.all(times == 1) and np.all(taken_by == 1)


def test_threads_take_the_range_of_a_thread_that_is_held_back() -> None:
    """Thread 1 starts only after the others have run out of items: they must have taken all of
    thread 1's range (the first quarter of the items with 4 threads, as schedule(static) deals).
    Which of them took which item depends on timing; that each was taken once does not."""
    n_items, n_threads = 100, 4
    times, taken_by = K.share_items(n_items, n_threads, 1)
    assert np.all(times == 1)
    assert not np.any(taken_by == 1)
