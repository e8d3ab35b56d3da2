"""The nodal rotary inertia of shells as a part option (issue 35, item 6; docs/theory.md, "Mass
and time step"): ``rotary_inertia = "scaled"`` (the default, I = m (t^2 + A) / 4 per node share m,
after Key & Beisinger 1971 and Hughes, Liu & Levit 1981), ``"radioss"`` (I = m (t^2 + A) / 12,
OpenRadioss's rule for its QBAT and QEPH shells: starter cinmas, m (A / 12 + t^2 / 12)) or
``"physical"`` (I = m t^2 / 12, the section's own, with the step capped at 2 t / (sqrt(5 (1 - nu)) c)).

- the option reaches the nodes: a free flat mesh spun at a uniform angular velocity has the
  kinetic energy 1/2 w^2 sum I, the sum over its elements of rho t A (t^2 + A) / 4 (or / 12);
- a thin plate's first bending frequency does not depend on it (the rotary inertia of a thin
  plate is of order (t / L)^2 in bending: Timoshenko's beam, Leissa's plates);
- a run with it stays stable at its own automatic step (energy balance) for any Poisson's ratio;
- scenes and the study knob carry it, and the default deck is unchanged.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import models as M
import test_verification as V
from paradyn import _schema
from paradyn.deck import Control
from paradyn.scene import SceneError, load_scene
from paradyn.scene.building import build_model
from paradyn.studies.design import KNOBS
from test_triangles import split

RULES = dict(_schema.ENUMS["rotary_inertia"])
DIVISOR = {"scaled": 4.0, "radioss": 12.0, "physical": 12.0}
ROOT = Path(__file__).resolve().parents[1]


def _with_rule(model: M.Model, rule: str) -> M.Model:
    if rule != "scaled":
        model.rotary_inertia = np.array([RULES[rule]], dtype=np.int32)
    return model


def _element_areas(mesh: M.geometry.Mesh) -> np.ndarray:
    """Area of each element of a flat mesh in the x-y plane (a triangle repeats its third node)."""
    x = mesh.coordinates[mesh.quads]
    d1 = x[:, 2] - x[:, 0]
    d2 = x[:, 3] - x[:, 1]
    return 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


@pytest.mark.parametrize("rule", ["scaled", "radioss", "physical"])
@pytest.mark.parametrize("shape", ["blt", "full", "triangles"])
def test_spun_mesh_carries_the_rule_inertia(tmp_path, rule, shape):
    """Reference: the rule's formula summed over the elements. Each element of area A gives each of
    its nodes (4, or 3 for a triangle) its share m = rho t A / 4 (/ 3) and the inertia
    m (t^2 + A) / 4 (scaled), m (t^2 + A) / 12 (radioss) or m t^2 / 12 (physical), so the nodes
    hold sum_e rho t A (t^2 + A) / d, d = 4 or 12 (t^2 alone for physical), about each axis. A
    free flat 6 x 4 mesh (1.2 x 0.8 m, t = 0.02 m, steel) with no translation and w = 3 rad/s about
    z at every node has the kinetic energy 1/2 w^2 times that sum at the start (first history
    record, before any force acts). Tolerance 1e-9: the rules differ by factors of 3 and more, a
    rule that did not reach the engine fails by 200 %."""
    mesh = M.strip(1.2, 0.8, 6, 4)
    if shape == "triangles":
        mesh = split(mesh)
    t, w = 0.02, 3.0
    spin = np.zeros((mesh.n_nodes, 3))
    spin[:, 2] = w
    control = Control(end_time=5e-6, output_interval=5e-6, history_interval=1e-6)
    model = M.shell_model(mesh, t, V.STEEL, control, angular_velocity=spin,
                          element="full" if shape == "full" else "blt")
    h = M.run(_with_rule(model, rule), tmp_path).results.history
    area = _element_areas(mesh)
    arm = t**2 + (0.0 if rule == "physical" else area)
    inertia = np.sum(V.STEEL.density * t * area * arm) / DIVISOR[rule]
    assert h["time"][0] == 0.0
    assert h["kinetic_energy"][0] == pytest.approx(0.5 * w**2 * inertia, rel=1e-9)


def test_thin_strip_first_frequency_does_not_depend_on_the_rule(tmp_path):
    """Reference: f1 = (1.8751^2 / 2 pi) sqrt(E I / (m L^4)) = 8.154 Hz (Euler-Bernoulli;
    Timoshenko, Vibration Problems in Engineering); the rotary inertia of the section changes it
    by a term of order (t / L)^2 = 1e-4 (Timoshenko beam; Leissa, Vibration of Plates, for thin
    plates). The 20 x 2 cantilever strip of test_verification (t / L = 1 / 100), released in its
    first mode: with each rule within 2 % of f1 (the verification test's tolerance) and the other
    rules within 1 % of the default's."""
    measured = {}
    for rule in ("scaled", "radioss", "physical"):
        beam = M.cantilever(V.STEEL_NU0)
        f1 = beam.first_frequency
        period = 1.0 / f1
        x = beam.mesh.coordinates[:, 0]
        phi, slope = M.cantilever_mode(x, beam.length)
        v0 = 1.0e-3 * 2.0 * np.pi * f1
        velocity = np.zeros((beam.mesh.n_nodes, 3))
        velocity[:, 2] = v0 * phi
        spin = np.zeros((beam.mesh.n_nodes, 3))
        spin[:, 1] = -v0 * slope
        control = Control(end_time=3.0 * period, output_interval=period, history_interval=period / 400,
                          time_step_safety=V.SAFETY)
        model = _with_rule(beam.model(control, velocity=velocity, angular_velocity=spin), rule)
        h = M.run(model, tmp_path / rule).results.history
        w_tip = h["tracked_displacement"][:, :, 2] @ beam.tip_weights
        times = M.crossings(h["time"], w_tip)
        times = times[times > 0.1 * period]
        assert len(times) >= 5
        measured[rule] = 1.0 / (2.0 * np.polyfit(np.arange(len(times)), times, 1)[0])
        assert measured[rule] == pytest.approx(f1, rel=0.02)
    assert measured["radioss"] == pytest.approx(measured["scaled"], rel=0.01)
    assert measured["physical"] == pytest.approx(measured["scaled"], rel=0.01)


@pytest.mark.parametrize("poisson", [-0.5, 0.0, 0.1, 0.3, 0.45])
def test_radioss_rule_is_stable_at_its_own_step(tmp_path, poisson):
    """Reference: energy balance (kinetic + internal + hourglass = external work) of
    test_verification.test_default_time_step_is_stable, the case that went NaN after about 110
    cycles for nu below about 0.12 when the default was m (t^2 + A) / 12: the 20 x 2 cantilever
    strip under a step tip load for 2000 cycles of the automatic step. With the radioss rule the
    part's wave speed is raised by sqrt(5 (1 - nu)) / 2 where that exceeds 1 (nu < 0.2), which
    keeps the rotational mode below the membrane limit; the run completes and conserves energy to
    1e-3 of the work done. The step is that of scaled for nu >= 0.2 and smaller below."""
    material = M.Material(young=V.STEEL_NU0.young, poisson=poisson, density=V.STEEL_NU0.density)
    beam = M.cantilever(material)
    dt = M.stable_time_step(beam.mesh, beam.material)
    control = Control(end_time=2000 * dt, output_interval=1000 * dt)
    model = _with_rule(beam.model(control, loads=[M.Load(beam.tip, 3, 5.0 * beam.tip_weights)]), "radioss")
    h = M.run(model, tmp_path).results.history
    stored = h["kinetic_energy"] + h["internal_energy"] + h["hourglass_energy"]
    assert np.all(np.isfinite(stored))
    assert np.abs(stored - h["external_work"]).max() <= 1e-3 * np.abs(h["external_work"]).max()
    factor = max(1.0, np.sqrt(5.0 * (1.0 - poisson)) / 2.0)
    assert h["dt"][-1] == pytest.approx(dt / factor, rel=0.02)


@pytest.mark.parametrize("thickness", [0.01, 0.001])
@pytest.mark.parametrize("poisson", [-0.5, 0.0, 0.3, 0.45])
def test_physical_rule_is_stable_at_its_capped_step(tmp_path, poisson, thickness):
    """Reference: the energy balance of test_radioss_rule_is_stable_at_its_own_step. With the
    physical inertia m t^2 / 12 the shear-coupled rotational mode has omega ~ sqrt(5 (1 - nu)) c / t,
    so each element's step is min(L, 2 t / sqrt(5 (1 - nu))) / c (times the safety 0.9). The
    20 x 2 strip (h = 0.05 m) at t = 0.01 m (the cap 1.5 to 2.6 times below L = h) and t = 1 mm (15
    to 26 times), a step tip load (scaled with t^3 for the same deflection), 2000 cycles: finite,
    energy conserved to 1e-3 of the work, and the step the capped one."""
    material = M.Material(young=V.STEEL_NU0.young, poisson=poisson, density=V.STEEL_NU0.density)
    beam = M.cantilever(material, thickness=thickness)
    cap = 2.0 * thickness / np.sqrt(5.0 * (1.0 - poisson))
    dt = 0.9 * min(cap, 0.05) / material.plate_wave_speed
    control = Control(end_time=2000 * dt, output_interval=1000 * dt)
    load = 5.0 * (thickness / 0.01) ** 3 * beam.tip_weights
    model = _with_rule(beam.model(control, loads=[M.Load(beam.tip, 3, load)]), "physical")
    h = M.run(model, tmp_path).results.history
    stored = h["kinetic_energy"] + h["internal_energy"] + h["hourglass_energy"]
    assert np.all(np.isfinite(stored))
    assert np.abs(stored - h["external_work"]).max() <= 1e-3 * np.abs(h["external_work"]).max()
    assert h["dt"][-1] == pytest.approx(dt, rel=0.02)


def test_scene_and_knob_carry_the_rule():
    """The study knob sets every part's rule and the scene's model carries it; the default scene
    has the deck's default, scaled."""
    scene = load_scene(ROOT / "cases" / "pipe_whip" / "scene.toml")
    assert KNOBS["rotary_inertia"].base(scene) == "scaled"
    assert list(build_model(scene).rotary_inertia) == [RULES["scaled"]] * 2
    KNOBS["rotary_inertia"].apply(scene, "radioss")
    assert [p.rotary_inertia for p in scene.parts] == ["radioss", "radioss"]
    assert list(build_model(scene).rotary_inertia) == [RULES["radioss"]] * 2


def test_keyword_deck_names_control_shell_and_keeps_the_default():
    """LS-DYNA sets its shell rotary mass with ROTASCL (*CONTROL_SHELL card 2, a scale factor on
    its own rule). ParaDyn reads card 1 of *CONTROL_SHELL (ISTUPD) and not card 2: the deck's parts
    keep the default rule (docs/keyword.md). Deck: pydyna's pipe (../shared/realdecks/pydyna_pipe),
    *CONTROL_SHELL at line 19 (card 1 only, ISTUPD = 1)."""
    deck = ROOT.parent / "shared" / "realdecks" / "pydyna_pipe" / "pipe.k"
    if not deck.exists():
        pytest.skip(f"{deck} is missing")
    from paradyn.keyword.scene import load_keyword

    read = load_keyword(deck)
    assert not any("CONTROL_SHELL is not supported" in w for w in read.warnings)
    assert {p.rotary_inertia for p in read.scene.parts} == {"scaled"}


@pytest.mark.parametrize("rule", ["radioss", "physical"])
def test_python_scene_carries_the_rule(rule):
    """paradyn.Scene.add_part takes ``rotary_inertia`` like the scene file's [[part]] key: the
    model's /parts/rotary_inertia is the rule's code; an unknown rule is an error naming the choices."""
    import paradyn

    scene = paradyn.Scene("rotary", end_time=1e-4, output_interval=1e-4)
    scene.add_material("steel", model="elastic", density=7850.0, youngs_modulus=2e11, poisson_ratio=0.3)
    scene.add_part("plate", material="steel", thickness=0.01, rotary_inertia=rule,
                   geometry=paradyn.Plate(size=(1.0, 0.5), elements=(4, 2)))
    assert list(scene.build().rotary_inertia) == [RULES[rule]]
    with pytest.raises(SceneError, match="is not one of: scaled, radioss, physical"):
        bad = paradyn.Scene("rotary", end_time=1e-4, output_interval=1e-4)
        bad.add_material("steel", model="elastic", density=7850.0, youngs_modulus=2e11, poisson_ratio=0.3)
        bad.add_part("plate", material="steel", thickness=0.01, rotary_inertia="exact",
                     geometry=paradyn.Plate(size=(1.0, 0.5), elements=(4, 2)))
        bad.build()
