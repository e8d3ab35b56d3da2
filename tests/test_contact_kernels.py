"""Contact kernels (issue 4), called through the f2py wrappers (``paradyn._kernels``).

Global search: 3-D bucket sort of the master nodes (Benson & Hallquist 1990) and the nearest
master node of a point. Local search and forces: closest point on a bilinear shell segment,
segment selection around the nearest node, penalty force between two-sided shells with
thickness, regularised Coulomb friction (Hallquist, Goudreau & Benson 1985; LS-DYNA Theory
Manual). Each test names its reference in its docstring.

Node and segment numbers returned by the wrappers are 1-based. A segment is ``xseg[:, I]`` for
its nodes I = 0..3 at (xi, eta) = (-1, -1), (1, -1), (1, 1), (-1, 1).
"""

from __future__ import annotations

import numpy as np
import pytest

from paradyn import _kernels as K

F = np.asfortranarray


def brute_nearest(master: np.ndarray, points: np.ndarray) -> np.ndarray:
    """1-based index of the nearest master node of each point; np.argmin keeps the first (lowest)."""
    d2 = ((points.T[:, None, :] - master.T[None, :, :]) ** 2).sum(axis=2)
    return np.argmin(d2, axis=1) + 1


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
# Closest point on a bilinear segment

SHAPE_SIGNS = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)


def shape(xi: float, eta: float) -> np.ndarray:
    return 0.25 * (1 + SHAPE_SIGNS[:, 0] * xi) * (1 + SHAPE_SIGNS[:, 1] * eta)


def surface(xseg: np.ndarray, xi, eta):
    """x(xi, eta) and its two tangents dx/dxi, dx/deta (numpy reference of the bilinear map)."""
    n = shape(xi, eta)
    dxi = 0.25 * SHAPE_SIGNS[:, 0] * (1 + SHAPE_SIGNS[:, 1] * eta)
    deta = 0.25 * SHAPE_SIGNS[:, 1] * (1 + SHAPE_SIGNS[:, 0] * xi)
    return xseg @ n, xseg @ dxi, xseg @ deta


def rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.standard_normal((3, 3)))
    q = q * np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def flat_quad(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A convex, non-parallelogram flat quadrilateral in a random orientation, and its normal."""
    local = np.array([[0.0, 0.0], [2.0, 0.2], [2.3, 1.7], [-0.2, 1.5]]) + rng.uniform(-0.15, 0.15, (4, 2))
    rot = rotation(rng)
    xseg = rot @ np.vstack([local.T, np.zeros(4)]) + rng.uniform(-3, 3, size=(3, 1))
    return F(xseg), rot[:, 2]


@pytest.mark.parametrize("seed", range(10))
def test_projection_above_flat_segment(seed: int) -> None:
    """Reference: construction. p = x(xi0, eta0) + h n on a flat quad projects back to
    (xi0, eta0) (to 1e-12), xc = x(xi0, eta0), normal = n (the plane's normal, which is
    dx/dxi x dx/deta normalised)."""
    rng = np.random.default_rng(seed)
    xseg, n = flat_quad(rng)
    for _ in range(20):
        xi0, eta0 = rng.uniform(-0.98, 0.98, 2)
        h = rng.uniform(-1.0, 1.0)
        x0, _, _ = surface(xseg, xi0, eta0)
        xi, eta, xc, normal = K.contact_closest_point(xseg, F(x0 + h * n))
        assert abs(xi - xi0) < 1e-12 and abs(eta - eta0) < 1e-12
        np.testing.assert_allclose(xc, x0, atol=1e-12)
        np.testing.assert_allclose(normal, n, atol=1e-12)


@pytest.mark.parametrize("seed", range(10))
def test_projection_beyond_an_edge_lands_on_the_edge(seed: int) -> None:
    """Reference: Euclidean projection onto the segment's boundary line. A point beyond edge 2-3
    (xi = 1) of a flat quad, off the plane, lands on that edge at the foot of its perpendicular:
    xi = 1, eta = 2 s - 1 where s is the parameter of the foot along the edge."""
    rng = np.random.default_rng(seed)
    xseg, n = flat_quad(rng)
    x2, x3 = xseg[:, 1], xseg[:, 2]
    edge = x3 - x2
    outward = np.cross(edge, n)
    outward /= np.linalg.norm(outward)
    assert np.dot(outward, x2 - xseg.mean(axis=1)) > 0
    for _ in range(20):
        s = rng.uniform(0.1, 0.9)
        p = x2 + s * edge + rng.uniform(0.01, 1.0) * outward + rng.uniform(-0.5, 0.5) * n
        xi, eta, xc, _ = K.contact_closest_point(xseg, F(p))
        assert xi == 1.0
        assert abs(eta - (2 * s - 1)) < 1e-12
        np.testing.assert_allclose(xc, x2 + s * edge, atol=1e-12)


@pytest.mark.parametrize("corner", range(4))
def test_projection_beyond_a_corner_lands_on_the_corner(corner: int) -> None:
    """Reference: Euclidean projection onto a convex polygon. A point in the normal cone of a
    corner (a positive combination of the outward normals of the two edges that meet there,
    plus any offset along the plane's normal) projects onto the corner node."""
    rng = np.random.default_rng(20 + corner)
    xseg, n = flat_quad(rng)
    xk = xseg[:, corner]
    e_prev = xk - xseg[:, (corner - 1) % 4]
    e_next = xseg[:, (corner + 1) % 4] - xk
    out_prev = np.cross(e_prev, n) / np.linalg.norm(e_prev)
    out_next = np.cross(e_next, n) / np.linalg.norm(e_next)
    for _ in range(20):
        a, b = rng.uniform(0.02, 1.0, 2)
        p = xk + a * out_prev + b * out_next + rng.uniform(-0.5, 0.5) * n
        xi, eta, xc, _ = K.contact_closest_point(xseg, F(p))
        np.testing.assert_array_equal([xi, eta], SHAPE_SIGNS[corner])
        np.testing.assert_allclose(xc, xk, atol=1e-13)


def warped_quad(rng: np.random.Generator, warp: float) -> np.ndarray:
    local = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]) + rng.uniform(-0.15, 0.15, (4, 2))
    z = warp * np.array([1.0, -1.0, 1.0, -1.0]) + rng.uniform(-0.05, 0.05, 4)
    return F(rotation(rng) @ np.vstack([local.T, z]))


def grid_search(xseg, p, xi_range, eta_range, m):
    xi, eta = np.meshgrid(np.linspace(*xi_range, m), np.linspace(*eta_range, m), indexing="ij")
    n = 0.25 * (1 + SHAPE_SIGNS[:, 0, None, None] * xi) * (1 + SHAPE_SIGNS[:, 1, None, None] * eta)
    x = np.einsum("ik,kab->iab", xseg, n)
    d2 = ((x - p[:, None, None]) ** 2).sum(axis=0)
    j = np.unravel_index(np.argmin(d2), d2.shape)
    return float(d2[j]), float(xi[j]), float(eta[j])


def grid_minimum(xseg: np.ndarray, p: np.ndarray, m: int = 401) -> tuple[float, float, float]:
    """Dense grid search of |x(xi, eta) - p|^2 over [-1, 1]^2 (numpy reference): an m x m grid,
    then an m x m grid over +-2 cells around its best point (spacing 2 / m^2)."""
    _, xi, eta = grid_search(xseg, p, (-1, 1), (-1, 1), m)
    h = 4.0 / (m - 1)
    return grid_search(xseg, p, (max(-1, xi - h), min(1, xi + h)), (max(-1, eta - h), min(1, eta + h)), m)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("warp", [0.1, 0.25])
def test_projection_on_warped_segment_is_the_true_minimiser(seed: int, warp: float) -> None:
    """References: the optimality conditions of min |x(xi, eta) - p| over [-1, 1]^2 (the
    tangency equations (x - p).dx/dxi = (x - p).dx/deta = 0 vanish to 1e-10 where the
    coordinate is interior; on a bound the derivative points outward), and a dense numpy grid
    search (the kernel's distance is no larger than the grid's best, and the two minimisers
    agree within a few grid spacings)."""
    rng = np.random.default_rng(seed)
    xseg = warped_quad(rng, warp)
    centre = xseg.mean(axis=1)
    for _ in range(6):
        p = centre + rng.uniform(-0.9, 0.9, 3)
        xi, eta, xc, normal = K.contact_closest_point(xseg, F(p))
        x, dxi, deta = surface(xseg, xi, eta)
        np.testing.assert_allclose(xc, x, atol=1e-14)
        r = xc - p
        g = np.array([r @ dxi, r @ deta])
        for c, gc in zip((xi, eta), g):
            if abs(c) < 1.0:
                assert abs(gc) < 1e-10
            else:
                assert gc * c <= 1e-14        # the distance falls outward across the bound
        nref = np.cross(dxi, deta)
        np.testing.assert_allclose(normal, nref / np.linalg.norm(nref), atol=1e-13)
        d2_grid, xi_g, eta_g = grid_minimum(xseg, p)
        assert r @ r <= d2_grid * (1 + 1e-12) + 1e-15
        assert abs(xi - xi_g) < 1e-3 and abs(eta - eta_g) < 1e-3


def test_projection_on_degenerate_triangle() -> None:
    """Reference: Euclidean projection onto a triangle (nodes 3 and 4 coincide), by construction
    inside the triangle (barycentric point + normal offset) and beyond its apex."""
    xseg = F(np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.5, 1.5, 0.0], [0.5, 1.5, 0.0]]).T)
    p = np.array([0.8, 0.4, 0.3])
    _, _, xc, normal = K.contact_closest_point(xseg, F(p))
    np.testing.assert_allclose(xc, [0.8, 0.4, 0.0], atol=1e-12)
    np.testing.assert_allclose(normal, [0, 0, 1], atol=1e-12)
    _, eta, xc, normal = K.contact_closest_point(xseg, F(np.array([0.5, 3.0, -0.2])))
    np.testing.assert_allclose(xc, [0.5, 1.5, 0.0], atol=1e-12)
    assert eta == 1.0
    np.testing.assert_allclose(normal, [0, 0, 1], atol=1e-12)


# ------------------------------------------------------------------------------------------------
# Stage 2: the segment around the nearest master node


def plate_mesh(nx: int, ny: int, rng: np.random.Generator, bump: float) -> tuple[np.ndarray, np.ndarray]:
    """A curved nx x ny quad mesh (z = bump * smooth function): coords (3, n), segments (4, m)."""
    xs, ys = np.meshgrid(np.arange(nx + 1, dtype=float), np.arange(ny + 1, dtype=float), indexing="ij")
    xs = xs + rng.uniform(-0.1, 0.1, xs.shape)
    ys = ys + rng.uniform(-0.1, 0.1, ys.shape)
    zs = bump * np.sin(0.7 * xs) * np.cos(0.5 * ys)
    coords = np.vstack([xs.ravel(), ys.ravel(), zs.ravel()])
    node = lambda i, j: i * (ny + 1) + j + 1                           # noqa: E731
    segs = [[node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)]
            for i in range(nx) for j in range(ny)]
    return coords, np.array(segs, dtype=np.int32).T


def test_node_segment_map_matches_python() -> None:
    """Reference: the node-to-segment incidence built in Python (ascending segment numbers); a
    node repeated in a triangle is listed once."""
    rng = np.random.default_rng(0)
    coords, segs = plate_mesh(4, 3, rng, 0.0)
    segs = np.concatenate([segs, np.array([[1], [2], [7], [7]], dtype=np.int32)], axis=1)
    n_nodes = coords.shape[1]
    start, lst, n_entries = K.contact_node_segments(n_nodes, F(segs))
    for i in range(1, n_nodes + 1):
        expect = [s + 1 for s in range(segs.shape[1]) if i in segs[:, s]]
        np.testing.assert_array_equal(lst[start[i - 1] - 1:start[i] - 1], expect)
    assert n_entries == start[-1] - 1 == sum(len(set(s)) for s in segs.T)


@pytest.mark.parametrize("seed", range(5))
def test_segment_candidates_pick_the_nearest_segment(seed: int) -> None:
    """Reference: brute force over the segments around the node, each projected with a dense
    numpy grid search; the chosen segment's closest point is (within the grid's resolution) the
    nearest of them, and matches a direct call of the projection."""
    rng = np.random.default_rng(seed)
    coords, segs = plate_mesh(4, 4, rng, 0.4)
    start, lst, n_entries = K.contact_node_segments(coords.shape[1], F(segs))
    lst = lst[:n_entries]
    for _ in range(15):
        p = np.array([rng.uniform(0.5, 3.5), rng.uniform(0.5, 3.5), rng.uniform(-0.8, 0.8)])
        node = int(brute_nearest(coords, p[:, None])[0])
        seg, xi, eta, xc, normal = K.contact_segment_candidates(F(p), node, F(coords), F(segs), start, lst)
        around = lst[start[node - 1] - 1:start[node] - 1]
        assert seg in around
        d2 = {s: grid_minimum(F(coords[:, segs[:, s - 1] - 1]), p, 201)[0] for s in around}
        assert np.sum((p - xc) ** 2) <= min(d2.values()) * (1 + 1e-12) + 1e-15
        ref = K.contact_closest_point(F(coords[:, segs[:, seg - 1] - 1]), F(p))
        np.testing.assert_allclose([xi, eta], ref[:2], atol=1e-15)
        np.testing.assert_allclose(normal, ref[3], atol=1e-15)


def test_segment_candidates_node_without_segments() -> None:
    """Reference: the definition (a node in no segment gives segment 0)."""
    coords = np.zeros((3, 5))
    coords[:, 1:] = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]).T
    segs = np.array([[2], [3], [4], [5]], dtype=np.int32)
    start, lst, _ = K.contact_node_segments(5, F(segs))
    seg, *_ = K.contact_segment_candidates(F(np.ones(3)), 1, F(coords), F(segs), start, lst)
    assert seg == 0


# ------------------------------------------------------------------------------------------------
# Penalty stiffness and force

E, NU = 200e9, 0.3
BULK = E / (3 * (1 - 2 * NU))


def test_penalty_stiffness_shell_form() -> None:
    """Reference: LS-DYNA Theory Manual, penalty stiffness of a shell segment
    k = f K A / max(diagonal), K = E / (3 (1 - 2 nu)); for a 2 x 1 rectangle A = 2, d = sqrt(5)."""
    xseg = F(np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]], dtype=float).T)
    k = K.contact_penalty_stiffness(xseg, E, NU, 0.1)
    assert k == pytest.approx(0.1 * BULK * 2.0 / np.sqrt(5.0), rel=1e-14)


def test_penalty_force_equals_stiffness_times_penetration_on_flat_plate() -> None:
    """Reference: the penalty law f = k (t_s/2 + t_m/2 - |d|) n for a node above a flat plate
    (analytic), with the master share -f N_I(xi, eta) at the nodes."""
    xseg = F(np.array([[0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0]], dtype=float).T)
    k = 1.0e6
    p = np.array([0.5, 1.5, 0.04])
    f, fm, pen, contact = K.contact_penalty_force(F(p), 0.06, xseg, 0.1, k)
    assert contact == 1
    assert pen == pytest.approx(0.08 - 0.04, abs=1e-15)
    np.testing.assert_allclose(f, [0, 0, k * 0.04], rtol=1e-14, atol=1e-20)
    np.testing.assert_allclose(fm, -np.outer(f, shape(-0.5, 0.5)), rtol=1e-14, atol=1e-20)


@pytest.mark.parametrize("seed", range(6))
def test_penalty_force_pushes_slave_out_on_its_own_side(seed: int) -> None:
    """Reference: two-sided shell contact (contact surfaces half a thickness off each side of
    the mid-surface): a slave on the +n side within reach is pushed along +n, one on the -n side
    along -n, with |f| = k (reach - |d|) in both cases."""
    rng = np.random.default_rng(seed)
    xseg, n = flat_quad(rng)
    k, ts, tm = 3.0e5, 0.1, 0.2
    reach = 0.5 * (ts + tm)
    for side in (1.0, -1.0):
        for _ in range(10):
            x0, _, _ = surface(xseg, *rng.uniform(-0.9, 0.9, 2))
            d = rng.uniform(0.001, 0.999) * reach
            f, fm, pen, contact = K.contact_penalty_force(F(x0 + side * d * n), ts, xseg, tm, k)
            assert contact == 1
            assert pen == pytest.approx(reach - d, rel=1e-10)
            np.testing.assert_allclose(f, side * k * (reach - d) * n, rtol=1e-9, atol=1e-9 * k * reach)


@pytest.mark.parametrize("seed", range(6))
def test_no_force_when_separated(seed: int) -> None:
    """Reference: the gap g = |d| - (t_s + t_m)/2 >= 0 means no contact: zero forces, zero
    penetration, on both sides."""
    rng = np.random.default_rng(seed)
    xseg, n = flat_quad(rng)
    ts, tm = 0.1, 0.2
    for side in (1.0, -1.0):
        x0, _, _ = surface(xseg, *rng.uniform(-0.9, 0.9, 2))
        d = 0.5 * (ts + tm) * rng.uniform(1.0001, 5.0)
        f, fm, pen, contact = K.contact_penalty_force(F(x0 + side * d * n), ts, xseg, tm, 1e6)
        assert contact == 0 and pen == 0.0
        assert not f.any() and not fm.any()


def random_contact(rng: np.random.Generator, warp: float = 0.15):
    xseg = warped_quad(rng, warp)
    xi0, eta0 = rng.uniform(-0.9, 0.9, 2)
    x0, dxi, deta = surface(xseg, xi0, eta0)
    n = np.cross(dxi, deta)
    n /= np.linalg.norm(n)
    p = x0 + rng.uniform(-0.04, 0.04) * n
    return xseg, p


@pytest.mark.parametrize("seed", range(10))
def test_penalty_forces_equal_opposite_and_moment_free(seed: int) -> None:
    """References: Newton's third law (slave and master forces sum to zero to round-off) and
    moment balance about the contact point xc: the master forces -f N_I at x_I have
    sum (x_I - xc) x f_I = 0 because sum N_I x_I = xc, and the slave force acts along the
    normal through xc, so the total moment about xc vanishes as well (warped segments)."""
    rng = np.random.default_rng(seed)
    k = 1.0e7
    for _ in range(10):
        xseg, p = random_contact(rng)
        f, fm, pen, contact = K.contact_penalty_force(F(p), 0.1, xseg, 0.1, k)
        assert contact == 1
        scale = np.linalg.norm(f)
        assert scale == pytest.approx(k * pen, rel=1e-12)
        np.testing.assert_allclose(f + fm.sum(axis=1), 0.0, atol=1e-14 * scale)
        _, _, xc, _ = K.contact_closest_point(xseg, F(p))
        m_master = sum(np.cross(xseg[:, i] - xc, fm[:, i]) for i in range(4))
        np.testing.assert_allclose(m_master, 0.0, atol=1e-13 * scale)
        np.testing.assert_allclose(np.cross(p - xc, f), 0.0, atol=1e-13 * scale)


def test_point_beyond_an_edge_is_ignored_or_meets_a_rounded_edge() -> None:
    """Reference: projection onto the segment (the point must lie over the segment, within
    edge_tolerance = 5 % of the longer diagonal); with rounded edges (radius (t_s + t_m)/2 about
    the edge) the gap is |p - xc| - reach along (p - xc) (analytic for a flat square)."""
    xseg = F(np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float).T)
    ts = tm = 0.2
    k = 1.0e4
    p = np.array([1.12, 0.5, 0.05])                 # 0.12 beyond edge xi = 1, within reach 0.2
    f, fm, pen, contact = K.contact_penalty_force(F(p), ts, xseg, tm, k)
    assert contact == 0 and not f.any()
    f, fm, pen, contact = K.contact_penalty_force(F(p), ts, xseg, tm, k, rounded_edges=1)
    dist = np.hypot(0.12, 0.05)
    assert contact == 1 and pen == pytest.approx(0.2 - dist, rel=1e-12)
    np.testing.assert_allclose(f, k * (0.2 - dist) * np.array([0.12, 0, 0.05]) / dist, rtol=1e-12)
    np.testing.assert_allclose(f + fm.sum(axis=1), 0, atol=1e-12 * k)
    p = np.array([1.03, 0.5, 0.05])                 # within the 5 % edge tolerance: face contact
    f, fm, pen, contact = K.contact_penalty_force(F(p), ts, xseg, tm, k)
    assert contact == 1 and pen == pytest.approx(0.15, rel=1e-12)
    np.testing.assert_allclose(f, [0, 0, k * 0.15], rtol=1e-12, atol=1e-9)


def test_friction_opposes_slip_and_is_capped() -> None:
    """Reference: regularised Coulomb friction f_t = -mu |f_n| v_t / max(|v_t|, v_slip) with
    mu = mu_d + (mu_s - mu_d) exp(-decay |v_t|) (LS-DYNA's exponential interpolation): opposite
    to the tangential slip, at the cap above v_slip, proportional to the slip speed below it,
    independent of the normal velocity; and still equal and opposite on slave and master."""
    xseg = F(np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float).T)
    k, ts, tm = 1.0e5, 0.1, 0.1
    p = np.array([0.3, 0.6, 0.08])
    fn = k * 0.02
    vm = F(np.zeros((3, 4)))
    mus, mud, decay, vslip = 0.5, 0.3, 2.0, 0.01
    for vs, capped in (([1.0, -0.5, -3.0], True), ([0.004, 0.003, 2.0], False)):
        vs = np.array(vs)
        f, fm, pen, contact = K.contact_penalty_force(F(p), ts, xseg, tm, k, F(vs), vm, mus, mud, decay, vslip)
        vt = np.array([vs[0], vs[1], 0.0])
        speed = np.linalg.norm(vt)
        mu = mud + (mus - mud) * np.exp(-decay * speed)
        ft = -mu * fn * vt / max(speed, vslip)
        np.testing.assert_allclose(f, ft + [0, 0, fn], rtol=1e-12)
        assert np.linalg.norm(f[:2]) <= mu * fn * (1 + 1e-12)
        if capped:
            assert np.linalg.norm(f[:2]) == pytest.approx(mu * fn, rel=1e-12)
        np.testing.assert_allclose(f + fm.sum(axis=1), 0, atol=1e-12 * fn)
    # the master's own velocity counts: moving the master with the slave leaves no slip
    vs = np.array([1.0, -0.5, 0.0])
    f, *_ = K.contact_penalty_force(F(p), ts, xseg, tm, k, F(vs), F(np.repeat(vs[:, None], 4, axis=1)),
                                    mus, mud, decay, vslip)
    np.testing.assert_allclose(f, [0, 0, fn], rtol=1e-12, atol=1e-12)


# ------------------------------------------------------------------------------------------------
# Rebalancing the candidates between the stages (the paper's node-wise block decomposition)


def candidate_blocks(n_candidates: int, n_ranks: int) -> list[range]:
    first, last = K.contact_candidate_blocks(n_candidates, n_ranks)
    return [range(int(f), int(l) + 1) for f, l in zip(first, last)]


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
