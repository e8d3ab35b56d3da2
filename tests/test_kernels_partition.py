"""Domain decomposition kernels (block and RCB partitions, the corner sum over ranks), called
through the f2py wrappers (``paradyn._kernels``).

Each test names the reference it checks against in its docstring. Real arrays passed to the
wrappers are float64 and Fortran-ordered; ``intent(inout)`` arrays are updated in place.
"""

from __future__ import annotations

import numpy as np
import pytest

from kernel_cases import F
from paradyn import _kernels as K
from paradyn import deck
from paradyn.mesh import geometry

# ------------------------------------------------------------------------------------------------
# domain decomposition


@pytest.mark.parametrize("n_elements, n_ranks", [
    (1, 1), (10, 1), (10, 3), (32, 4), (512, 3), (1024, 7), (3, 5), (7, 7), (1_000_003, 13),
])
def test_block_partition(n_elements: int, n_ranks: int) -> None:
    """Reference: the paper's contiguous element blocks (domain_decomposition.block_owner):
    owners are 0-based, non-decreasing (contiguous blocks), every element has exactly one owner
    in 0..n_ranks-1, block sizes differ by at most one, and block r holds elements
    floor(r n / p) + 1 .. floor((r + 1) n / p) (1-based)."""
    owner = np.asarray(K.block_partition(n_elements, n_ranks))
    assert owner.shape == (n_elements,)
    assert owner.min() >= 0 and owner.max() <= n_ranks - 1
    assert np.all(np.diff(owner) >= 0)
    sizes = np.bincount(owner, minlength=n_ranks)
    assert sizes.sum() == n_elements
    assert sizes.max() - sizes.min() <= 1
    r = np.arange(n_ranks + 1, dtype=np.int64)
    bounds = (r * n_elements) // n_ranks
    np.testing.assert_array_equal(sizes, np.diff(bounds))


def _rcb(centroids: np.ndarray, n_ranks: int) -> np.ndarray:
    """rcb_partition on centroids given as (n, 3)."""
    c = F(np.asarray(centroids, dtype=np.float64).T)
    return np.asarray(K.rcb_partition(c.shape[1], c, n_ranks))


def _rcb_reference(centroids: np.ndarray, n_ranks: int) -> np.ndarray:
    """The rule of docs/theory.md written independently with numpy: cut the longest side of the
    bounding box (lowest axis on a tie), the first n q_low / q elements in (coordinate, id) order
    go to the first q_low = q // 2 ranks."""
    owner = np.full(len(centroids), -1)

    def split(ids: np.ndarray, rank0: int, q: int) -> None:
        if q == 1 or ids.size == 0:
            owner[ids] = rank0
            return
        extent = centroids[ids].max(axis=0) - centroids[ids].min(axis=0)
        axis = int(np.argmax(extent))            # first maximum: the lowest axis on a tie
        ids = ids[np.lexsort((ids, centroids[ids, axis]))]
        n_low = ids.size * (q // 2) // q
        split(ids[:n_low], rank0, q // 2)
        split(ids[n_low:], rank0 + q // 2, q - q // 2)

    split(np.arange(len(centroids)), 0, n_ranks)
    return owner


def _grid_centroids(nx: int, ny: int) -> np.ndarray:
    """Centroids of an nx x ny grid of unit squares, numbered row by row (x fastest)."""
    x, y = np.meshgrid(np.arange(nx) + 0.5, np.arange(ny) + 0.5, indexing="xy")
    return np.column_stack([x.ravel(), y.ravel(), np.zeros(nx * ny)])


def _point_sets() -> dict[str, np.ndarray]:
    rng = np.random.default_rng(5)
    return {
        "grid_12x7": _grid_centroids(12, 7),
        "random_3d_500": rng.random((500, 3)) * [3.0, 1.0, 2.0],
        "line_with_duplicates": np.repeat(np.column_stack([np.arange(9.0), np.zeros(9), np.zeros(9)]), 3, axis=0),
        "three_points": rng.random((3, 3)),
    }


@pytest.mark.parametrize("name", list(_point_sets()))
@pytest.mark.parametrize("n_ranks", [1, 2, 3, 4, 5, 7, 8])
def test_rcb_partition_owners_and_sizes(name: str, n_ranks: int) -> None:
    """Reference: the rule of docs/theory.md (recursive coordinate bisection), as an independent
    numpy implementation: the owners are exactly its owners, every element has one owner in
    0..p-1 and part sizes differ by at most one, for any rank count (not only powers of two)."""
    centroids = _point_sets()[name]
    owner = _rcb(centroids, n_ranks)
    assert owner.shape == (len(centroids),)
    assert owner.min() >= 0 and owner.max() <= n_ranks - 1
    sizes = np.bincount(owner, minlength=n_ranks)
    assert sizes.sum() == len(centroids)
    assert sizes.max() - sizes.min() <= 1
    np.testing.assert_array_equal(owner, _rcb_reference(centroids, n_ranks))


@pytest.mark.parametrize("n_ranks", [2, 3, 4, 5, 7, 8])
def test_rcb_parts_are_separated_by_axis_aligned_planes(n_ranks: int) -> None:
    """Reference: the definition of a bisection by planes x_k = const: for every two parts
    there is an axis along which one part lies entirely at or below the other (random points in
    general position, where no two coordinates tie). Contiguous blocks of a random numbering fail
    this, so the check has teeth."""
    centroids = np.random.default_rng(11).random((400, 3)) * [4.0, 2.0, 1.0]
    owner = _rcb(centroids, n_ranks)

    def separated(a: np.ndarray, b: np.ndarray) -> bool:
        return bool(np.any((a.max(axis=0) <= b.min(axis=0)) | (b.max(axis=0) <= a.min(axis=0))))

    parts = [centroids[owner == r] for r in range(n_ranks)]
    for r in range(n_ranks):
        for s in range(r + 1, n_ranks):
            assert separated(parts[r], parts[s]), (r, s)
    blocks = np.asarray(K.block_partition(len(centroids), n_ranks))
    assert not separated(centroids[blocks == 0], centroids[blocks == 1])


def test_rcb_partition_of_a_grid_is_boxes() -> None:
    """Reference: hand count on an 8 x 2 grid of unit squares (long axis x): 2 ranks get the two
    4 x 2 halves, 4 ranks the four 2 x 2 quarters, in order of x."""
    centroids = _grid_centroids(8, 2)
    halves = _rcb(centroids, 2).reshape(2, 8)
    np.testing.assert_array_equal(halves, [[0, 0, 0, 0, 1, 1, 1, 1]] * 2)
    quarters = _rcb(centroids, 4).reshape(2, 8)
    np.testing.assert_array_equal(quarters, [[0, 0, 1, 1, 2, 2, 3, 3]] * 2)
    # a 2 x 8 grid (long axis y) is cut across y instead: rows 0-3 and rows 4-7
    tall = _rcb(_grid_centroids(2, 8), 2).reshape(8, 2)
    np.testing.assert_array_equal(tall, [[0, 0]] * 4 + [[1, 1]] * 4)


def test_rcb_partition_follows_coordinates_not_numbering() -> None:
    """Reference: hand count on a line of 10 elements numbered against x (element 0 at the far
    end): 3 ranks get 3, 3 and 4 elements (n_low = 10 // 3, then 7 // 2) in order of x."""
    centroids = np.column_stack([np.arange(10.0)[::-1], np.zeros(10), np.zeros(10)])
    owner = _rcb(centroids, 3)
    np.testing.assert_array_equal(owner, [2, 2, 2, 2, 1, 1, 1, 0, 0, 0])


def test_rcb_partition_breaks_ties_by_element_id() -> None:
    """Reference: docs/theory.md, ties in the cut coordinate go by element id. With every
    centroid at the same point the parts are the id ranges of the block partition; with each
    point of a line present twice, the copies with lower ids come first; and a second call gives
    the same array (every rank computes it alone)."""
    same = np.ones((10, 3))
    np.testing.assert_array_equal(_rcb(same, 3), K.block_partition(10, 3))
    line = np.column_stack([np.arange(5.0), np.zeros(5), np.zeros(5)])
    doubled = np.vstack([line, line])             # element i and i + 5 coincide
    owner = _rcb(doubled, 5)
    np.testing.assert_array_equal(owner, [0, 1, 2, 3, 4, 0, 1, 2, 3, 4])
    owner = _rcb(doubled, 4)   # x order 0, 5, 1, 6, 2 | 7, 3, 8, 4, 9, then 0, 5 | 1, 6, 2 and 7, 3 | 8, 4, 9
    np.testing.assert_array_equal(owner, [0, 1, 1, 2, 3, 0, 1, 2, 3, 3])
    random = np.round(np.random.default_rng(3).random((300, 3)) * 4) / 4   # many exact ties
    np.testing.assert_array_equal(_rcb(random, 7), _rcb(random, 7))


def _permuted_plate(nx: int, ny: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A flat nx x ny plate whose elements are numbered in random order: coordinates (n, 3),
    connectivity (e, 4) 0-based, and the permutation (element k is element perm[k] of the
    row-by-row numbering)."""
    mesh = geometry.plate((float(nx), float(ny)), (nx, ny))
    perm = np.random.default_rng(seed).permutation(mesh.n_elements)
    return mesh.coordinates, mesh.quads[perm], perm


def _shared_nodes(connectivity: np.ndarray, owner: np.ndarray) -> int:
    """Nodes touched by elements of more than one rank."""
    pairs = np.unique(np.column_stack([connectivity.ravel(), np.repeat(owner, 4)]), axis=0)
    return int(np.count_nonzero(np.bincount(pairs[:, 0]) > 1))


def _engine_owner(method: str, coordinates: np.ndarray, connectivity: np.ndarray, n_ranks: int) -> np.ndarray:
    return np.asarray(K.partition_elements(deck.PARTITIONS[method], F(coordinates.T),
                                           F(connectivity.T.astype(np.int32) + 1), n_ranks))


@pytest.mark.parametrize("n_ranks, cut_nodes", [(2, 17), (4, 33), (8, 65)])
def test_rcb_cuts_a_badly_numbered_plate_along_straight_lines(n_ranks: int, cut_nodes: int) -> None:
    """Reference: a 16 x 16 plate cut by straight grid lines: one line (17 shared nodes) on 2
    ranks, a line and a half-line each side (17 + 2 x 8 = 33) on 4, and 65 on 8, whatever the
    element numbering. Contiguous blocks of a random numbering share far more nodes (about all
    of them)."""
    coordinates, connectivity, perm = _permuted_plate(16, 16, seed=7)
    rcb = _engine_owner("rcb", coordinates, connectivity, n_ranks)
    blocks = _engine_owner("blocks", coordinates, connectivity, n_ranks)
    assert _shared_nodes(connectivity, rcb) == cut_nodes
    assert _shared_nodes(connectivity, blocks) > 3 * cut_nodes
    # the same parts as for the row-by-row numbering: here rcb depends on positions only
    plain = geometry.plate((16.0, 16.0), (16, 16))
    row_by_row = np.empty_like(rcb)
    row_by_row[perm] = rcb
    np.testing.assert_array_equal(row_by_row, _engine_owner("rcb", plain.coordinates, plain.quads, n_ranks))


def _two_part_mesh(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A 6 x 5 plate and a 4 x 8 cylinder as one mesh, elements randomly renumbered: coordinates,
    connectivity (0-based) and element part."""
    plate = geometry.plate((0.3, 0.25), (6, 5))
    tube = geometry.cylinder(0.05, 0.4, center=(0.15, 0.1, 0.2), elements_around=4, elements_along=8)
    coordinates = np.vstack([plate.coordinates, tube.coordinates])
    connectivity = np.vstack([plate.quads, tube.quads + plate.n_nodes])
    part = np.concatenate([np.zeros(plate.n_elements, int), np.ones(tube.n_elements, int)])
    perm = np.random.default_rng(seed).permutation(len(connectivity))
    return coordinates, connectivity[perm], part[perm]


@pytest.mark.parametrize("method", ["blocks", "rcb"])
@pytest.mark.parametrize("n_ranks", [1, 2, 3, 4, 7])
def test_decomposition_sums_every_corner_exactly_once(method: str, n_ranks: int) -> None:
    """Reference: the serial nodal sum. Issue 5: every element owned by exactly one rank, shared
    nodes consistent, forces on shared nodes summed exactly once. decompose builds every rank's
    domain for the owners of the method, and the wrapper plays out the engine's corner exchange
    and fixed-order sum between them without MPI. Checked against numpy: each element is local on
    exactly its owner; each node is held by exactly the ranks whose elements touch it and owned
    by exactly one, the lowest; on every rank that holds a node, the sum of its corners equals
    the serial one: the count of corners, the sum of the corner ids (a corner lost or counted
    twice changes it) and, bitwise, a sum of random values taken in ascending element order."""
    coordinates, connectivity, part = _two_part_mesh(seed=n_ranks)
    n_nodes, n_elements = len(coordinates), len(connectivity)
    owner = _engine_owner(method, coordinates, connectivity, n_ranks)
    rng = np.random.default_rng(1)
    values = np.empty((3, 4, n_elements))
    values[0] = 1.0
    values[1] = np.arange(4 * n_elements).reshape(n_elements, 4).T      # corner id 4 e + c
    values[2] = rng.standard_normal((4, n_elements)) * 10.0 ** rng.integers(-3, 4, (4, n_elements))
    (element_holders, element_rank, node_holders, node_owners, n_neighbours, n_sent, node_sum,
     status) = K.decomposition_check(n_nodes, F(connectivity.T.astype(np.int32) + 1), part.astype(np.int32) + 1,
                                     owner.astype(np.int32), n_ranks, F(values))
    assert status == 0
    np.testing.assert_array_equal(element_holders, 1)
    np.testing.assert_array_equal(element_rank, owner)

    ranks_of_node = [set() for _ in range(n_nodes)]
    serial = np.zeros((3, n_nodes))
    for e in range(n_elements):                  # ascending element order, as the engine sums
        for c in range(4):
            n = connectivity[e, c]
            ranks_of_node[n].add(int(owner[e]))
            serial[:, n] += values[:, c, e]
    np.testing.assert_array_equal(node_holders, [len(r) for r in ranks_of_node])
    np.testing.assert_array_equal(node_owners, 1)
    for n in range(n_nodes):
        for r in range(n_ranks):
            if r in ranks_of_node[n]:
                assert np.array_equal(node_sum[:, n, r], serial[:, n]), (n, r)
            else:
                assert np.all(node_sum[:, n, r] == 0.0)
    neighbours = [set() for _ in range(n_ranks)]
    for held in ranks_of_node:
        for r in held:
            neighbours[r] |= held - {r}
    np.testing.assert_array_equal(n_neighbours, [len(s) for s in neighbours])
    assert (n_ranks == 1) == (n_sent.sum() == 0)
