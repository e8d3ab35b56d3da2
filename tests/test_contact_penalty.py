"""Contact kernels (issue 4) of the contact forces, called through the f2py wrappers
(``paradyn._kernels``): penalty force between two-sided shells with thickness and regularised
Coulomb friction (Hallquist, Goudreau & Benson 1985; LS-DYNA Theory Manual; the force law is
fortran/src/contact/force/contact_penalty.f90). Each test names its reference in its docstring.

Node and segment numbers returned by the wrappers are 1-based. A segment is ``xseg[:, I]`` for
its nodes I = 0..3 at (xi, eta) = (-1, -1), (1, -1), (1, 1), (-1, 1).
"""

from __future__ import annotations

import numpy as np
import pytest

from contact_kernel_cases import F, flat_quad, shape, surface, warped_quad
from paradyn import _kernels as K

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
            f, _, pen, contact = K.contact_penalty_force(F(x0 + side * d * n), ts, xseg, tm, k)
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
        f, fm, _, _ = K.contact_penalty_force(F(p), ts, xseg, tm, k, F(vs), vm, mus, mud, decay, vslip)
        vt = np.array([vs[0], vs[1], 0.0])
        speed = np.linalg.norm(vt)
        mu = mud + (mus - mud) * np.exp(-decay * speed)
        ft = -mu * fn * vt / max(speed, vslip)
        np.testing.assert_allclose(f, ft + np.array([0, 0, fn]), rtol=1e-12)
        assert np.linalg.norm(f[:2]) <= mu * fn * (1 + 1e-12)
        if capped:
            assert np.linalg.norm(f[:2]) == pytest.approx(mu * fn, rel=1e-12)
        np.testing.assert_allclose(f + fm.sum(axis=1), 0, atol=1e-12 * fn)
    # the master's own velocity counts: moving the master with the slave leaves no slip
    vs = np.array([1.0, -0.5, 0.0])
    f, *_ = K.contact_penalty_force(F(p), ts, xseg, tm, k, F(vs), F(np.repeat(vs[:, None], 4, axis=1)),
                                    mus, mud, decay, vslip)
    np.testing.assert_allclose(f, [0, 0, fn], rtol=1e-12, atol=1e-12)
