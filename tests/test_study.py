"""Issue 16: paradyn-study / paradyn.study, what accuracy costs in time.

The pieces without the engine first (Richardson extrapolation against analytic sequences, the
'not asymptotic' messages, quantities on a made-up history, designs, the Pareto front, the target
choice), then studies of the 32-element plate (cases/small_plate, under a second a run): the files
and their contents, the cache by deck content, the [study] table and bad input.
"""

from __future__ import annotations

import csv
import json
import math
import os
from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn import scene
from paradyn.studies.analysis import StudyRun, analyse
from paradyn.studies.cli import main as study_main
from paradyn.studies.design import Design, StudyError, apply, label
from paradyn.studies.error import (
    ORDER_RANGE,
    pareto_front,
    parse_quantities,
    parse_target,
    reference,
    relative_error,
    richardson,
)
from paradyn.studies.spec import StudySpec
from paradyn.studies.sweep import StudyResult

ROOT = Path(__file__).resolve().parents[1]
PLATE = ROOT / "cases" / "small_plate" / "scene.toml"
PIPES = ROOT / "cases" / "pipe_whip" / "scene.toml"


# ---------------------------------------------------------------------------------------------
# Richardson extrapolation


@pytest.mark.parametrize(("order", "ratio"), [(2.0, 2.0), (1.5, 3.0), (4.0, 2.0)])
def test_richardson_recovers_the_limit_and_order_of_an_analytic_sequence(order: float, ratio: float) -> None:
    """q(h) = 3 + 0.7 h^p on meshes refined by `ratio`: the limit 3 and the order p come back exactly
    (to round-off), whatever the coarse rungs below the three finest."""
    factors = [1.0, ratio, ratio**2, ratio**3]
    values = [3.0 + 0.7 * (1.0 / f) ** order for f in factors]
    ex = richardson(factors, values)
    assert ex.message == ""
    assert ex.order == pytest.approx(order, rel=1e-9)
    assert ex.value == pytest.approx(3.0, rel=1e-12)


@pytest.mark.parametrize(("values", "words"), [
    ([1.0, 1.2, 1.1], "alternate in sign"),          # oscillating
    ([1.0, 1.1, 1.3], "do not shrink"),              # diverging
    ([1.0, 1.1, 1.16], "observed order 0.74"),       # changes shrink by 1.67 < 2: order below 1
    ([1.0, 1.5, 1.5001], "observed order 12.29"),   # changes shrink by 5000: faster than any error term
])
def test_richardson_says_when_the_ladder_is_not_asymptotic(values: list[float], words: str) -> None:
    ex = richardson([1, 2, 4], values)
    assert ex.value is None
    assert "not in the asymptotic range" in ex.message and words in ex.message


def test_richardson_needs_three_meshes_refined_by_a_constant_ratio() -> None:
    assert "needs 3 meshes" in richardson([1, 2], [1.0, 1.1]).message
    assert "constant ratio" in richardson([1, 2, 3], [1.0, 1.1, 1.12]).message
    converged = richardson([1, 2, 4], [2.5, 2.5, 2.5])
    assert converged.value == 2.5 and converged.order is None and converged.message == ""
    assert ORDER_RANGE == (1.0, 6.0)


def test_reference_prefers_a_given_value_then_richardson_then_the_finest_run() -> None:
    ladder = [(1.0, 1.25), (2.0, 1.0625), (4.0, 1.015625)]   # 1 + 0.25 h^2
    assert reference(7.0, "richardson", ladder, 1.015625).source == "given"
    rich = reference(None, "richardson", ladder, 1.015625)
    assert rich.source == "richardson" and rich.value == pytest.approx(1.0) and rich.order == pytest.approx(2.0)
    finest = reference(None, "finest", ladder, 1.015625)
    assert finest.source == "finest run" and finest.value == 1.015625 and finest.note == ""
    oscillating = reference(None, "richardson", [(1.0, 1.0), (2.0, 1.2), (4.0, 1.1)], 1.1)
    assert oscillating.source == "finest run" and oscillating.value == 1.1
    assert "alternate in sign" in oscillating.note and "against the finest run" in oscillating.note
    assert relative_error(1.1, 1.0) == pytest.approx(0.1) and relative_error(0.5, 0.0) == 0.5


# ---------------------------------------------------------------------------------------------
# quantities, target, front


def test_quantities_read_a_history() -> None:
    t = np.linspace(0.0, 1e-3, 11)
    history = {"time": t, "a_dz": -t * 1e3, "b_dz": np.sin(t * 5e3), "internal_energy": t**2}
    [at] = parse_quantities("a", "a.dz@2.5e-4")
    assert at.value(history) == pytest.approx(-0.25)
    two = parse_quantities("a", "a.dz@1e-4,5e-4")
    assert [q.name for q in two] == ["a@0.0001", "a@0.0005"]
    [mean] = parse_quantities("m", "mean(a, b).dz@3e-4")
    assert mean.value(history) == pytest.approx(0.5 * (-0.3 + math.sin(1.5)))
    [diff] = parse_quantities("d", "diff(a,b).dz@3e-4")
    assert diff.value(history) == pytest.approx(-0.3 - math.sin(1.5))
    [peak] = parse_quantities("p", "a.dz:peak")
    assert peak.value(history) == pytest.approx(-1.0)       # the largest magnitude, with its sign
    assert parse_quantities("e", "internal_energy:final")[0].value(history) == pytest.approx(1e-6)
    assert parse_quantities("x", "b.dz:max")[0].value(history) == pytest.approx(np.max(np.sin(t * 5e3)))
    with pytest.raises(StudyError, match=r"run ends at 0\.001 s"):
        parse_quantities("late", "a.dz@2e-3")[0].value(history)
    with pytest.raises(StudyError, match="no history column c_dz"):
        parse_quantities("c", "c.dz:final")[0].value(history)
    for bad, words in [("a.dz", "end it with @TIME"), ("a.dq@1e-4", "components are"),
                       ("a.dz@soon", "must be numbers"), ("diff(a).dz@1e-4", "diff takes two points")]:
        with pytest.raises(StudyError, match=words):
            parse_quantities("bad", bad)


def test_target_and_pareto_front() -> None:
    assert parse_target("1%") == pytest.approx(0.01) and parse_target(0.05) == 0.05
    for bad in ("one percent", "0%", "-1"):
        with pytest.raises(StudyError, match="target"):
            parse_target(bad)
    costs = [1.0, 2.0, 2.0, 3.0, 5.0, 0.5]
    errors = [0.10, 0.05, 0.08, 0.06, 0.01, 0.30]
    assert pareto_front(costs, errors) == [5, 0, 1, 4]   # 2 and 3 are beaten by run 1


def _run(config: tuple, cost: float, value: float) -> StudyRun:
    return StudyRun(config, label(config), False, {"core_s": cost}, values={"q": value})


def test_analysis_names_the_cheapest_run_that_meets_the_target() -> None:
    """Made-up runs of q = 1 + 0.2 h^2 on meshes 1, 2, 4 and two cheaper variants: the reference is
    1 (Richardson, order 2); at 2 % both mesh=4 (1.25 %) and integration_points=3 (1.5 %) meet it,
    and the second costs less; at 0.5 % no run meets it."""
    runs = [_run((), 1.0, 1.2), _run((("mesh", 2.0),), 4.0, 1.05), _run((("mesh", 4.0),), 16.0, 1.0125),
            _run((("time_step", 0.0),), 0.5, 1.3), _run((("integration_points", 3),), 0.9, 1.015)]
    spec = StudySpec(design=Design(knobs={"mesh": [1.0, 2.0, 4.0], "time_step": [0.0],
                                          "integration_points": [3]}), target=0.02)
    base = {"mesh": 1, "time_step": 1e-6, "integration_points": 5}
    quantity = parse_quantities("q", "x.dz:final")[0]
    analysis = analyse(runs, [quantity], spec, base)
    assert analysis.references["q"].value == pytest.approx(1.0)
    assert [r.error for r in runs] == pytest.approx([0.2, 0.05, 0.0125, 0.3, 0.015])
    assert runs[analysis.target_run].label == "integration_points=3"
    assert "'integration_points=3', error 1.5 %" in analysis.target_answer
    assert [runs[i].label for i in analysis.front] == ["time_step=0", "integration_points=3", "mesh=4"]
    steps = {(s.knob, s.before, s.after): s for s in analysis.steps}
    assert steps[("mesh", 1, 2.0)].cost_ratio == pytest.approx(4.0)
    assert steps[("integration_points", 3, 5)].error_after == pytest.approx(0.2)
    strict = analyse(runs, [quantity], StudySpec(design=spec.design, target=0.005), base)
    assert strict.target_run is None and "No run meets" in strict.target_answer


# ---------------------------------------------------------------------------------------------
# designs and knobs


def test_designs_expand_around_the_base() -> None:
    sc = scene.load_scene(PIPES)
    oat = Design("one_at_a_time", {"mesh": [1, 2], "integration_points": [3, 5, 7]}).configurations(sc)
    assert [label(c) for c in oat] == ["base", "mesh=2", "integration_points=3", "integration_points=7"]
    grid = Design("grid", {"mesh": [1, 2], "symmetric": [True, False]}).configurations(sc)
    assert len(grid) == 4 and (("mesh", 2.0), ("symmetric", False)) in grid
    listed = Design("list", runs=[{"mesh": 2, "plasticity": False}]).configurations(sc)
    assert [label(c) for c in listed] == ["base", "mesh=2, plasticity=False"]


def test_knobs_set_the_scene() -> None:
    sc = scene.load_scene(PIPES)
    fine = apply(sc, (("mesh", 2.0), ("penalty_scale", 0.2), ("plasticity", False), ("time_step", 0.0),
                      ("contact_travel_limit", 0.1)))
    assert fine.run.contact_travel_limit == 0.1
    assert [(p.geometry.elements_around, p.geometry.elements_along) for p in fine.parts] == [(32, 64)] * 2
    assert fine.contacts[0].penalty_scale == 0.2 and fine.run.effect_switches == {"plasticity": "off"}
    assert fine.run.time_step == 0.0 and sc.parts[0].geometry.elements_around == 16   # the scene is kept
    plate = apply(scene.load_scene(PLATE), (("mesh", 0.5),))
    assert plate.parts[0].geometry.elements == (4, 2)
    full = apply(sc, (("element", "full"),))   # issue 35: the fully integrated element as a knob
    assert [p.element for p in full.parts] == ["full"] * 2 and [p.element for p in sc.parts] == ["blt"] * 2
    assert scene.build_model(full).shell_element.tolist() == [2, 2]


@pytest.mark.parametrize(("design", "words"), [
    (Design(knobs={"precision": ["single"]}), "must be one of double, mixed"),
    (Design(knobs={"mesh_size": [1]}), "unknown knob 'mesh_size'"),
    (Design(knobs={"integration_points": [2.5]}), "takes int values"),
    (Design(knobs={"integration_points": [11]}), "must be 1 to 9"),
    (Design(knobs={"element": ["bt"]}), "must be one of blt, full"),
    (Design(knobs={"penalty_scale": [0.2]}), "needs a \\[\\[contact\\]\\]"),
    (Design(kind="list", knobs={"mesh": [2]}), "takes its configurations from runs"),
    (Design(knobs={}), "turns no knob"),
    (Design(kind="sobol", knobs={"mesh": [2]}), "unknown design 'sobol'"),
])
def test_bad_designs_are_named(design: Design, words: str) -> None:
    with pytest.raises(StudyError, match=words):
        design.configurations(scene.load_scene(PLATE))


def test_a_mesh_factor_must_keep_counts_whole() -> None:
    with pytest.raises(StudyError, match="elements_around = 18, which must be a whole number and a multiple of 4"):
        apply(scene.load_scene(PIPES), (("mesh", 1.125),))
    with pytest.raises(StudyError, match=r"elements\[0\] = 2.4, which must be a whole number"):
        apply(scene.load_scene(PLATE), (("mesh", 0.3),))


# ---------------------------------------------------------------------------------------------
# studies of the 32-element plate (the engine runs)

QUANTITIES = {"tip": "tip_corner.dz@1e-4,2e-4", "middle": "middle.dz:peak"}


@pytest.fixture(scope="module")
def plate_study(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, StudyResult]:
    out = tmp_path_factory.mktemp("plate_study")
    result = paradyn.study(PLATE, out, knobs={"mesh": [1, 2, 4], "integration_points": [3]},
                           quantities=QUANTITIES, target="10%", jobs=2, progress=False)
    return out, result


def test_study_files_hold_every_run(plate_study: tuple[Path, StudyResult]) -> None:
    """study.csv and study.json hold each run's knobs, cost, indicators, quantities and errors; the
    quantities are those of the run's own results.h5, the indicators those of its summary.json."""
    out, result = plate_study
    rows = list(csv.DictReader((out / "study.csv").open()))
    assert [r["run"] for r in rows] == ["base", "mesh=2", "mesh=4", "integration_points=3"]
    assert [int(r["elements"]) for r in rows] == [32, 128, 512, 32]
    assert [r["mesh"] for r in rows] == ["", "2.0", "4.0", ""] and rows[3]["integration_points"] == "3"
    for row in rows:
        folder = out / "runs" / row["key"]
        history = paradyn.read(folder / "results.h5").history_table()
        t, dz = history["time"], history["tip_corner_dz"]
        assert float(row["tip@0.0001"]) == pytest.approx(np.interp(1e-4, t, dz), rel=1e-12)
        middle = history["middle_dz"][np.argmax(np.abs(history["middle_dz"]))]
        assert float(row["middle"]) == pytest.approx(middle, rel=1e-12)
        record = json.loads((folder / "run.json").read_text())
        summary = json.loads((folder / "summary.json").read_text())
        assert float(row["core_s"]) == pytest.approx(record["core_s"]) and record["core_s"] > 0
        assert int(row["cycles"]) == summary["cycles"] and float(row["peak_memory_mb"]) > 0
        assert float(row["whole_s"]) >= float(row["engine_s"]) > 0
        assert float(row["energy_balance_error"]) == pytest.approx(summary["accuracy"]["energy_balance_error"])
        assert 0 < float(row["dt_over_stable_dt"]) <= 1
    data = json.loads((out / "study.json").read_text())
    assert data["runs"] == json.loads(json.dumps(data["runs"])) and len(data["runs"]) == 4
    assert set(data["references"]) == {"tip@0.0001", "tip@0.0002", "middle"}
    assert data["pareto_front"] == [result.runs[i].label for i in result.analysis.front]
    assert data["unavailable_knobs"] == {}
    errors = [max(float(r[f"error_{q}"]) for q in data["references"]) for r in rows]
    assert errors == pytest.approx([float(r["error"]) for r in rows])
    assert (out / "pareto.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = (out / "study.md").read_text()
    assert "| # | run | elements |" in text and result.analysis.target_answer in text


def test_target_names_the_cheapest_run_under_it(plate_study: tuple[Path, StudyResult]) -> None:
    """The run the target names has an error under 10 % and no run under 10 % costs less."""
    _, result = plate_study
    ok = [r for r in result.runs if r.error is not None and r.error <= 0.10]
    chosen = result.runs[result.analysis.target_run]
    assert chosen in ok and chosen.cost("core_s") == min(r.cost("core_s") for r in ok)
    assert f"'{chosen.label}'" in result.analysis.target_answer


def test_runs_are_cached_by_deck_content(tmp_path: Path) -> None:
    """A second study in the same folder runs nothing; extended by one knob value it runs only that
    one; the finished runs' files are not touched."""
    options = {"quantities": {"tip": "tip_corner.dz:final"}, "progress": False, "jobs": 1}
    first = paradyn.study(PLATE, tmp_path, knobs={"mesh": [1, 2]}, **options)
    assert first.ran == 2 and not any(r.cached for r in first.runs)
    stamps = {p: p.stat().st_mtime_ns for p in tmp_path.glob("runs/*/results.h5")}
    again = paradyn.study(PLATE, tmp_path, knobs={"mesh": [1, 2]}, **options)
    assert again.ran == 0 and all(r.cached for r in again.runs)
    extended = paradyn.study(PLATE, tmp_path, knobs={"mesh": [1, 2], "warping_correction": [False]}, **options)
    assert extended.ran == 1 and [r.cached for r in extended.runs] == [True, True, False]
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps
    assert len(list(tmp_path.glob("runs/*/run.json"))) == 3
    assert [r.values for r in again.runs] == [r.values for r in first.runs]


STUDY_TABLE = """
[study]
design = "grid"
target = "5%"
cost = "engine_s"
[study.knobs]
mesh = [1, 2]
time_step_safety = [0.5, 0.9]
[study.quantities]
tip = "tip_corner.dz@2e-4"
"""


def test_a_study_table_in_the_scene(tmp_path: Path) -> None:
    """paradyn-run's reader accepts [study] and the study takes its defaults from it; the command
    line replaces them (here the cost)."""
    path = tmp_path / "scene.toml"
    path.write_text(PLATE.read_text() + STUDY_TABLE)
    assert scene.load_scene(path).parts[0].name == "plate"
    out = tmp_path / "study"
    assert study_main([str(path), "-o", str(out), "-q", "--cost", "cycles"]) == 0
    data = json.loads((out / "study.json").read_text())
    assert [r["run"] for r in data["runs"]] == ["base", "time_step_safety=0.5", "mesh=2, time_step_safety=0.5",
                                                "mesh=2"]
    assert data["spec"]["design"]["kind"] == "grid" and data["target"] == pytest.approx(0.05)
    assert data["cost_measure"] == "cycles" and list(data["references"]) == ["tip"]
    assert data["references"]["tip"]["source"] == "finest run"   # two meshes: no Richardson
    assert "needs 3 meshes" in data["references"]["tip"]["note"]
    path.write_text(PLATE.read_text() + STUDY_TABLE.replace('cost = "engine_s"', 'costs = "engine_s"'))
    with pytest.raises(StudyError, match="unknown key 'costs' in \\[study\\]"):
        paradyn.study(path, out, progress=False)
    path.write_text("study = 3\n" + PLATE.read_text())
    with pytest.raises(scene.SceneError, match="'study' in the scene must be a table"):
        scene.load_scene(path)


@pytest.mark.parametrize(("args", "words"), [
    (["--knob", "precision=quad"], "must be one of double, mixed"),
    (["--knob", "mesh=1,1.3"], "must be a whole number"),
    (["--knob", "mesh"], "must be written NAME=VALUE"),
    (["--knob", "mesh=1,2", "--quantity", "tip_corner.dz"], "end it with @TIME"),
    (["--knob", "mesh=1,2", "--target", "tiny"], "target 'tiny' is not a number"),
    (["--knob", "mesh=1,2", "--reference", "best"], "unknown reference 'best'"),
    (["--knob", "mesh=1,2", "--target-quantity", "tip"], "'tip' is not a quantity of the study"),
    (["--knob", "mesh=1,2", "--quantity", "corner.dz@1e-4"], "the scene tracks no point 'corner'"),
    (["--knob", "mesh=1,2", "--quantity", "tip_corner.dz@3e-4"], "but the runs end at 0.0002 s"),
])
def test_bad_input_exits_2_and_writes_nothing(tmp_path: Path, capsys: pytest.CaptureFixture, args: list[str],
                                              words: str) -> None:
    out = tmp_path / "study"
    assert study_main([str(PLATE), "-o", str(out), "-q", *args]) == 2
    assert words in capsys.readouterr().err
    assert not out.exists()


def test_command_line_study_with_a_given_reference(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """--reference NAME=VALUE: errors against the given value; the table is printed."""
    out = tmp_path / "study"
    assert study_main([str(PLATE), "-o", str(out), "-q", "--knob", "mesh=1,2", "--quantity", "tip=tip_corner.dz@2e-4",
                       "--reference", "tip=1e-4", "--target", "50%", "-j", "1"]) == 0
    printed = capsys.readouterr().out
    rows = list(csv.DictReader((out / "study.csv").open()))
    assert [float(r["error"]) for r in rows] == pytest.approx([abs(float(r["tip"]) - 1e-4) / 1e-4 for r in rows])
    assert "| tip | 0.0001 | given |" in printed and "Cheapest configuration that meets 0.5" in printed
    assert os.access(out / "study.md", os.R_OK)


def test_a_failed_run_is_reported_and_not_cached(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    """A run the engine stops (here [run] energy_error_limit = 1e-15, passed on the first cycle):
    its row carries the engine's message, the exit status is 1, and it leaves no run.json, so the
    next study runs it again."""
    path = tmp_path / "scene.toml"
    path.write_text(PLATE.read_text().replace("[run]\n", "[run]\nenergy_error_limit = 1e-15\n", 1))
    out = tmp_path / "study"
    args = [str(path), "-o", str(out), "-q", "--knob", "mesh=1,2", "--quantity", "tip=tip_corner.dz:final"]
    assert study_main(args) == 1
    err = capsys.readouterr().err
    assert "run 'base' failed: paradyn-engine: error: the energy balance error reached" in err
    rows = list(csv.DictReader((out / "study.csv").open()))
    assert all("energy_error_limit" in r["status"] for r in rows) and all(r["error"] == "" for r in rows)
    assert not list(out.glob("runs/*/run.json"))
    data = json.loads((out / "study.json").read_text())
    tip = data["references"]["tip"]
    assert tip["source"] == "none" and "give a reference value" in tip["note"]
    assert study_main(args) == 1 and "2 run now, 0 from the cache" in (out / "study.md").read_text()


def test_a_scene_built_in_python(tmp_path: Path) -> None:
    """paradyn.study takes a paradyn.Scene as it takes a file: the same decks, so the same runs."""
    built = paradyn.Scene.from_toml(PLATE)
    options = {"knobs": {"mesh": [1, 2]}, "quantities": {"tip": "tip_corner.dz:final"}, "progress": False,
               "jobs": 1}
    from_file = paradyn.study(PLATE, tmp_path, **options)
    from_python = paradyn.study(built, tmp_path, **options)
    assert from_python.ran == 0 and [r.key for r in from_python.runs] == [r.key for r in from_file.runs]
    path = tmp_path / "scene.toml"   # a [study] table comes along with the scene's tables, and is checked
    path.write_text(PLATE.read_text() + STUDY_TABLE.replace('cost = "engine_s"', 'costs = "engine_s"'))
    with pytest.raises(StudyError, match="unknown key 'costs' in \\[study\\]"):
        paradyn.study(paradyn.Scene.from_toml(path), tmp_path / "other", progress=False)
