"""Contact kernels (issue 4) of the local search, called through the f2py wrappers
(``paradyn._kernels``): closest point on a bilinear shell segment and segment selection around
the nearest node (Hallquist, Goudreau & Benson 1985; LS-DYNA Theory Manual). Each test names its
reference in its docstring.

Node and segment numbers returned by the wrappers are 1-based. A segment is ``xseg[:, I]`` for
its nodes I = 0..3 at (xi, eta) = (-1, -1), (1, -1), (1, 1), (-1, 1).
"""

from __future__ import annotations

import numpy as np
import pytest

from contact_kernel_cases import SHAPE_SIGNS, F, brute_nearest, flat_quad, surface, warped_quad
from paradyn import _kernels as K

# ------------------------------------------------------------------------------------------------
# Closest point on a bilinear segment


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
        for c, gc in zip((xi, eta), g, strict=True):
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


@pytest.mark.parametrize("seed", range(3))
def test_a_candidate_skipped_for_its_reach_touches_no_segment(seed: int) -> None:
    """Reference: penalty_force itself, on every segment around the node, with rounded edges
    (the engine's test). Points at distances around the reach: wherever segment_candidates with
    the reach gives no segment, no segment touches; where it gives one, it is the same answer,
    bit for bit, as without the reach; and it skips some points (else the test proves nothing)."""
    rng = np.random.default_rng(seed)
    coords, segs = plate_mesh(4, 4, rng, 0.4)
    start, lst, n_entries = K.contact_node_segments(coords.shape[1], F(segs))
    lst = lst[:n_entries]
    skipped = 0
    for _ in range(200):
        p = np.array([rng.uniform(-0.5, 4.5), rng.uniform(-0.5, 4.5), rng.uniform(-1.5, 1.5)])
        node = int(brute_nearest(coords, p[:, None])[0])
        t = rng.uniform(0.05, 0.8)
        found = K.contact_segment_candidates(F(p), node, F(coords), F(segs), start, lst, reach=t)
        touches = [K.contact_penalty_force(F(p), t, F(coords[:, segs[:, s - 1] - 1]), t, 1.0, rounded_edges=1)[3]
                   for s in lst[start[node - 1] - 1:start[node] - 1]]
        if found[0] == 0:
            skipped += 1
            assert not any(touches), (p, t)
        else:
            every = K.contact_segment_candidates(F(p), node, F(coords), F(segs), start, lst)
            for a, b in zip(found, every, strict=True):
                np.testing.assert_array_equal(a, b)
    assert 20 < skipped < 180


@pytest.mark.parametrize("seed", range(3))
def test_a_clear_slave_stays_clear_while_it_moves_less_than_half_its_clearance(seed: int) -> None:
    """Reference: penalty_force itself on every segment around the node. Where segment_candidates
    reports a clearance c > 0 (no segment can touch), the slave moved anywhere within c / 2.1 (the
    engine's skip allows 2 (1 + 0.05) times the movement) touches no segment either; and where a
    segment touches, the clearance is 0. Some points are clear (else the test proves nothing)."""
    rng = np.random.default_rng(seed)
    coords, segs = plate_mesh(4, 4, rng, 0.4)
    start, lst, n_entries = K.contact_node_segments(coords.shape[1], F(segs))
    lst = lst[:n_entries]
    clear = 0
    for _ in range(150):
        p = np.array([rng.uniform(-0.5, 4.5), rng.uniform(-0.5, 4.5), rng.uniform(-1.5, 1.5)])
        node = int(brute_nearest(coords, p[:, None])[0])
        t = rng.uniform(0.05, 0.8)
        c = K.contact_segment_clearance(F(p), node, F(coords), F(segs), start, lst, t)
        around = lst[start[node - 1] - 1:start[node] - 1]
        if c <= 0:
            continue
        clear += 1
        for _ in range(5):
            step = rng.standard_normal(3)
            q = p + rng.uniform(0, 1) * c / 2.1 * step / np.linalg.norm(step)
            touches = [K.contact_penalty_force(F(q), t, F(coords[:, segs[:, s - 1] - 1]), t, 1.0, rounded_edges=1)[3]
                       for s in around]
            assert not any(touches), (p, q, t, c)
    assert 20 < clear < 150


def test_clearance_above_a_flat_plate_is_the_height_less_the_reach() -> None:
    """Reference: construction. Above the middle of a flat plate at height h, every segment around
    the node is h away, so the clearance is h - (reach + 0.05 times the longest diagonal), to 1e-8."""
    coords, segs = plate_mesh(4, 4, np.random.default_rng(0), 0.0)
    start, lst, n_entries = K.contact_node_segments(coords.shape[1], F(segs))
    node = int(brute_nearest(coords, np.array([[2.0], [2.0], [0.0]]))[0])
    x = coords[:, node - 1]
    around = segs[:, lst[start[node - 1] - 1:start[node] - 1] - 1] - 1
    diagonal = max(max(np.linalg.norm(coords[:, s[2]] - coords[:, s[0]]),
                       np.linalg.norm(coords[:, s[3]] - coords[:, s[1]])) for s in around.T)
    for h, t in ((0.9, 0.2), (0.5, 0.1)):
        p = F(x + np.array([0.1, 0.1, h]))
        c = K.contact_segment_clearance(p, node, F(coords), F(segs), start, lst[:n_entries], t)
        assert abs(c - (h - t - 0.05 * diagonal)) < 1e-8


def _random_segments(rng: np.random.Generator) -> list[np.ndarray]:
    segments = [flat_quad(rng)[0] for _ in range(4)] + [warped_quad(rng, w) for w in (0.1, 0.25, 0.4)]
    triangle = flat_quad(rng)[0].copy()
    triangle[:, 3] = triangle[:, 2]
    return [*segments, F(triangle)]


@pytest.mark.parametrize("seed", range(4))
def test_distance_bound_is_below_the_true_distance(seed: int) -> None:
    """Reference: the dense numpy grid search of the distance from p to the segment (its square
    root, less the grid's resolution). On flat, warped and triangular segments, for points near
    and far, above the face and beyond edges and corners, the bound never exceeds it."""
    rng = np.random.default_rng(seed)
    for xseg in _random_segments(rng):
        centre = xseg.mean(axis=1)
        for scale in (0.3, 1.5, 5.0):
            for _ in range(6):
                p = centre + scale * rng.standard_normal(3)
                bound = K.contact_segment_distance_bound(xseg, F(p))
                d2, _, _ = grid_minimum(xseg, p, 201)
                assert 0.0 <= bound <= np.sqrt(d2) * (1 + 1e-9)


@pytest.mark.parametrize("seed", range(4))
def test_distance_bound_is_tight_above_a_flat_face_and_beyond_an_edge(seed: int) -> None:
    """Reference: construction. Above the interior of a flat quadrilateral the distance is the
    height h, and the bound is h (to 1e-8, its round-off allowance): the slab alone. Beyond edge 2-3 in the plane, at a
    distance s out, the bound is s (to 1e-8): the edge plane alone (so both parts do work)."""
    rng = np.random.default_rng(seed)
    xseg, n = flat_quad(rng)
    for _ in range(10):
        xi0, eta0 = rng.uniform(-0.9, 0.9, 2)
        h = rng.uniform(-1.0, 1.0)
        x0, _, _ = surface(xseg, xi0, eta0)
        assert abs(K.contact_segment_distance_bound(xseg, F(x0 + h * n)) - abs(h)) < 1e-8
    x2, x3 = xseg[:, 1], xseg[:, 2]
    outward = np.cross(x3 - x2, n)
    outward /= np.linalg.norm(outward)
    far = max(np.dot(outward, xseg[:, k] - x2) for k in range(4))
    for out in (0.1, 0.5, 2.0):
        p = 0.5 * (x2 + x3) + (far + out) * outward
        assert abs(K.contact_segment_distance_bound(xseg, F(p)) - out) < 1e-8


def test_segment_candidates_node_without_segments() -> None:
    """Reference: the definition (a node in no segment gives segment 0)."""
    coords = np.zeros((3, 5))
    coords[:, 1:] = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]).T
    segs = np.array([[2], [3], [4], [5]], dtype=np.int32)
    start, lst, _ = K.contact_node_segments(5, F(segs))
    seg, *_ = K.contact_segment_candidates(F(np.ones(3)), 1, F(coords), F(segs), start, lst)
    assert seg == 0
