"""The exact sum the contact's energy and definition forces are added with (core/exact_sum.f90,
docs/theory.md "Parallel contact and determinism"), called through the f2py wrapper
``exact_sum_split``, which deals the terms to some accumulators, as ranks would hold them, adds the
accumulators as MPI_Allreduce does and rounds once.

Reference: Python's ``math.fsum``, the correctly rounded sum of its terms (Shewchuk's algorithm),
written independently of the kernel. Every case compares the bits, and every case is summed in
several orders and splits, which must all give the same bits.
"""

from __future__ import annotations

import math
import struct

import numpy as np
import pytest

from paradyn import _kernels as K

SPLITS = (1, 2, 3, 7, 64)


def _bits(x: float) -> int:
    return struct.unpack("<q", struct.pack("<d", x))[0]


def _exact(x: np.ndarray, parts: int = 1) -> float:
    return float(K.exact_sum_split(np.ascontiguousarray(x, dtype=np.float64), parts))


def _cases() -> dict[str, np.ndarray]:
    rng = np.random.default_rng(19)
    big = rng.standard_normal(5000) * 10.0 ** rng.integers(-300, 300, 5000)
    pairs = rng.standard_normal(2000) * 1e200
    tiny = rng.integers(-2**52, 2**52, 3000) * 5e-324          # subnormals and small normals
    return {
        "normal_10000": rng.standard_normal(10_000),
        "ranges_1e-300_to_1e300": big,
        "cancelling_pairs_and_a_small_rest": np.concatenate([pairs, -pairs, [1e-300, 3.0, -2.5e-17]]),
        "huge_cancellation": np.array([1e308, 1.0, -1e308, 1e-308, -1.0, 2.0**-1074]),
        "subnormals": tiny.astype(np.float64),
        "all_negative": -np.abs(rng.standard_normal(3000)) * 1e-5,
        "tie_to_even_down": np.array([2.0**53, 1.0]),
        "tie_to_even_up": np.array([2.0**53 + 2.0, 1.0]),
        "tie_broken_by_a_tiny_term": np.array([2.0**53, 1.0, 2.0**-1000]),
        "many_equal_terms": np.full(200_000, 0.1),
        "near_the_largest": np.array([1.7e308, -1.0e308, 1.0e308, -0.5e308]),
        "products_of_a_step": rng.standard_normal(4000) * rng.standard_normal(4000) * 1e3,
    }


@pytest.mark.parametrize("name", sorted(_cases()))
def test_exact_sum_is_fsum_in_any_order_and_split(name: str) -> None:
    """The kernel's sum has the bits of math.fsum's (correctly rounded), for the terms as given,
    reversed and shuffled three ways, dealt to 1, 2, 3, 7 and 64 accumulators."""
    x = _cases()[name]
    expected = math.fsum(x)
    rng = np.random.default_rng(5)
    orders = [x, x[::-1]] + [rng.permutation(x) for _ in range(3)]
    for terms in orders:
        for parts in SPLITS:
            got = _exact(terms, parts)
            assert _bits(got) == _bits(expected), (name, parts, got, expected)


def test_exact_sum_differs_from_the_running_sum_where_it_must() -> None:
    """A case the left-to-right double sum gets wrong (it loses the 1.0 to the 1e16s), so the test
    above can tell an exact sum from an ordinary one."""
    x = np.array([1e16, 1.0, -1e16])
    assert sum(x.tolist()) == 0.0
    assert _exact(x) == 1.0 == math.fsum(x)


def test_exact_sum_of_zeros_and_nothing() -> None:
    """An exact zero is +0.0 (as math.fsum gives for [-0.0]); no terms sum to +0.0."""
    for x in (np.array([]), np.array([-0.0]), np.array([0.0, -0.0]), np.array([3.5, -3.5])):
        for parts in SPLITS:
            got = _exact(x, parts)
            assert got == 0.0 and math.copysign(1.0, got) == 1.0


def test_exact_sum_of_non_finite_terms() -> None:
    """IEEE: an infinity wins over finite terms, NaN or both infinities give NaN, on any split."""
    inf, nan = float("inf"), float("nan")
    for parts in SPLITS:
        assert _exact(np.array([1.0, inf, -1e308, 2.0]), parts) == inf
        assert _exact(np.array([1.0, -inf, 2.0]), parts) == -inf
        assert math.isnan(_exact(np.array([inf, 1.0, -inf]), parts))
        assert math.isnan(_exact(np.array([1.0, nan, 2.0]), parts))


def test_exact_sum_beyond_the_largest_double_is_infinite() -> None:
    """A finite sum past the largest double (where math.fsum raises) rounds to an infinity of its
    sign, and its exact cancellation still gives the finite answer."""
    assert _exact(np.array([1.7e308, 1.7e308])) == float("inf")
    assert _exact(np.array([-1.7e308, -1.7e308])) == -float("inf")
    assert _exact(np.array([1.7e308, 1.7e308, -1.7e308, 1.0])) == math.fsum([1.7e308, 1.0])
