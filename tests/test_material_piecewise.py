"""The piecewise-linear members (material models "piecewise_linear", "piecewise_linear_rate";
LS-DYNA MAT_024) through the whole stack, and their scene keys.

Reference: uniaxial stress on the hardening curve, sigma = R(rate) k(eps_p) (tests/test_kernels_piecewise.py
checks the kernel to 1e-9). Each run is one square shell element of a scene built in Python,
driven as a material point at a constant logarithmic strain rate D in uniaxial stress, as in
tests/test_material_rate.py: once the flow is plastic the effective strain rate is D, so the flow
stress at the end is k(eps_p) times the rate factor at D. The multilinear curve rises 250 -> 300 ->
330 MPa at plastic strains 0, 0.01, 0.03 and extends along its last segment; a run at 1000 1/s
ends near eps_p = 0.027, on its second segment.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn import scene as scene_package
from test_material_rate import run_strip, stretch

SIZE, YOUNG, STRAIN = 0.01, 210e9, 0.03
CURVE = {"time": [0.0, 0.01, 0.03], "value": [250e6, 300e6, 330e6]}
MILD_STEEL = {"rate_c": 40.4, "rate_p": 5.0}   # Jones, Structural Impact: C 1/s, P
RATE_CURVE = {"time": [0.0, 100.0, 10000.0], "value": [1.0, 1.5, 2.5]}


def _hardening(eps_p: float) -> float:
    x, y = CURVE["time"], CURVE["value"]
    if eps_p > x[-1]:
        return y[-1] + (y[-1] - y[-2]) / (x[-1] - x[-2]) * (eps_p - x[-1])
    return float(np.interp(eps_p, x, y))


def _strip(rate: float, model: str, **material: object) -> paradyn.Scene:
    end = STRAIN / rate
    s = paradyn.Scene(f"{model} at {rate:g}/s", end_time=end, output_interval=end / 10)
    s.add_curve("hardening", **CURVE)
    s.add_curve("rates", **RATE_CURVE)
    s.add_material("steel", model=model, density=7850.0, youngs_modulus=YOUNG, poisson_ratio=0.3,
                   yield_stress=250e6, **material)
    return stretch(s, rate, end)


@pytest.mark.parametrize(("model", "options", "factor"), [
    ("piecewise_linear", {"hardening_curve": "hardening"}, 1.0),
    ("piecewise_linear_rate", {"hardening_curve": "hardening", **MILD_STEEL}, 1.0 + (1000.0 / 40.4) ** 0.2),
    ("piecewise_linear", {"hardening_curve": "hardening", "rate_curve": "rates"}, 1.5 + 1.0 * 900.0 / 9900.0),
])
def test_the_flow_stress_follows_the_curve_and_the_rate(tmp_path: Path, model: str, options: dict[str, object],
                                                         factor: float) -> None:
    """At 1000 1/s the flow stress is k(eps_p) times the static (1), Cowper-Symonds (2.90) or
    rate-curve (1.59) factor within 1 %, with eps_p on the curve's second segment; the rate
    changes the answer by the factor."""
    stress, eps_p = run_strip(_strip(1000.0, model, **options), tmp_path)
    assert 0.01 < eps_p[-1] < 0.03
    expected = factor * _hardening(float(eps_p[-1]))
    assert stress[-1, 0] == pytest.approx(expected, rel=0.01)
    assert abs(stress[-1, 1]) < 0.01 * expected


def test_the_bilinear_law_without_a_curve_is_j2_isotropic(tmp_path: Path) -> None:
    """No hardening curve: yield_stress and tangent_modulus (LS-DYNA's SIGY, ETAN) make the member
    j2_plasticity with beta = 1; every frame's stress within 1e-6 of the flow stress."""
    tangent = 2e9
    plain, plain_eps = run_strip(_strip(100.0, "j2_plasticity", tangent_modulus=tangent), tmp_path / "j2")
    curve, curve_eps = run_strip(_strip(100.0, "piecewise_linear", tangent_modulus=tangent), tmp_path / "pl")
    assert plain_eps[-1] > 0.02
    np.testing.assert_allclose(curve, plain, rtol=0.0, atol=1e-6 * 250e6)
    np.testing.assert_allclose(curve_eps, plain_eps, rtol=1e-6, atol=1e-9)


def _material(s: paradyn.Scene, name: str, model: str = "piecewise_linear", **options: object) -> None:
    s.add_material(name, model=model, density=1.0, youngs_modulus=1e9, poisson_ratio=0.3, yield_stress=1e6,
                   **options)


def test_the_keys_belong_to_their_models() -> None:
    """hardening_curve to the piecewise models, rate_curve to piecewise_linear (the Cowper-Symonds
    member takes rate_c, rate_p), hardening_mixing not to them (isotropic, as MAT_024)."""
    s = paradyn.Scene(end_time=1e-3, output_interval=1e-4)
    with pytest.raises(scene_package.SceneError, match=r"'hardening_curve' in \[\[material\]\] #1 'a' only applies "
                                                       r"to model = \"piecewise_linear\" or \"piecewise_linear_rate\""):
        _material(s, "a", model="j2_plasticity", hardening_curve="c")
    with pytest.raises(scene_package.SceneError, match=r"'rate_curve' .* only applies to model = \"piecewise_linear\""):
        _material(s, "b", model="piecewise_linear_rate", rate_curve="c", **MILD_STEEL)
    with pytest.raises(scene_package.SceneError, match=r"'hardening_mixing' .* only applies to model = "
                                                       r"\"j2_plasticity\" or \"j2_rate\""):
        _material(s, "c", hardening_mixing=0.5)
    with pytest.raises(scene_package.SceneError, match=r"'rate_c'"):
        _material(s, "d", model="piecewise_linear_rate", rate_p=5.0)


@pytest.mark.parametrize(("curve", "words"), [
    ({"time": [0.0, 0.1], "value": [2e6, 3e6]}, r"starts at \(0, 2e\+06\), not at zero plastic strain with "
                                                r"yield_stress = 1e\+06; start the curve at \(0, yield_stress\)"),
    ({"time": [0.01, 0.1], "value": [1e6, 3e6]}, r"starts at \(0.01, 1e\+06\)"),
    ({"time": [0.0, 0.1, 0.2], "value": [1e6, 3e6, 2e6]}, r"decreases to 2e\+06 at plastic strain 0.2; give a "
                                                           r"curve that never decreases"),
])
def test_a_bad_hardening_curve_is_refused(tmp_path: Path, curve: dict[str, list[float]], words: str) -> None:
    s = paradyn.Scene(end_time=1e-3, output_interval=1e-4)
    s.add_curve("k", **curve)
    _material(s, "m", hardening_curve="k")
    s.add_part("p", material="m", thickness=0.001, geometry=paradyn.Plate((0.01, 0.01), (1, 1)))
    label = r"'hardening_curve' = 'k' in \[\[material\]\] #1 'm' \(time = plastic strain, value = yield stress \(Pa\)\)"
    with pytest.raises(scene_package.SceneError, match=label + r": (the curve|the yield stress) " + words):
        s.build()


def test_a_bad_or_missing_rate_curve_is_refused() -> None:
    s = paradyn.Scene(end_time=1e-3, output_interval=1e-4)
    s.add_curve("r", time=[0.0, 10.0], value=[1.0, -1.0])
    _material(s, "m", rate_curve="r")
    s.add_part("p", material="m", thickness=0.001, geometry=paradyn.Plate((0.01, 0.01), (1, 1)))
    with pytest.raises(scene_package.SceneError, match=r"rates >= 0 and factors > 0, this one starts at rate 0 with "
                                                       r"least factor -1"):
        s.build()
    t = paradyn.Scene(end_time=1e-3, output_interval=1e-4)
    _material(t, "m", rate_curve="nothing")
    t.add_part("p", material="m", thickness=0.001, geometry=paradyn.Plate((0.01, 0.01), (1, 1)))
    with pytest.raises(scene_package.SceneError, match=r"'rate_curve' = 'nothing' .* names no \[\[curve\]\]"):
        t.build()
