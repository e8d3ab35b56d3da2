"""J2 plasticity kernels (plane stress), called through the f2py wrappers (``paradyn._kernels``).

Each test names the reference it checks against in its docstring. Real arrays passed to the
wrappers are float64 and Fortran-ordered; ``intent(inout)`` arrays are updated in place.

Constants shared with the other kernel tests are in ``tests/kernel_cases.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kernel_cases import C_PLANE, ET, NU, SY0, E, F, G, H
from paradyn import _kernels as K

# ------------------------------------------------------------------------------------------------
# J2 plasticity, plane stress, driven along a uniaxial stress path


def _von_mises(s: np.ndarray) -> float:
    return math.sqrt(s[0] ** 2 - s[0] * s[1] + s[1] ** 2 + 3.0 * s[2] ** 2)


class UniaxialPoint:
    """One J2 material point driven along a uniaxial stress path sigma = (s, 0, 0).

    The routine takes in-plane strain increments, so each axial increment ``de`` is paired with
    the lateral increment that leaves syy = 0 after the update, found by secant iteration from
    the elastic guess -nu de (each trial restarts from the converged state).
    """

    def __init__(self, beta: float, tangent: float = ET) -> None:
        self.beta = beta
        self.tangent = tangent
        self.stress = np.zeros(3)
        self.back = np.zeros(3)
        self.eps_p = np.array(0.0)   # rank-0 in/out argument: a 0-d array, updated in place
        self.strain = 0.0            # total axial strain

    def trial(self, de: float, dey: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        stress, back, eps_p = self.stress.copy(), self.back.copy(), np.array(float(self.eps_p))
        K.j2_update(stress, back, eps_p, np.array([de, dey, 0.0]), E, NU, SY0, self.tangent, self.beta)
        return stress, back, eps_p

    def step(self, de: float) -> None:
        scale = max(abs(self.sigma), SY0)
        guesses = [-NU * de, -NU * de * (1.0 + 1e-3) if de != 0.0 else 1e-12]
        trials = [self.trial(de, d) for d in guesses]
        for _ in range(60):
            (d0, d1), (g0, g1) = guesses[-2:], (trials[-2][0][1], trials[-1][0][1])
            if abs(g1) <= 1e-14 * scale or abs(trials[0][0][1]) <= 1e-14 * scale or g1 == g0:
                break
            guesses.append(d1 - g1 * (d1 - d0) / (g1 - g0))
            trials.append(self.trial(de, guesses[-1]))
        best = min(trials, key=lambda trial: abs(trial[0][1]))
        assert abs(best[0][1]) <= 1e-12 * scale, "lateral strain iteration did not reach syy = 0"
        self.stress, self.back, self.eps_p = best
        self.strain += de

    @property
    def sigma(self) -> float:
        return float(self.stress[0])


def _load(point: UniaxialPoint, strain_target: float, de: float) -> list[tuple[float, float, float]]:
    """Increments of ``de`` up to ``strain_target``; returns (strain, sigma, eps_p) after each."""
    path = []
    n = round((strain_target - point.strain) / de)
    for _ in range(n):
        point.step(de)
        path.append((point.strain, point.sigma, float(point.eps_p)))
    return path


def test_j2_uniaxial_elastic_slope_yield_point_and_hardening_slope() -> None:
    """Reference: the bilinear uniaxial stress-strain curve of linear isotropic hardening
    (Simo & Hughes, Computational Inelasticity, sec. 1.4 and 3.4): slope E up to sigma = sy0,
    then dsigma/deps = Et and dsigma/deps_p = H = E Et / (E - Et); eps_p = eps - sigma / E."""
    point = UniaxialPoint(beta=1.0)
    de = 1e-5
    eps_yield = SY0 / E                                   # 1.25e-3, a whole number of increments
    path = np.array(_load(point, 3 * eps_yield, de))
    strain, sigma, eps_p = path.T

    elastic = strain <= eps_yield * (1 + 1e-12)
    assert np.all(eps_p[elastic] == 0.0)
    np.testing.assert_allclose(np.diff(np.r_[0.0, sigma[elastic]]) / de, E, rtol=1e-9)
    yield_index = int(np.flatnonzero(elastic)[-1])
    assert sigma[yield_index] == pytest.approx(SY0, rel=1e-12)    # the yield point itself
    assert eps_p[yield_index + 1] > 0.0                            # and flow right after it

    plastic = ~elastic
    slope = np.diff(sigma[yield_index:]) / np.diff(strain[yield_index:])
    np.testing.assert_allclose(slope, ET, rtol=1e-6)
    plastic_slope = np.diff(sigma[plastic]) / np.diff(eps_p[plastic])
    np.testing.assert_allclose(plastic_slope, H, rtol=1e-6)

    # on the yield surface after every plastic step (isotropic: radius sy0 + H eps_p, no back stress)
    for s, ep in zip(sigma[plastic], eps_p[plastic], strict=True):
        assert abs(s) == pytest.approx(SY0 + H * ep, rel=1e-9)
    # plastic strain consistency: eps_p = total axial strain - sigma / E
    np.testing.assert_allclose(eps_p, strain - sigma / E, rtol=0, atol=1e-9)


@pytest.mark.parametrize("beta", [0.0, 0.5, 1.0])
def test_j2_returned_stress_lies_on_the_yield_surface(beta: float) -> None:
    """Reference: consistency of the return mapping (Simo & Hughes sec. 3.4): after a plastic
    update, von Mises(sigma - alpha) = sy0 + beta H eps_p, for uniaxial steps and for large
    random plane-stress strain increments."""
    point = UniaxialPoint(beta=beta)
    path = _load(point, 4e-3, 2e-5)
    assert path[-1][2] > 0
    xi = point.stress - point.back
    assert _von_mises(xi) == pytest.approx(SY0 + beta * H * float(point.eps_p), rel=1e-9)

    rng = np.random.default_rng(12)
    stress, back, eps_p = np.zeros(3), np.zeros(3), np.array(0.0)
    plastic_steps = 0
    for _ in range(200):
        de = rng.uniform(-1.0, 1.0, 3) * 1.5e-3
        before = float(eps_p)
        K.j2_update(stress, back, eps_p, de, E, NU, SY0, ET, beta)
        if float(eps_p) > before:
            plastic_steps += 1
            radius = SY0 + beta * H * float(eps_p)
            assert _von_mises(stress - back) == pytest.approx(radius, rel=1e-9)
        else:
            assert _von_mises(stress - back) <= (SY0 + beta * H * float(eps_p)) * (1 + 1e-12)
    assert plastic_steps > 50




@pytest.mark.parametrize("beta", [
    0.0,
    0.5,
])
def test_j2_uniaxial_hardening_slope_with_kinematic_hardening(beta: float) -> None:
    """Reference: J2 flow with linear combined hardening and Prager's rule (Simo & Hughes sec. 1.5
    and 2.3.2) gives, under uniaxial stress, the same bilinear curve for every beta: slope Et
    after yield, dsigma/deps_p = H = E Et / (E - Et) (docs/formats.md: Et is the tangent modulus)."""
    point = UniaxialPoint(beta=beta)
    path = np.array(_load(point, 3 * SY0 / E, 1e-5))
    strain, sigma, eps_p = path.T
    plastic = eps_p > 0
    np.testing.assert_allclose(np.diff(sigma[plastic]) / np.diff(strain[plastic]), ET, rtol=1e-6)
    np.testing.assert_allclose(np.diff(sigma[plastic]) / np.diff(eps_p[plastic]), H, rtol=1e-6)


@pytest.mark.parametrize("beta", [
    0.0,
    0.5,
    1.0,
])
def test_j2_reverse_yield_bauschinger(beta: float) -> None:
    """Reference: uniaxial load reversal under linear combined hardening (Simo & Hughes sec. 1.5):
    after loading to sigma_max with plastic strain eps_p, the elastic range is
    2 (sy0 + beta H eps_p), so re-yield happens at sigma_max - 2 (sy0 + beta H eps_p):
    sigma_max - 2 sy0 for kinematic (beta = 0), -sigma_max for isotropic (beta = 1). The
    unloading is bracketed to 1e-7 of the elastic range on either side of that point."""
    point = UniaxialPoint(beta=beta)
    _load(point, 5e-3, 2e-5)
    sigma_max, eps_p = point.sigma, float(point.eps_p)
    assert eps_p > 1e-3
    elastic_range = 2.0 * (SY0 + beta * H * eps_p)
    expected = sigma_max - elastic_range
    if beta == 0.0:
        assert expected == pytest.approx(sigma_max - 2 * SY0, rel=1e-12)
    if beta == 1.0:
        assert expected == pytest.approx(-sigma_max, rel=1e-9)

    unload = -elastic_range / E       # the elastic strain range back to the re-yield point
    inside = UniaxialPoint(beta)
    outside = UniaxialPoint(beta)
    for p in (inside, outside):
        p.stress, p.back, p.eps_p, p.strain = point.stress.copy(), point.back.copy(), \
            np.array(eps_p), point.strain
    inside.step(unload * (1 - 1e-7))
    outside.step(unload * (1 + 1e-7))
    assert float(inside.eps_p) == eps_p, "re-yielded too early"
    assert inside.sigma == pytest.approx(expected, rel=1e-6)
    assert float(outside.eps_p) > eps_p, "did not re-yield"
    assert outside.sigma == pytest.approx(expected, rel=1e-6)


def test_j2_elastic_shear_and_biaxial_increments() -> None:
    """Reference: plane-stress Hooke's law with engineering shear strain, below yield:
    dsxx = E/(1-nu^2) (dexx + nu deyy), dsyy = E/(1-nu^2) (deyy + nu dexx), dsxy = G dgxy."""
    stress, back, eps_p = np.zeros(3), np.zeros(3), np.array(0.0)
    de = np.array([2e-4, -1e-4, 3e-4])
    K.j2_update(stress, back, eps_p, de, E, NU, SY0, ET, 1.0)
    expected = [C_PLANE * (de[0] + NU * de[1]), C_PLANE * (de[1] + NU * de[0]), G * de[2]]
    np.testing.assert_allclose(stress, expected, rtol=1e-14)
    assert float(eps_p) == 0.0 and np.all(back == 0.0)



# ------------------------------------------------------------------------------------------------
# the vectorised return mapping: a point's result must not depend on its batch


def test_j2_points_match_the_scalar_return_and_do_not_depend_on_their_neighbours() -> None:
    """Reference: j2_update (the scalar return mapping, checked against closed forms above).
    The array form used by the element kernel runs the same algorithm across points: 200 random
    states and increments, about half yielding, agree with the scalar return to round-off, and a
    point's result is bitwise the same in any batch (whole, alone, shifted)."""
    rng = np.random.default_rng(5)
    m = 200
    stress0 = rng.uniform(-2e8, 2e8, (m, 3))
    back0 = rng.uniform(-3e7, 3e7, (m, 3))
    eps0 = rng.uniform(0.0, 1e-2, m)
    de = rng.uniform(-1.5e-3, 1.5e-3, (m, 3))

    def batch(sl: slice) -> tuple[np.ndarray, ...]:
        s, b, e = F(stress0[sl].copy()), F(back0[sl].copy()), eps0[sl].copy()
        K.j2_update_points(s, b, e, F(de[sl]), E, NU, SY0, ET, 0.5)
        return s, b, e

    s_all, b_all, e_all = batch(slice(0, m))
    yielded = e_all > eps0
    assert 0.2 * m < np.count_nonzero(yielded) < 0.8 * m
    for i in range(m):
        s, b, e = stress0[i].copy(), back0[i].copy(), np.array(eps0[i])
        K.j2_update(s, b, e, de[i], E, NU, SY0, ET, 0.5)
        np.testing.assert_allclose(s_all[i], s, rtol=1e-12, atol=1e-12 * SY0)
        np.testing.assert_allclose(b_all[i], b, rtol=1e-12, atol=1e-12 * SY0)
        assert float(e_all[i]) == pytest.approx(float(e), rel=1e-12, abs=1e-18)
    for sl in (slice(3, 4), slice(1, 66), slice(70, 200), slice(131, 140)):
        s, b, e = batch(sl)
        assert np.array_equal(s, s_all[sl]) and np.array_equal(b, b_all[sl]) and np.array_equal(e, e_all[sl])
