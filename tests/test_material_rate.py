"""The rate-dependent J2 member (material model "j2_rate"): Cowper-Symonds scaling of the yield radius.

Reference: the Cowper-Symonds law, sigma_y(rate) = sigma_y0 (1 + (rate / C)^(1/P)), with the
published constants of mild steel, C = 40.4 1/s and P = 5 (Jones, Structural Impact, ch. 8;
LS-DYNA MAT_003's SRC and SRP). Each run is one square shell element of a scene built in Python
(paradyn.Scene -> deck -> engine), driven as a material point at a constant logarithmic strain
rate D in uniaxial stress: every node's in-plane velocity is prescribed, the far edge along x at
D L0 exp(D t), the far edge along y at -D/2 W0 exp(-D t / 2) (the contraction of incompressible
plastic flow), the near edges held, the out-of-plane dofs fixed. Once the flow is plastic the
stress tends to uniaxial (syy -> 0, the flow direction of plane-stress J2 being that of the
prescribed rate), and the effective strain rate the member computes equals D.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn import scene as scene_package

MILD_STEEL = {"rate_c": 40.4, "rate_p": 5.0}   # Jones, Structural Impact: C 1/s, P
SIZE = 0.01          # m, the element's side
YIELD = 250e6        # Pa
YOUNG = 210e9        # Pa
STRAIN = 0.03        # the axial logarithmic strain at the end of a run


def _strip(rate: float, model: str, **material: float) -> paradyn.Scene:
    end = STRAIN / rate
    s = paradyn.Scene(f"{model} at {rate:g}/s", end_time=end, output_interval=end / 10)
    s.add_material("steel", model=model, density=7850.0, youngs_modulus=YOUNG, poisson_ratio=0.3,
                   yield_stress=YIELD, **material)
    return stretch(s, rate, end)


def stretch(s: paradyn.Scene, rate: float, end: float) -> paradyn.Scene:
    """A one-element strip of the scene's "steel" stretched along x at a constant logarithmic
    strain rate (prescribed edge velocities on exponential curves), free to narrow as plasticity
    wants (the edge y = SIZE at half the rate): a uniaxial stress path to the end time."""
    s.add_part("strip", material="steel", thickness=0.001, integration_points=3,
               geometry=paradyn.Plate((SIZE, SIZE), (1, 1)))
    lo, hi = -1e-6, SIZE + 1e-6
    s.add_fix("strip", box=[[lo, lo, -1.0], [hi, hi, 1.0]], dofs=["uz", "rotations"])
    s.add_fix("strip", box=[[lo, lo, -1.0], [1e-6, hi, 1.0]], dofs=["ux"])
    s.add_fix("strip", box=[[lo, lo, -1.0], [hi, 1e-6, 1.0]], dofs=["uy"])
    times = np.linspace(0.0, end, 11)
    s.add_curve("stretch", time=times.tolist(), value=np.exp(rate * times).tolist())
    s.add_curve("narrow", time=times.tolist(), value=np.exp(-0.5 * rate * times).tolist())
    s.add_prescribe("strip", box=[[SIZE - 1e-6, lo, -1.0], [hi, hi, 1.0]], dof="ux", value=rate * SIZE,
                    curve="stretch")
    s.add_prescribe("strip", box=[[lo, SIZE - 1e-6, -1.0], [hi, hi, 1.0]], dof="uy", value=-0.5 * rate * SIZE,
                    curve="narrow")
    return s


def run_strip(s: paradyn.Scene, out: Path) -> tuple[np.ndarray, np.ndarray]:
    """The element's membrane stress (sxx, syy, sxy) and its plastic strain, frame by frame."""
    res = paradyn.run(s, out, ranks=1, threads=1, post=False)
    assert isinstance(res, paradyn.Results)
    return np.asarray(res.membrane_stress.read_all())[:, 0, :], np.asarray(res.plastic_strain.read_all())[:, 0]


def _scale(rate: float, rate_c: float, rate_p: float) -> float:
    return 1.0 + (rate / rate_c) ** (1.0 / rate_p)


@pytest.mark.parametrize("rate", [1.0, 100.0, 1000.0])
def test_flow_stress_is_the_cowper_symonds_stress(tmp_path: Path, rate: float) -> None:
    """Perfect plasticity: the flow stress is sigma_y (1 + (D / C)^(1/P)) within 1 % (factors
    1.48, 2.20, 2.90 at 1, 100, 1000 1/s), the stress uniaxial."""
    stress, eps_p = run_strip(_strip(rate, "j2_rate", **MILD_STEEL), tmp_path)
    expected = YIELD * _scale(rate, **MILD_STEEL)
    assert eps_p[-1] > 0.02
    assert stress[-1, 0] == pytest.approx(expected, rel=0.01)
    assert abs(stress[-1, 1]) < 0.01 * expected and abs(stress[-1, 2]) < 0.01 * expected


def test_hardening_yield_radius_is_scaled(tmp_path: Path) -> None:
    """Linear isotropic hardening: the whole radius sigma_y0 + H eps_p is scaled, H = E Et / (E - Et)."""
    tangent, rate = 2e9, 100.0
    stress, eps_p = run_strip(_strip(rate, "j2_rate", tangent_modulus=tangent, **MILD_STEEL), tmp_path)
    h = YOUNG * tangent / (YOUNG - tangent)
    expected = (YIELD + h * eps_p[-1]) * _scale(rate, **MILD_STEEL)
    assert stress[-1, 0] == pytest.approx(expected, rel=0.01)
    assert stress[-1, 0] > YIELD * _scale(rate, **MILD_STEEL) * 1.1   # the hardening is there


def test_far_below_c_it_is_j2_plasticity(tmp_path: Path) -> None:
    """D / C = 1e-20 (C = 1e22 1/s at 100 1/s, P = 5: a factor 1 + 1e-4): every frame's stress
    and plastic strain are those of j2_plasticity within 1e-3 (of the flow stress)."""
    rate = 100.0
    options = {"tangent_modulus": 1e9, "hardening_mixing": 0.5}
    slow, slow_eps = run_strip(_strip(rate, "j2_rate", rate_c=1e22, rate_p=5.0, **options), tmp_path / "rate")
    plain, plain_eps = run_strip(_strip(rate, "j2_plasticity", **options), tmp_path / "plain")
    assert plain_eps[-1] > 0.02
    np.testing.assert_allclose(slow, plain, rtol=0.0, atol=1e-3 * YIELD)
    np.testing.assert_allclose(slow_eps, plain_eps, rtol=1e-3, atol=1e-6)


def test_the_rate_keys_belong_to_j2_rate() -> None:
    """rate_c and rate_p are [[material]] keys of j2_rate alone (schema: checked_when strain_rate),
    required there, and bounded (> 0)."""
    s = paradyn.Scene(end_time=1e-3, output_interval=1e-4)
    with pytest.raises(scene_package.SceneError, match=r"'rate_c' in \[\[material\]\] #1 'a' only applies to "
                                                       r"model = \"j2_rate\""):
        s.add_material("a", model="j2_plasticity", density=1.0, youngs_modulus=1.0, poisson_ratio=0.3,
                       yield_stress=0.1, rate_c=40.4)
    with pytest.raises(scene_package.SceneError, match=r"'rate_p' in \[\[material\]\] #1 'b'"):
        s.add_material("b", model="j2_rate", density=1.0, youngs_modulus=1.0, poisson_ratio=0.3,
                       yield_stress=0.1, rate_c=40.4, rate_p=0.0)
    with pytest.raises(scene_package.SceneError, match=r"'rate_c'"):
        s.add_material("c", model="j2_rate", density=1.0, youngs_modulus=1.0, poisson_ratio=0.3,
                       yield_stress=0.1, rate_p=5.0)
    s.add_material("d", model="j2_rate", density=1.0, youngs_modulus=1.0, poisson_ratio=0.3,
                   yield_stress=0.1, **MILD_STEEL)
