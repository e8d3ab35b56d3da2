"""``paradyn-run --check`` (issue 18, item 3): the mass per part, the stable step and its element,
the cycles, wall time and memory, the initial penetrations and the unit warnings, before a run.

The step and its element are checked against the engine itself (its ``--check`` set-up, printed
to 16 digits, and the history of a run: ``dt_stable`` and ``dt_element`` at record 0), the masses
against rho t A of plates whose area is known exactly, the warnings against the habits they name.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import models as M
import paradyn
from paradyn import cli
from paradyn.deck import Control, Model
from paradyn.running import preflight
from paradyn.running.launch import EngineError

STEEL = M.Material(young=200.0e9, poisson=0.3, density=7850.0)
ALUMINIUM = M.Material(young=70.0e9, poisson=0.33, density=2700.0)
SMALL_PLATE = Path(__file__).resolve().parents[1] / "cases" / "small_plate" / "scene.toml"


def _two_plates(control: Control | None = None) -> Model:
    """Two 0.1 x 0.05 m plates side by side, steel 2 mm and aluminium 3 mm, their inner nodes moved
    at random in the plane (the outline, hence each part's area, stays exact), so one element
    controls the step."""
    rng = np.random.default_rng(18)
    meshes = []
    for origin in ((0.0, 0.0, 0.0), (0.0, 0.06, 0.0)):
        mesh = M.flat_plate((0.1, 0.05), (8, 4), origin=origin)
        x = mesh.coordinates
        inner = ((x[:, 0] > 1e-9) & (x[:, 0] < 0.1 - 1e-9) & (x[:, 1] - origin[1] > 1e-9)
                 & (x[:, 1] - origin[1] < 0.05 - 1e-9))
        x[inner, :2] += rng.uniform(-3e-3, 3e-3, size=(int(inner.sum()), 2))
        meshes.append(mesh)
    control = control or Control(end_time=1e-4, output_interval=5e-5, history_interval=1e-5)
    model = M.contact_model([M.Body(meshes[0], 0.002), M.Body(meshes[1], 0.003)], STEEL, control,
                            pairs=()).model
    model.part_material = np.array([0, 1], dtype=np.int32)
    model.material_model = np.array([model.material_model[0]] * 2)
    model.density = np.array([STEEL.density, ALUMINIUM.density])
    model.youngs_modulus = np.array([STEEL.young, ALUMINIUM.young])
    model.poisson_ratio = np.array([STEEL.poisson, ALUMINIUM.poisson])
    model.failure_strain = np.zeros(2)
    model.part_names = ["steel_plate", "aluminium_plate"]
    model.initial_velocity = np.tile([0.0, 0.0, 1.0], (model.n_nodes, 1))   # something acts: no idle warning
    return model


def test_the_step_and_its_element_are_the_engines(tmp_path: Path) -> None:
    """The check's stable step equals the engine's (its --check set-up and the run's dt_stable at
    record 0) to 1e-12, and its element is the run's dt_element; the cycles are the engine's."""
    model = _two_plates()
    check = preflight.check_model(model)
    engine = preflight.engine_check(model)
    assert check.step.dt == pytest.approx(engine.dt_stable, rel=1e-12)
    assert (check.dt, check.cycles) == (pytest.approx(engine.dt, rel=1e-12), engine.steps)
    res = paradyn.run(model, tmp_path / "run", ranks=1, threads=1, post=False)
    assert check.step.dt == pytest.approx(float(res.history["dt_stable"][0]), rel=1e-12)
    assert check.step.element == int(res.history["dt_element"][0])
    assert check.cycles == res.run["cycles"]
    assert check.step.part == model.part_names[int(model.element_part[check.step.element])]
    assert len(set(np.round(preflight.element_steps(model)[0], 15))) > 10   # the mesh is uneven


def test_a_requested_step_below_the_stable_one_is_the_engines_fixed_step() -> None:
    model = _two_plates()
    stable = preflight.check_model(model).step.dt
    model.control = replace(model.control, time_step=0.37 * stable)
    check, engine = preflight.check_model(model), preflight.engine_check(model)
    assert check.dt == pytest.approx(engine.dt, rel=1e-12) and check.cycles == engine.steps
    assert check.dt <= 0.37 * stable and "requested step" in "\n".join(check.lines())


def test_mass_per_part_is_rho_t_area() -> None:
    parts = preflight.check_model(_two_plates()).parts
    assert [p.name for p in parts] == ["steel_plate", "aluminium_plate"]
    assert parts[0].mass_kg == pytest.approx(STEEL.density * 0.002 * 0.1 * 0.05, rel=1e-12)
    assert parts[1].mass_kg == pytest.approx(ALUMINIUM.density * 0.003 * 0.1 * 0.05, rel=1e-12)
    assert [p.elements for p in parts] == [32, 32]


def test_mass_scaling_adds_the_engines_mass(tmp_path: Path) -> None:
    """With [run] mass_scaling_step above the smallest elements' steps, the check's step is the
    target and its added mass is the engine's (summary added_mass_kg, to 1e-12)."""
    model = _two_plates()
    target = 1.3 * preflight.check_model(model).step.dt
    model.control = replace(model.control, mass_scaling_step=target, mass_scaling_limit=0.5)
    check = preflight.check_model(model)
    assert check.step.dt == pytest.approx(target, rel=1e-12)
    res = paradyn.run(model, tmp_path / "run", ranks=1, threads=1, post=False)
    assert sum(p.added_kg for p in check.parts) == pytest.approx(res.run["added_mass_kg"], rel=1e-12)
    assert sum(p.added_kg for p in check.parts) > 0


def test_wall_time_and_memory_follow_the_stated_figures(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """Before this machine's rate is measured (an empty cache), the development machine's."""
    model = _two_plates()
    monkeypatch.delenv(preflight.RATE_ENV, raising=False)
    monkeypatch.setenv("PARADYN_CACHE_DIR", str(tmp_path / "empty-cache"))
    one = preflight.check_model(model, 1, 1)
    assert one.rate == preflight.RATE_PER_CORE
    assert one.wall_s == pytest.approx(one.cycles * 64 / preflight.RATE_PER_CORE, rel=1e-12)
    assert one.memory_mb == pytest.approx(40.0 + 2e-3 * 90)   # 90 nodes
    four = preflight.check_model(model, 2, 2)
    assert four.rate == pytest.approx(4 * preflight.PARALLEL_EFFICIENCY * preflight.RATE_PER_CORE)
    assert four.memory_mb == pytest.approx(2 * (40.0 + 2e-3 * 45))   # 2 ranks, each its half of the nodes
    monkeypatch.setenv(preflight.RATE_ENV, "1e5")
    measured = preflight.check_model(model, 2, 2)
    assert measured.rate == 1e5 and preflight.RATE_ENV in measured.rate_source


@pytest.mark.parametrize("density, young, habit", [
    (2.7e-9, 70e3, "tonne/mm^3"),
    (7.85e-6, 200e9, "kg/mm^3"),
    (7.85, 200e9, "g/cm^3"),
    (7850.0, 210000.0, "MPa"),
    (7850.0, 210.0, "GPa"),
    (7850.0, 2e13, "diamond"),
])
def test_a_material_in_another_unit_system_is_named(density: float, young: float, habit: str) -> None:
    model = _two_plates()
    model.density = np.array([density, ALUMINIUM.density])
    model.youngs_modulus = np.array([young, ALUMINIUM.young])
    warnings = preflight.check_model(model).warnings
    assert len(warnings) >= 1 and habit in warnings[0] and "material_0" in warnings[0]


def test_a_thickness_in_millimetres_is_named() -> None:
    model = _two_plates()
    model.thickness = np.array([2.0, 0.003])
    warnings = preflight.check_model(model).warnings
    assert any("part steel_plate: thickness 2 m" in w and "millimetres" in w and "0.002" in w for w in warnings)


def test_sound_si_values_give_no_warning() -> None:
    assert preflight.check_model(_two_plates()).warnings == []


def test_too_many_cycles_are_named_with_the_time_they_take() -> None:
    model = _two_plates(Control(end_time=20.0, output_interval=1.0))
    warnings = preflight.check_model(model).warnings
    assert len(warnings) == 1 and "cycles" in warnings[0] and "mass_scaling_step" in warnings[0]


def _scene(tmp_path: Path, replace_text: tuple[str, str] | None = None, name: str = "scene.toml") -> Path:
    text = SMALL_PLATE.read_text()
    if replace_text is not None:
        assert replace_text[0] in text
        text = text.replace(*replace_text)
    path = tmp_path / name
    path.write_text(text)
    return path


def test_check_prints_the_report_and_writes_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.chdir(tmp_path)
    scene = _scene(tmp_path, ("thickness = 0.002", "thickness = 2"))
    assert cli.main([str(scene), "--check", "-q"]) == 0
    out = capsys.readouterr().out
    for text in ("part plate: 32 elements", "stable step", "cycles to end_time", "memory about",
                 "warning: part plate: thickness 2 m", "engine: first step"):
        assert text in out, text
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]


def test_check_reports_the_engines_initial_penetrations(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from test_initial_penetration import _scene_text

    scene = tmp_path / "scene.toml"
    scene.write_text(_scene_text("move", 0.006))
    assert cli.main([str(scene), "--check", "-q"]) == 0
    out = capsys.readouterr().out
    assert "engine: first step" in out and "1 warning(s) at set-up" in out
    assert "warning: initial penetration in /contact/pairs[0]: 9 nodes of part 0" in out


def test_check_gives_the_engines_refusal(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A deck the engine refuses at set-up (mass scaling past its limit) fails the check with the
    engine's message and status 2."""
    scene = _scene(tmp_path, ("time_step_safety = 0.9", "time_step_safety = 0.9\nmass_scaling_step = 1e-3\n"
                                                         "mass_scaling_limit = 0.01"))
    assert cli.main([str(scene), "--check", "-q"]) == 2
    assert "mass_scaling_limit" in capsys.readouterr().err


def test_engine_check_of_a_bad_deck_raises(tmp_path: Path) -> None:
    model = _two_plates()
    model.control = replace(model.control, mass_scaling_step=1e-3, mass_scaling_limit=0.01)
    with pytest.raises(EngineError, match="mass_scaling_limit") as error:
        preflight.engine_check(model)
    assert error.value.exit_code == 2


def test_every_run_starts_with_the_check(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scene = _scene(tmp_path, ("density = 7860.0", "density = 7.86"))
    assert cli.main([str(scene), "-o", str(tmp_path / "run"), "-t", "1", "--no-plots", "--no-vtk"]) == 0
    err = capsys.readouterr().err
    assert err.index("meshing") < err.index("stable step") < err.index("post-processing") and "g/cm^3" in err
    assert cli.main([str(scene), "-o", str(tmp_path / "run"), "-t", "1", "--no-plots", "--no-vtk", "-q"]) == 0
    quiet = capsys.readouterr().err
    assert "stable step" not in quiet and "meshing" not in quiet
    assert quiet.splitlines() == [next(line for line in err.splitlines() if "g/cm^3" in line)]   # the warning alone


def test_settings_that_rarely_mean_what_was_meant_are_named() -> None:
    """An output interval longer than the run, an hourglass coefficient of 1e6 and a contact
    penalty scale of 1e6 run, but each gets a warning that names it and a usual value."""
    model = _two_plates(Control(end_time=1e-4, output_interval=5e-4, history_interval=1e-5))
    model.hourglass_coefficient = np.array([1e6, 0.1])
    model.contact_pairs = np.array([[0, 1]], dtype=np.int32)
    model.contact_penalty_scale = np.array([1e6])
    warnings = preflight.check_model(model).warnings
    assert any(w.startswith("output_interval 0.0005 s is longer than end_time 0.0001 s") for w in warnings)
    assert not any(w.startswith("history_interval") for w in warnings)
    assert any(w.startswith("part steel_plate: hourglass coefficient 1e+06 is far above") for w in warnings)
    assert any(w.startswith("contact 0: penalty scale 1e+06 is far above") for w in warnings)
    assert len(warnings) == 3
