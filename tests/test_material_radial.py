"""The j2_radial member (material/j2_radial_material.f90, plane_stress_returns'
j2_radial_update_points): j2_plasticity's law with the radial return without the plane-stress
iteration (OpenRadioss's shell default, Iplas = 2), a model choice for issue 35 item 6.

References: the radial return of J2 plasticity (Wilkins 1964; Simo & Hughes 1998, Box 3.2): the
plastic strain of an increment is d_eps_p = (|xi_trial| - k) / (3 G + H), and the relative stress is
scaled back along itself onto the hardened yield radius k + beta H d_eps_p. Here |.| is the von Mises
norm of the plane-stress relative stress xi = s - alpha, k = sigma_y0 + beta H eps_p.
"""

from __future__ import annotations

import numpy as np
import pytest

from kernel_cases import ET, NU, SY0, E, F, G, H
from paradyn import _kernels as K


def _von_mises(s: np.ndarray) -> np.ndarray:
    return np.sqrt(s[:, 0] ** 2 - s[:, 0] * s[:, 1] + s[:, 1] ** 2 + 3.0 * s[:, 2] ** 2)


def _states(m: int, seed: int = 3) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(seed)
    return (rng.uniform(-2e8, 2e8, (m, 3)), rng.uniform(-3e7, 3e7, (m, 3)), rng.uniform(0.0, 1e-2, m),
            rng.uniform(-1.5e-3, 1.5e-3, (m, 3)))


@pytest.mark.parametrize("beta", [1.0, 0.5, 0.0], ids=["isotropic", "mixed", "kinematic"])
def test_radial_return_lands_on_the_hardened_radius_along_the_trial(beta: float) -> None:
    stress0, back0, eps0, de = _states(300)
    s, b, e = F(stress0.copy()), F(back0.copy()), eps0.copy()
    K.j2_radial_points(s, b, e, F(de), E, NU, SY0, ET, beta)
    c = E / (1.0 - NU**2)
    trial = stress0 + c * np.column_stack([de[:, 0] + NU * de[:, 1], de[:, 1] + NU * de[:, 0],
                                           0.5 * (1.0 - NU) * de[:, 2]])
    xi_trial = trial - back0
    radius = SY0 + beta * H * eps0
    yielding = _von_mises(xi_trial) > radius
    assert 0.1 * len(eps0) < np.count_nonzero(yielding) < 0.9 * len(eps0)   # both kinds of point
    d_eps = (_von_mises(xi_trial) - radius) / (3.0 * G + H)
    np.testing.assert_allclose(e[yielding] - eps0[yielding], d_eps[yielding], rtol=1e-12)
    assert np.array_equal(e[~yielding], eps0[~yielding])
    np.testing.assert_allclose(s[~yielding], trial[~yielding], rtol=1e-14, atol=1e-6)
    xi = s - b
    hardened = radius + beta * H * (e - eps0)
    np.testing.assert_allclose(_von_mises(xi[yielding]), hardened[yielding], rtol=1e-12)
    # radial: the new relative stress is the trial's scaled, so their cross terms vanish
    unit_trial = xi_trial[yielding] / _von_mises(xi_trial[yielding])[:, None]
    unit_new = xi[yielding] / _von_mises(xi[yielding])[:, None]
    np.testing.assert_allclose(unit_new, unit_trial, atol=1e-12)
    # the back stress moves by (1 - beta) H d_eps_p along the trial
    np.testing.assert_allclose(b[yielding] - back0[yielding],
                               (1.0 - beta) * H * d_eps[yielding, None] * unit_trial, rtol=1e-9, atol=1e-6)


def test_radial_and_exact_returns_differ_off_the_radial_path() -> None:
    """The exact plane-stress return (j2_update_points) and the radial one agree where the flow is
    radial in the plane-stress stress space and differ where the plane-stress condition bends it: an
    equibiaxial trial (radial in both) gives the same stress; a pure-shear trial too; a uniaxial
    strain increment from a uniaxial state (the exact return's flow adds lateral contraction) does not."""
    def both(stress: list[float], de: list[float]) -> tuple[np.ndarray, np.ndarray]:
        out = []
        for kernel in (K.j2_update_points, K.j2_radial_points):
            s, b, e = F(np.array([stress], dtype=float)), F(np.zeros((1, 3))), np.zeros(1)
            kernel(s, b, e, F(np.array([de], dtype=float)), E, NU, SY0, 0.0, 1.0)
            out.append(s[0])
        return out[0], out[1]
    exact, radial = both([0.0, 0.0, 0.0], [2e-3, 2e-3, 0.0])
    np.testing.assert_allclose(radial, exact, rtol=1e-10, atol=1e-3)
    exact, radial = both([0.0, 0.0, 0.0], [0.0, 0.0, 4e-3])
    np.testing.assert_allclose(radial, exact, rtol=1e-10, atol=1e-3)
    exact, radial = both([SY0, 0.0, 0.0], [2e-3, 0.0, 0.0])
    assert np.abs(radial - exact).max() > 1e-3 * SY0


def test_a_scene_runs_the_radial_member(tmp_path) -> None:
    """model = "j2_radial" in a scene: the pipe whip on a 50 MPa steel to 1 ms runs with it and yields.
    Its internal energy stays within 2 % of the exact return's and differs from it (the returns
    differ only off the radial path); its plastic work is a quarter lower (measured 2.03 J exact,
    1.55 J radial): the 3-D multiplier 3 G + H counts less plastic strain than the plane-stress
    return does for the same drop of stress in a near-uniaxial state (E + H there)."""
    from pathlib import Path

    import paradyn
    from paradyn.scene import load_scene

    history = {}
    for model in ("j2_plasticity", "j2_radial"):
        scene = load_scene(Path(__file__).resolve().parents[1] / "cases" / "pipe_whip" / "scene.toml")
        for material in scene.materials:
            material.model = model
            material.yield_stress = 50e6         # yields within the first millisecond
        scene.run.end_time = 1.0e-3
        history[model] = paradyn.run(scene, tmp_path / model, ranks=1, threads=1, post=False).history
    exact, radial = (np.asarray(history[m]["internal_energy"]) for m in ("j2_plasticity", "j2_radial"))
    plastic = [float(np.asarray(history[m]["part_plastic_work"])[-1].sum()) for m in ("j2_plasticity", "j2_radial")]
    assert min(plastic) > 0.0
    assert plastic[1] < plastic[0]
    assert radial[-1] == pytest.approx(exact[-1], rel=0.02)
    assert radial[-1] != exact[-1]
