"""Contact kernels (issue 4) of the global search, called through the f2py wrappers
(``paradyn._kernels``): 3-D bucket sort of the master nodes (Benson & Hallquist 1990), the
nearest master node of a point, and the candidates rebalanced between the stages. Each test
names its reference in its docstring.

Node and segment numbers returned by the wrappers are 1-based. A segment is ``xseg[:, I]`` for
its nodes I = 0..3 at (xi, eta) = (-1, -1), (1, -1), (1, 1), (-1, 1).
"""

from __future__ import annotations

import numpy as np
import pytest

from contact_kernel_cases import F, brute_nearest
from paradyn import _kernels as K


def nearest(master: np.ndarray, points: np.ndarray, bucket_size: float,
            max_distance: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    idx, n_buckets = K.contact_nearest_nodes(F(master), bucket_size, F(points), max_distance=max_distance)
    return np.asarray(idx), np.asarray(n_buckets)


# ------------------------------------------------------------------------------------------------
# Bucket sort: nearest master node


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("bucket_size", [0.0, 0.01, 0.05, 0.13, 0.5, 3.0])
def test_bucket_nearest_equals_brute_force_random(seed: int, bucket_size: float) -> None:
    """Reference: brute-force nearest neighbour (numpy, all pairs) on random clouds."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 400))
    scale = rng.uniform(0.2, 2.0, size=3)              # anisotropic boxes
    master = rng.uniform(-1.0, 1.0, size=(3, n)) * scale[:, None]
    points = rng.uniform(-1.3, 1.3, size=(3, 500)) * scale[:, None]
    idx, n_buckets = nearest(master, points, bucket_size)
    np.testing.assert_array_equal(idx, brute_nearest(master, points))
    assert np.prod(n_buckets) <= max(n, 1)


@pytest.mark.parametrize("seed", range(4))
def test_bucket_nearest_clustered_cloud(seed: int) -> None:
    """Reference: brute force; master nodes in a few tight clusters, so most buckets are empty
    and the search must widen its rings."""
    rng = np.random.default_rng(100 + seed)
    centres = rng.uniform(-10, 10, size=(3, 4))
    master = np.concatenate([c[:, None] + 0.01 * rng.standard_normal((3, 50)) for c in centres.T], axis=1)
    points = rng.uniform(-12, 12, size=(3, 400))
    for h in (0.001, 0.02, 1.0):
        idx, _ = nearest(master, points, h)
        np.testing.assert_array_equal(idx, brute_nearest(master, points))


@pytest.mark.parametrize("spacing", [1.0, 0.5, 0.37])
def test_bucket_ties_on_structured_grid_go_to_lowest_index(spacing: float) -> None:
    """Reference: brute force with first-minimum tie break. Lattice nodes in shuffled order,
    queried at cell centres, face centres, edge midpoints and the nodes themselves, where 8, 4, 2
    or 1 nodes are exactly equidistant (half-integer offsets of dyadic spacings are exact)."""
    rng = np.random.default_rng(7)
    g = np.arange(5) * 1.0
    lattice = np.array(np.meshgrid(g, g, g[:3], indexing="ij")).reshape(3, -1)
    master = lattice[:, rng.permutation(lattice.shape[1])]
    half = np.arange(-1, 10) * 0.5
    points = np.array(np.meshgrid(half, half, np.arange(-1, 6) * 0.5, indexing="ij")).reshape(3, -1)
    for h in (spacing, 0.5 * spacing, 2.0 * spacing, 0.0):
        idx, _ = nearest(master, points, h)
        np.testing.assert_array_equal(idx, brute_nearest(master, points))


def test_bucket_duplicate_nodes_go_to_lowest_index() -> None:
    """Reference: brute force; coincident master nodes are ties, won by the lowest index."""
    rng = np.random.default_rng(3)
    base = rng.uniform(0, 1, size=(3, 30))
    master = np.concatenate([base, base[:, ::-1], base], axis=1)
    points = np.concatenate([base, rng.uniform(-0.2, 1.2, size=(3, 200))], axis=1)
    idx, _ = nearest(master, points, 0.1)
    np.testing.assert_array_equal(idx, brute_nearest(master, points))
    np.testing.assert_array_equal(idx[:30], np.arange(1, 31))


@pytest.mark.parametrize("distance", [5.0, 1e3, 1e6])
def test_bucket_points_far_outside_the_master_box(distance: float) -> None:
    """Reference: brute force, for points far from the box in every direction (faces, edges and
    corners of the box)."""
    rng = np.random.default_rng(11)
    master = rng.uniform(0, 1, size=(3, 300))
    dirs = rng.standard_normal((3, 200))
    dirs /= np.linalg.norm(dirs, axis=0)
    points = 0.5 + distance * dirs
    axes = np.concatenate([np.eye(3), -np.eye(3)], axis=1) * distance + 0.5
    points = np.concatenate([points, axes], axis=1)
    for h in (0.02, 0.2):
        idx, _ = nearest(master, points, h)
        np.testing.assert_array_equal(idx, brute_nearest(master, points))


def test_bucket_flat_and_collinear_master_sets() -> None:
    """Reference: brute force; master nodes on a plane (a flat shell) and on a line, where the
    grid has a single bucket across the flat axes."""
    rng = np.random.default_rng(5)
    sheet = np.vstack([rng.uniform(0, 2, size=(2, 300)), np.zeros((1, 300))])
    line = np.vstack([np.zeros((1, 100)), rng.uniform(-1, 1, size=(1, 100)), np.zeros((1, 100))])
    points = rng.uniform(-0.5, 2.5, size=(3, 300))
    for master in (sheet, line):
        for h in (0.0, 0.05, 0.3):
            idx, n_buckets = nearest(master, points, h)
            np.testing.assert_array_equal(idx, brute_nearest(master, points))
    _, n_buckets = nearest(sheet, points, 0.05)
    assert n_buckets[2] == 1


def test_bucket_single_node_and_empty_master_set() -> None:
    """Reference: the definition (one node is nearest to everything; no node gives 0)."""
    points = np.random.default_rng(1).uniform(-5, 5, size=(3, 20))
    idx, n_buckets = nearest(np.array([[0.3], [0.2], [0.1]]), points, 0.1)
    np.testing.assert_array_equal(idx, np.ones(20, dtype=int))
    np.testing.assert_array_equal(n_buckets, [1, 1, 1])
    idx, _ = nearest(np.zeros((3, 0)), points, 0.1)
    np.testing.assert_array_equal(idx, np.zeros(20, dtype=int))


@pytest.mark.parametrize("radius", [0.01, 0.05, 0.3])
def test_bucket_search_radius(radius: float) -> None:
    """Reference: brute force restricted to the radius (the nearest node if it lies within
    max_distance, else 0), for points near and far from a sheet of master nodes."""
    rng = np.random.default_rng(9)
    master = np.vstack([rng.uniform(0, 1, size=(2, 400)), 0.01 * rng.uniform(size=(1, 400))])
    points = np.vstack([rng.uniform(-0.3, 1.3, size=(2, 400)), rng.uniform(-0.4, 0.4, size=(1, 400))])
    ref = brute_nearest(master, points)
    dist = np.linalg.norm(points - master[:, ref - 1], axis=0)
    ref[dist > radius] = 0
    for h in (0.0, 0.02, 0.1):
        idx, _ = nearest(master, points, h, radius)
        np.testing.assert_array_equal(idx, ref)
    assert 0 < np.count_nonzero(ref) < ref.size


def within(master: np.ndarray, points: np.ndarray, radius: float) -> np.ndarray:
    """Brute force restricted to a radius: the nearest master node (1-based) or 0 beyond it."""
    ref = brute_nearest(master, points)
    ref[np.linalg.norm(points - master[:, ref - 1], axis=0) > radius] = 0
    return ref


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("margin", [0.005, 0.02, 0.04])
def test_slave_lists_give_the_grid_answer_along_a_walk(seed: int, margin: float) -> None:
    """Reference: brute force within the search radius at every point of a slave's random walk
    (steps of a fifth of the margin, so lists are kept for several steps and then made again);
    most answers come from a kept list, some from a new one."""
    rng = np.random.default_rng(seed)
    master = np.vstack([rng.uniform(0, 1, size=(2, 300)), 0.02 * rng.uniform(size=(1, 300))])
    steps = rng.standard_normal((3, 300)) * (0.2 * margin / np.sqrt(3))
    points = np.array([0.5, 0.5, 0.05])[:, None] + np.cumsum(steps, axis=1)
    radius = 0.08
    nearest_, listed = K.contact_nearest_listed(F(master), 0.05, F(points), radius, margin, 0, np.zeros(3))
    np.testing.assert_array_equal(nearest_, within(master, points, radius))
    assert np.count_nonzero(nearest_) > 0
    assert 0.5 * points.shape[1] < np.count_nonzero(listed) < points.shape[1]


def test_a_list_is_not_kept_across_a_new_grid() -> None:
    """Reference: brute force on the moved masters. The slave stands still while the masters move
    by more than the search radius and the grid is built again: the answers after that follow the
    new positions (a list from before the new grid would keep the old nearest node)."""
    rng = np.random.default_rng(3)
    master = rng.uniform(0, 1, size=(3, 300))
    points = np.repeat(np.array([[0.5], [0.5], [0.5]]), 6, axis=1)
    shift = np.array([0.2, -0.1, 0.15])
    nearest_, listed = K.contact_nearest_listed(F(master), 0.1, F(points), 0.15, 0.05, 4, shift)
    np.testing.assert_array_equal(nearest_[:3], within(master, points[:, :3], 0.15))
    np.testing.assert_array_equal(nearest_[3:], within(master + shift[:, None], points[:, 3:], 0.15))
    assert nearest_[2] != nearest_[3]
    np.testing.assert_array_equal(listed, [0, 1, 1, 0, 1, 1])


def test_a_list_too_long_falls_back_to_the_grid() -> None:
    """Reference: brute force. A dense cluster puts more master nodes within the radius than a
    list holds: the answers are still right, and none is taken from a list."""
    rng = np.random.default_rng(4)
    master = 0.5 + 0.01 * rng.standard_normal((3, 200))
    points = 0.5 + 0.003 * np.cumsum(rng.standard_normal((3, 20)), axis=1)
    nearest_, listed = K.contact_nearest_listed(F(master), 0.0, F(points), 0.1, 0.05, 0, np.zeros(3))
    np.testing.assert_array_equal(nearest_, within(master, points, 0.1))
    assert not listed.any()


def test_bucket_count_is_capped_by_node_count() -> None:
    """Reference: the design rule of O(n) memory, number of buckets <= number of nodes, even for
    a bucket size far below the node spacing; and equal to the requested grid when it fits."""
    rng = np.random.default_rng(2)
    master = rng.uniform(0, 1, size=(3, 1000))
    _, n_buckets = nearest(master, master[:, :5], 1e-9)
    assert np.prod(n_buckets) <= 1000
    assert np.prod(n_buckets) >= 1000 / 1.25**3 / 8     # not shrunk much more than needed
    extent = master.max(axis=1) - master.min(axis=1)
    _, n_buckets = nearest(master, master[:, :5], 0.25)
    np.testing.assert_array_equal(n_buckets, np.floor(extent / 0.25).astype(int))
    # the automatic size (bucket_size <= 0) gives square buckets on a flat sheet
    sheet = np.vstack([rng.uniform(0, 1, size=(2, 10000)), np.zeros((1, 10000))])
    _, n_buckets = nearest(sheet, sheet[:, :5], 0.0)
    assert n_buckets[2] == 1 and abs(n_buckets[0] - n_buckets[1]) <= 1
    assert 10000 / 1.25**2 / 4 <= np.prod(n_buckets) <= 10000



# ------------------------------------------------------------------------------------------------
# Rebalancing the candidates between the stages (the paper's node-wise block decomposition)


def candidate_blocks(n_candidates: int, n_ranks: int) -> list[range]:
    first, last = K.contact_candidate_blocks(n_candidates, n_ranks)
    return [range(int(start), int(end) + 1) for start, end in zip(first, last, strict=True)]


@pytest.mark.parametrize("n_candidates", [0, 1, 2, 3, 5, 7, 64, 100, 101, 1023])
@pytest.mark.parametrize("n_ranks", [1, 2, 3, 4, 7, 16])
def test_candidate_blocks_cover_every_candidate_once_in_equal_blocks(n_candidates: int, n_ranks: int) -> None:
    """Reference: the paper's section 5 (kave = kont / np candidates per processor). The blocks,
    in rank order, are 1..n_candidates exactly once, each contiguous and ascending, and their
    sizes differ by at most one, also with fewer candidates than ranks and with none."""
    blocks = candidate_blocks(n_candidates, n_ranks)
    assert len(blocks) == n_ranks
    assert [k for block in blocks for k in block] == list(range(1, n_candidates + 1))
    sizes = [len(block) for block in blocks]
    assert max(sizes) - min(sizes) <= 1
    assert sum(sizes) == n_candidates


def cyclic_pairs(candidate_slaves: np.ndarray, n_ranks: int, rng: np.random.Generator) -> np.ndarray:
    """The pairs (slave, master) as the all-gather delivers them: slaves dealt cyclically
    (slave j to rank (j - 1) mod n_ranks), each rank's pairs ascending, rank after rank."""
    masters = {int(j): int(rng.integers(1, 500)) for j in candidate_slaves}
    pairs = [(j, masters[j]) for r in range(n_ranks) for j in sorted(masters) if (j - 1) % n_ranks == r]
    return np.array(pairs, dtype=np.int32).T.reshape(2, -1)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("n_ranks", [1, 2, 3, 4])
@pytest.mark.parametrize("spread", ["random", "one_rank", "none"])
def test_candidates_in_slave_order_then_equal_blocks(seed: int, n_ranks: int, spread: str) -> None:
    """Reference: sorting in numpy. The candidates gathered rank after rank come out in
    ascending slave order with their masters, and the blocks are equal even when every candidate
    lies in one rank's cyclic share (spread "one_rank", the worst case for the global stage)."""
    rng = np.random.default_rng(seed)
    n_slaves = 200
    slaves = np.arange(1, n_slaves + 1)
    if spread == "random":
        chosen = slaves[rng.random(n_slaves) < 0.3]
    elif spread == "one_rank":
        chosen = slaves[(slaves - 1) % n_ranks == n_ranks - 1][:37]
    else:
        chosen = slaves[:0]
    pairs = cyclic_pairs(chosen, n_ranks, rng)
    n_candidates, candidates = K.contact_candidates_in_order(n_slaves, F(pairs))
    expect = pairs[:, np.argsort(pairs[0], kind="stable")]
    assert n_candidates == len(chosen)
    np.testing.assert_array_equal(candidates[:, :n_candidates], expect)
    assert np.all(np.diff(candidates[0, :n_candidates]) > 0)
    sizes = [len(block) for block in candidate_blocks(n_candidates, n_ranks)]
    assert max(sizes) - min(sizes) <= 1 and sum(sizes) == n_candidates
