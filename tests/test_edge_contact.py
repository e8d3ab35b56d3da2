"""Edge-to-edge contact kernels (issue 35 item 2; fortran/src/contact/force/edge_penalty.f90) through
the f2py wrappers (``paradyn._kernels``): the closest points of two segments against a brute-force
minimum, the penalty force against the analytic law, the conservation of linear and angular momentum
(the force lies along the line of the two closest points), and two thin plates crossing edge against
edge that the node-to-segment law does not see.
"""

from __future__ import annotations

import numpy as np
import pytest

from contact_kernel_cases import F
from paradyn import _kernels as K


def _closest_brute(a1, a2, b1, b2, n: int = 401) -> tuple[float, float, float]:
    """The smallest |P(s) - Q(u)| over an n x n grid of the unit square, then refined by a finer grid
    around it: (s, u, distance)."""
    s = np.linspace(0.0, 1.0, n)
    p = a1[None, :] + s[:, None] * (a2 - a1)[None, :]
    q = b1[None, :] + s[:, None] * (b2 - b1)[None, :]
    d = np.linalg.norm(p[:, None, :] - q[None, :, :], axis=2)
    i, j = np.unravel_index(np.argmin(d), d.shape)
    return float(s[i]), float(s[j]), float(d[i, j])


def test_closest_points_of_skew_segments_match_brute_force() -> None:
    """Reference: the minimum of |P(s) - Q(u)|^2 over the unit square (a convex quadratic), found by
    sampling: the kernel's distance is never above the sampled minimum and within the grid's error."""
    rng = np.random.default_rng(35)
    for _ in range(200):
        a1, a2, b1, b2 = (rng.uniform(-1.0, 1.0, 3) for _ in range(4))
        s, u = K.contact_edge_closest(a1, a2, b1, b2)
        assert 0.0 <= s <= 1.0 and 0.0 <= u <= 1.0
        distance = np.linalg.norm(a1 + s * (a2 - a1) - b1 - u * (b2 - b1))
        _, _, brute = _closest_brute(a1, a2, b1, b2)
        assert distance <= brute + 1e-12
        assert distance >= brute - 1e-2 * max(np.linalg.norm(a2 - a1), np.linalg.norm(b2 - b1))


def test_closest_points_of_crossing_edges_are_analytic() -> None:
    """Reference (analytic): the x-axis edge from (-1, 0, 0) to (3, 0, 0) and the edge along y at x = 1,
    z = -h from (1, -2, -h) to (1, 2, -h) are closest at s = 1/2, u = 1/2, a distance h apart."""
    s, u = K.contact_edge_closest(np.array([-1.0, 0, 0]), np.array([3.0, 0, 0]),
                                  np.array([1.0, -2, -0.3]), np.array([1.0, 2, -0.3]))
    assert s == pytest.approx(0.5, abs=1e-15) and u == pytest.approx(0.5, abs=1e-15)


def test_edge_force_is_the_penalty_law_and_conserves_momentum() -> None:
    """Reference: the penalty law f = k ((t_a + t_b) / 2 - |P - Q|) (P - Q) / |P - Q| on P, shared out
    by the segment parameters (analytic). Over random crossing pairs the four forces sum to zero and
    their moment sum_I x_I x f_I is zero (to round-off of the force's size times the coordinates)."""
    rng = np.random.default_rng(7)
    k, t_a, t_b = 3.0e7, 0.02, 0.04
    checked = 0
    for _ in range(400):
        centre = rng.uniform(-1.0, 1.0, 3)
        da, db = rng.standard_normal(3), rng.standard_normal(3)
        normal = np.cross(da, db)
        normal /= np.linalg.norm(normal)
        gap = rng.uniform(-0.01, 0.05)
        sa, sb = rng.uniform(0.2, 0.8, 2)
        a1 = centre - sa * da + 0.5 * gap * normal
        a2 = a1 + da
        b1 = centre - sb * db - 0.5 * gap * normal
        b2 = b1 + db
        force, penetration, touching = K.contact_edge_force(a1, a2, b1, b2, t_a, t_b, k)
        expected = 0.5 * (t_a + t_b) - abs(gap)
        if expected <= 0.0:
            assert touching == 0 and np.all(force == 0.0)
            continue
        checked += 1
        assert touching == 1
        assert penetration == pytest.approx(expected, rel=1e-9, abs=1e-13)
        size = k * penetration
        on_p = force[:, 0] + force[:, 1]
        assert np.linalg.norm(on_p) == pytest.approx(size, rel=1e-9)
        assert np.dot(on_p, normal) * np.sign(gap if gap != 0 else 1) > 0   # pushes a away from b
        assert np.abs(force.sum(axis=1)).max() <= 1e-14 * size
        x = np.stack([a1, a2, b1, b2], axis=1)
        moment = np.cross(x.T, force.T).sum(axis=0)
        assert np.abs(moment).max() <= 1e-13 * size * (1.0 + np.abs(x).max())
        s, u = K.contact_edge_closest(a1, a2, b1, b2)
        assert force[:, 1] == pytest.approx(s * on_p, rel=1e-12, abs=1e-12 * size)
        assert force[:, 3] == pytest.approx(-u * on_p, rel=1e-12, abs=1e-12 * size)
    assert checked > 100


def test_edges_meeting_end_on_or_parallel_are_left_to_node_to_segment() -> None:
    """An edge whose closest point is an end of the other edge (a node against an edge) and parallel
    edges are not edge crossings: no force here (node-to-segment contact with rounded edges has them)."""
    a1, a2 = np.array([0.0, 0, 0]), np.array([1.0, 0, 0])
    end_on = K.contact_edge_force(a1, a2, np.array([1.001, -1, 0]), np.array([1.001, 1, 0]), 0.01, 0.01, 1.0)
    parallel = K.contact_edge_force(a1, a2, np.array([0.2, 0, 0.001]), np.array([0.8, 0, 0.001]), 0.01, 0.01, 1.0)
    assert end_on[2] == 0 and parallel[2] == 0


def test_crossed_plates_edge_first_are_seen_by_edges_not_by_nodes() -> None:
    """Two thin plates crossed at right angles meet edge first: plate A hangs in the x-z plane with its
    lower edge along x, plate B stands in the y-z plane with its upper edge along y, the edges a
    distance 0.6 (t_a + t_b) / 2 apart at their midpoints. No node of either plate is within reach of
    the other's segment (node-to-segment with rounded edges finds no contact: every node is 0.5 from
    the crossing), while the edge pair carries a force of k times the penetration (analytic)."""
    t, k, h = 0.002, 1.0e6, 0.6 * 0.002
    plate_a = np.array([[-0.5, 0, 0], [0.5, 0, 0], [0.5, 0, 1.0], [-0.5, 0, 1.0]]).T + np.array([[0], [0], [h]])
    plate_b = np.array([[0, -0.5, -1.0], [0, 0.5, -1.0], [0, 0.5, 0], [0, -0.5, 0]]).T
    for p, seg in [(plate_a[:, i], plate_b) for i in range(4)] + [(plate_b[:, i], plate_a) for i in range(4)]:
        _, _, _, touching = K.contact_penalty_force(F(p), t, F(seg), t, k, rounded_edges=1)
        assert touching == 0
    force, penetration, touching = K.contact_edge_force(plate_a[:, 0], plate_a[:, 1], plate_b[:, 3],
                                                        plate_b[:, 2], t, t, k)
    assert touching == 1
    assert penetration == pytest.approx(t - h, rel=1e-12)
    assert force[:, 0] + force[:, 1] == pytest.approx([0.0, 0.0, k * (t - h)], rel=1e-12, abs=1e-9)
    assert force[2, 0] == pytest.approx(0.5 * k * (t - h), rel=1e-12)
