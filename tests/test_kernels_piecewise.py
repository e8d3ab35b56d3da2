"""The piecewise-linear plasticity member (LS-DYNA MAT_024), its batch kernel through f2py.

Reference: uniaxial stress in J2 plasticity with isotropic hardening. On a monotonic uniaxial
path the plastic axial strain is the effective plastic strain, so at every step the stress is the
flow stress of the reached plastic strain and the total axial strain splits into its elastic and
plastic parts (Simo & Hughes, Computational Inelasticity, sec. 1.2 and 3.4; the plane-stress
return of the member is backward Euler, exact on a uniaxial path with any step):

    sigma = R(rate) k(eps_p),   eps = sigma / E + eps_p,

k the hardening curve (a polyline of eps_p, extrapolated along its last segment), R the rate
factor: 1 (static), 1 + (rate / C)^(1/P) (Cowper & Symonds 1957; C = 40.4 1/s, P = 5 for mild
steel, Jones, Structural Impact, ch. 8), or the rate curve's factor. The test knows the applied
strain increments, hence the effective strain rate sqrt(4/3 (d1^2 + d2^2 + d1 d2)) / dt the
member scales by; the expected (sigma, eps_p) solve the two relations above independently (a
scalar root). A formulation that missed a segment crossing, used the wrong slope, scaled only
sigma_y0 or took the rate as the axial one alone would miss by more than the 1e-9 tolerance.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kernel_cases import NU, E, F
from paradyn import _kernels as K

# a multilinear curve with a steeper segment after a flat one (the slope rises, then falls)
STRAIN = np.array([0.0, 0.01, 0.03, 0.08])
STRESS = np.array([250e6, 300e6, 330e6, 400e6])
MILD_STEEL = (40.4, 5.0)                      # Cowper-Symonds C (1/s), P
RATES = np.array([0.0, 10.0, 100.0, 1000.0])  # a rate curve: factor against strain rate (1/s)
FACTORS = np.array([1.0, 1.3, 1.8, 2.5])
NONE, COWPER_SYMONDS, TABULATED = 0, 1, 2


def _curve(eps_p: float) -> float:
    """k(eps_p): linear between the points, along the last segment beyond them."""
    j = min(max(int(np.searchsorted(STRAIN, eps_p, side="right")) - 1, 0), len(STRAIN) - 2)
    slope = (STRESS[j + 1] - STRESS[j]) / (STRAIN[j + 1] - STRAIN[j])
    return float(STRESS[j] + slope * (eps_p - STRAIN[j]))


def _factor(law: int, rate: float) -> float:
    if law == COWPER_SYMONDS:
        return 1.0 + (rate / MILD_STEEL[0]) ** (1.0 / MILD_STEEL[1])
    if law == TABULATED:
        return float(np.interp(rate, RATES, FACTORS))   # held beyond the ends
    return 1.0


class Point:
    """One material point of the member on a uniaxial stress path: each axial increment is paired
    with the lateral one that leaves syy = 0 (secant iteration, each trial from the converged state)."""

    def __init__(self, law: int = NONE, strain: np.ndarray = STRAIN, stress: np.ndarray = STRESS) -> None:
        self.law, self.strain_points, self.stress_points = law, strain, stress
        self.stress, self.eps_p, self.state = F(np.zeros((1, 3))), np.zeros(1), F(np.zeros((1, 1)))
        self.total = 0.0
        self.rate = 0.0

    def trial(self, de: float, dey: float, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        stress, eps_p, state = self.stress.copy(order="F"), self.eps_p.copy(), self.state.copy(order="F")
        c, p = MILD_STEEL
        K.piecewise_update_points(stress, eps_p, state, F([[de, dey, 0.0]]), dt, E, NU, self.strain_points,
                                  self.stress_points, self.law, c, p, RATES, FACTORS)
        return stress, eps_p, state

    def step(self, de: float, dt: float) -> None:
        guesses = [-NU * de, -0.5 * de]
        trials = [self.trial(de, d, dt) for d in guesses]
        for _ in range(60):
            (d0, d1), (g0, g1) = guesses[-2:], (trials[-2][0][0, 1], trials[-1][0][0, 1])
            if abs(g1) <= 1e-13 * abs(trials[-1][0][0, 0]) or g1 == g0:
                break
            guesses.append(d1 - g1 * (d1 - d0) / (g1 - g0))
            trials.append(self.trial(de, guesses[-1], dt))
        best = int(np.argmin([abs(t[0][0, 1]) for t in trials]))
        assert abs(trials[best][0][0, 1]) <= 1e-11 * abs(trials[best][0][0, 0])
        self.stress, self.eps_p, self.state = trials[best]
        dey = guesses[best]
        self.rate = math.sqrt(4.0 / 3.0 * (de**2 + dey**2 + de * dey)) / dt
        self.total += de

    @property
    def sigma(self) -> float:
        return float(self.stress[0, 0])


def _expected(total: float, factor: float) -> tuple[float, float]:
    """(sigma, eps_p) of uniaxial stress at total axial strain ``total`` on the scaled curve."""
    if total * E <= factor * _curve(0.0):
        return total * E, 0.0
    lo, hi = 0.0, total   # the residual total - sigma / E - eps_p decreases in eps_p: bisection
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if total - factor * _curve(mid) / E - mid > 0.0 else (lo, mid)
    return factor * _curve(lo), lo


def test_the_break_points_of_a_multilinear_curve_are_hit() -> None:
    """Static curve, driven in 20 steps to each break point's total strain s_j / E + e_j: the stress
    is s_j and the plastic strain e_j within 1e-9, the point on segment j (its state word)."""
    point = Point()
    for j in range(1, len(STRAIN)):
        target = STRESS[j] / E + STRAIN[j]
        for _ in range(20):
            point.step((target - point.total) / 20 if _ < 19 else target - point.total, 1e-6)
        assert point.sigma == pytest.approx(STRESS[j], rel=1e-9)
        assert point.eps_p[0] == pytest.approx(STRAIN[j], rel=1e-9)
        assert int(point.state[0, 0]) in (j - 1, min(j, len(STRAIN) - 2))   # on the break: either side


def test_one_step_across_several_segments_lands_on_the_curve() -> None:
    """One step from rest to eps_p near 0.05 crosses three break points (the return runs again on
    each next segment from the same trial): the answer is the curve's, within 1e-9."""
    point = Point()
    total = 0.05 + _curve(0.05) / E
    point.step(total, 1e-6)
    sigma, eps_p = _expected(total, 1.0)
    assert point.sigma == pytest.approx(sigma, rel=1e-9)
    assert point.eps_p[0] == pytest.approx(eps_p, rel=1e-9)
    assert int(point.state[0, 0]) == 2


def test_beyond_the_last_point_the_last_segment_extends() -> None:
    """eps_p = 0.2, past the last point (0.08): the stress follows the last segment's line
    (LS-DYNA's extrapolation), 400 MPa + 1.4 GPa x 0.12 = 568 MPa."""
    point = Point()
    total = 0.2 + 568e6 / E
    for _ in range(50):
        point.step(total / 50, 1e-6)
    assert point.sigma == pytest.approx(568e6, rel=1e-9)
    assert point.eps_p[0] == pytest.approx(0.2, rel=1e-9)


@pytest.mark.parametrize(("law", "rate"), [(NONE, 100.0), (COWPER_SYMONDS, 1.0), (COWPER_SYMONDS, 100.0),
                                           (COWPER_SYMONDS, 1000.0), (TABULATED, 5.0), (TABULATED, 300.0),
                                           (TABULATED, 5000.0)])
def test_the_flow_stress_is_the_curve_times_the_rate_factor(law: int, rate: float) -> None:
    """A constant axial strain rate to eps = 6 %: at every plastic step sigma = R(rate) k(eps_p) and
    eps = sigma / E + eps_p within 1e-9 (Cowper-Symonds factors 1.48, 2.20, 2.90 at 1, 100, 1000 1/s;
    the rate curve interpolated at 5 and 300 1/s, held at 2.5 beyond 1000 1/s)."""
    point = Point(law)
    steps = 60
    dt = 0.06 / steps / rate
    plastic = 0
    for _ in range(steps):
        point.step(0.06 / steps, dt)
        if point.eps_p[0] > 0.0:
            plastic += 1
            factor = _factor(law, point.rate)
            assert point.sigma == pytest.approx(factor * _curve(point.eps_p[0]), rel=1e-9)
            assert point.total == pytest.approx(point.sigma / E + point.eps_p[0], rel=1e-9)
    assert plastic > steps // 2
    sigma, eps_p = _expected(point.total, _factor(law, point.rate))
    assert point.sigma == pytest.approx(sigma, rel=1e-9) and point.eps_p[0] == pytest.approx(eps_p, rel=1e-9)
    if law == COWPER_SYMONDS:   # the published factors of mild steel at these rates
        assert _factor(law, point.rate) == pytest.approx({1.0: 1.476, 100.0: 2.198, 1000.0: 2.899}[rate], abs=2e-3)
    if law == TABULATED and rate > 1000.0:
        assert _factor(law, point.rate) == 2.5


def test_a_bilinear_curve_is_isotropic_j2() -> None:
    """The two points (0, sigma_y0), (1, sigma_y0 + H) (LS-DYNA's ETAN, H = E Et / (E - Et)) give
    the J2 member's answer with beta = 1 on a general (biaxial and shear) path, within 1e-12."""
    sy0, et = 250e6, 2e9
    h = E * et / (E - et)
    rng = np.random.default_rng(7)
    m = 40
    increments = F(rng.normal(scale=4e-4, size=(m, 3)))
    stress_a, stress_b = F(np.zeros((m, 3))), F(np.zeros((m, 3)))
    eps_a, eps_b, state, back = np.zeros(m), np.zeros(m), F(np.zeros((m, 1))), F(np.zeros((m, 3)))
    for _ in range(15):
        K.piecewise_update_points(stress_a, eps_a, state, increments, 1e-6, E, NU, np.array([0.0, 1.0]),
                                  np.array([sy0, sy0 + h]), NONE, 1.0, 1.0, RATES, FACTORS)
        K.j2_update_points(stress_b, back, eps_b, increments, E, NU, sy0, et, 1.0)
    assert eps_b.max() > 0.003
    np.testing.assert_allclose(stress_a, stress_b, rtol=0.0, atol=1e-12 * sy0 * 10)
    np.testing.assert_allclose(eps_a, eps_b, rtol=1e-11, atol=1e-15)


def test_the_dissipated_work_is_the_area_under_the_curve() -> None:
    """W(eps_p) = integral of k from 0 to eps_p, by the trapezoids of the polyline (and the last
    segment's line beyond it): at 0, 0.005, a break point and past the end, within 1e-12."""
    eps = np.array([0.0, 0.005, 0.03, 0.2])
    work = K.piecewise_dissipated_work(eps, STRAIN, STRESS)
    fine = [sum(e / 4000 * _curve((k + 0.5) * e / 4000) for k in range(4000)) for e in eps]   # midpoint rule
    expected = [0.0, 0.005 * 0.5 * (250e6 + 275e6), 0.01 * 275e6 + 0.02 * 315e6,
                0.01 * 275e6 + 0.02 * 315e6 + 0.05 * 365e6 + 0.12 * 484e6]
    np.testing.assert_allclose(work, expected, rtol=1e-12, atol=1e-3)
    np.testing.assert_allclose(work, fine, rtol=1e-6, atol=1e-3)
