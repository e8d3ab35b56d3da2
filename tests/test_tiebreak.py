"""Tiebreak contact (``[[contact]] kind = "tiebreak"``; docs/theory.md, "Tiebreak").

The failure surface is LS-DYNA's (Keyword User's Manual, Vol. I, *CONTACT_TIEBREAK_NODES_TO_SURFACE):
a tie fails when (sigma_n / NFLS)^2 + (sigma_s / SFLS)^2 >= 1, sigma its force over its slave
node's tributary area. Two steel plates 40 x 20 x 2 mm (one shell each) stacked at their half
thicknesses: the lower one clamped, the four nodes of the upper one tied to it and each loaded by a
quarter of a force ramped linearly in time. By symmetry (and the membrane's stiffness in the
plane) every tie carries a quarter of the load over a quarter of the area, so all four fail in the
same step, when the load reaches

    F = NFLS x A (a pull along the normal),  F = SFLS x A (a pull in the plane),
    F = (cos^2 a / NFLS^2 + sin^2 a / SFLS^2)^(-1/2) x A (a pull at a from the normal),

A = 800 mm^2 the tied area. The ramp reaches F in about 1 ms, against the tie spring's period of a
few steps (quasi-static to a few per mille); a wrong area (the node's full shell area, the
master's), a criterion without the square or on force rather than stress, misses by 25 % or more.
A failed tie becomes penalty contact against its segment: a plate pressed down after its ties
failed in shear is still held on the lower one.
"""

from __future__ import annotations

import copy
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn import _schema, deck
from paradyn.running import launch

T = 0.002         # m, both plates' thickness
SIZE = (0.04, 0.02)
GRID = (1, 1)
AREA = SIZE[0] * SIZE[1]
NFLS = 2.0e5      # Pa: F = 160 N in tension
SFLS = 1.0e5      # Pa: F = 80 N in shear
RAMP = 2.0e-3     # s, the load's ramp to its full value
END = 1.6e-3


def _plates(direction: tuple[float, float], full: float, normal: float = NFLS, shear: float = SFLS) -> deck.Model:
    """The upper plate pulled by full x t / RAMP (N) along direction = (x, z), shared by area."""
    scene = paradyn.Scene("tiebreak plates", end_time=END, output_interval=END / 4, history_interval=2e-6)
    scene.add_material("steel", model="elastic", density=7800.0, youngs_modulus=2e11, poisson_ratio=0.3)
    scene.add_part("upper", material="steel", thickness=T,
                   geometry=paradyn.Plate(size=SIZE, elements=GRID, origin=[0.0, 0.0, T]))
    scene.add_part("lower", material="steel", thickness=T, geometry=paradyn.Plate(size=SIZE, elements=GRID))
    scene.add_contact("upper", "lower", kind="tiebreak", normal_failure_stress=normal, shear_failure_stress=shear)
    scene.add_fix("lower", box=[[-1.0, -1.0, -1e-6], [1.0, 1.0, 1e-6]])
    dx, dy = SIZE[0] / GRID[0], SIZE[1] / GRID[1]
    for i in range(GRID[0] + 1):
        for j in range(GRID[1] + 1):
            share = (1.0 if 0 < i < GRID[0] else 0.5) * (1.0 if 0 < j < GRID[1] else 0.5) * dx * dy / AREA
            for dof, part in (("ux", direction[0]), ("uz", direction[1])):
                if part != 0.0:
                    scene.add_load("upper", point=[i * dx, j * dy, T], dof=dof, value=full * share * part,
                                   ramp_time=RAMP)
    return scene.build()


def _run(model: deck.Model, folder: Path, ranks: int = 1) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1)
    return folder / "results.h5"


def _failure_load(results: Path, full: float) -> tuple[float, np.ndarray]:
    """The load (N) at the first record with failed ties, and the failed count's history."""
    with h5py.File(results) as f:
        t = f["history/time"][:]
        failed = f["history/failed_ties"][:]
    first = int(np.argmax(failed > 0))
    assert failed[first] > 0, "no tie failed"
    return full * t[first] / RAMP, failed


@pytest.mark.parametrize(("name", "angle", "expected"), [
    ("tension", 0.0, NFLS * AREA),
    ("shear", 90.0, SFLS * AREA),
    ("combined", 60.0, AREA / np.sqrt(np.cos(np.pi / 3) ** 2 / NFLS**2 + np.sin(np.pi / 3) ** 2 / SFLS**2)),
])
def test_ties_fail_at_the_stress_criterion(tmp_path: Path, name: str, angle: float, expected: float) -> None:
    a = np.radians(angle)
    full = expected * RAMP / (0.8 * END)   # the failure load reached at 80 % of the run
    load, failed = _failure_load(_run(_plates((np.sin(a), np.cos(a)), full), tmp_path / name), full)
    assert abs(load - expected) < 0.01 * expected, (name, load, expected)
    # every tie at once (4 nodes, all of the same stress), and none before
    assert failed[-1] == (GRID[0] + 1) * (GRID[1] + 1)
    assert np.all(np.diff(failed) >= 0)


def test_a_tie_without_failure_stress_in_a_mode_holds_in_it(tmp_path: Path) -> None:
    """SFLS = 0: a pull in the plane never fails the ties (the shear mode adds nothing)."""
    full = SFLS * AREA * 2.0
    _, failed = _failure_load_or_none(_run(_plates((1.0, 0.0), full, shear=0.0), tmp_path))
    assert failed.max() == 0.0


def _failure_load_or_none(results: Path) -> tuple[None, np.ndarray]:
    with h5py.File(results) as f:
        return None, f["history/failed_ties"][:]


@pytest.fixture(scope="module")
def torn(tmp_path_factory: pytest.TempPathFactory) -> tuple[deck.Model, dict[str, Path]]:
    """The combined pull, on one rank and on two (local contact, and the replicated scheme)."""
    folder = tmp_path_factory.mktemp("tiebreak")
    expected = NFLS * AREA
    model = _plates((0.5, np.sqrt(0.75)), expected * RAMP / (0.8 * END))
    runs = {"one": _run(model, folder / "one")}
    if shutil.which("mpirun") or shutil.which("mpiexec"):
        for name, gather in (("local", None), ("all", "all")):
            two = copy.deepcopy(model)
            two.control.contact_gather = gather
            runs[name] = _run(two, folder / name, 2)
    return model, runs


@pytest.mark.mpi
def test_tie_failure_is_bitwise_the_same_on_two_ranks(torn: tuple[deck.Model, dict[str, Path]]) -> None:
    _, runs = torn
    if len(runs) == 1:
        pytest.skip("mpirun is not installed")
    with h5py.File(runs["one"]) as one:
        keys = ("frames/displacement", "history/failed_ties", "history/contact_force")
        reference = {key: one[key][:] for key in keys}
    assert reference["history/failed_ties"][-1] == 4.0
    for name in ("local", "all"):
        with h5py.File(runs[name]) as two:
            for key, values in reference.items():
                assert np.array_equal(two[key][:], values), (name, key)


def test_restart_after_ties_failed_is_the_uninterrupted_run(tmp_path: Path,
                                                           torn: tuple[deck.Model, dict[str, Path]]) -> None:
    """The failed ties go into the checkpoint: restarted after they failed (at about 1.3 ms), the
    run gives the uninterrupted run's frames and failed count bit for bit (a restart that forgot
    them would tie the plate again where it is)."""
    model, runs = copy.deepcopy(torn[0]), torn[1]
    model.control.checkpoint_interval = 1.45e-3
    folder = tmp_path / "checkpointed"
    results = _run(model, folder)
    target = folder / "restart.h5"
    shutil.copy(results, target)
    with h5py.File(target, "r+") as f:
        f.attrs["complete"] = np.int32(0)
    shutil.copy(folder / "results.checkpoint.h5", folder / "restart.checkpoint.h5")
    launch.run_engine(folder / "deck.h5", target, 1, 1, restart=True)
    with h5py.File(runs["one"]) as one, h5py.File(target) as two:
        assert two.attrs["complete"] == 1
        assert one["history/failed_ties"][-1] == 4.0
        for key in ("frames/displacement", "frames/velocity", "history/failed_ties"):
            assert np.array_equal(one[key][:], two[key][:]), key


def _lap_deck(contact: str) -> str:
    """Two one-shell parts 10 mm square stacked 2 mm apart, and the contact block ``contact``."""
    text = ("*KEYWORD\n*CONTROL_TERMINATION\n    0.0001\n"
            "*MAT_ELASTIC\n         1    7800.0     2e+11       0.3\n"
            "*SECTION_SHELL\n         1         2                   3\n     0.002     0.002     0.002     0.002\n"
            "*PART\nupper\n         1         1         1\n*PART\nlower\n         2         1         1\n*NODE\n")
    corners = [(0.0, 0.0), (0.01, 0.0), (0.01, 0.01), (0.0, 0.01)]
    text += "".join(f"{4 * p + k + 1:8d}{x:16.6f}{y:16.6f}{0.002 * (1 - p):16.6f}\n"
                    for p in range(2) for k, (x, y) in enumerate(corners))
    shells = ["".join(f"{n:8d}" for n in (p + 1, p + 1, 4 * p + 1, 4 * p + 2, 4 * p + 3, 4 * p + 4)) for p in range(2)]
    text += "*ELEMENT_SHELL\n" + "\n".join(shells) + "\n"
    return text + contact + "*END\n"


def test_keyword_tiebreak_nodes_to_surface_reads_its_failure_stresses(tmp_path: Path) -> None:
    from paradyn.keyword.scene import load_keyword
    path = tmp_path / "lap.k"
    path.write_text(_lap_deck("*CONTACT_TIEBREAK_NODES_TO_SURFACE\n         1         2         3         3\n\n\n"
                              "     2.0e6     1.0e6\n"))
    model = load_keyword(path).model
    assert list(model.contact_kind) == [_schema.ENUMS["contact_kind"]["tiebreak"]]
    assert model.contact_normal_failure_stress[0] == 2.0e6
    assert model.contact_shear_failure_stress[0] == 1.0e6


@pytest.mark.parametrize(("card", "message"), [
    ("         2     2.0e6     1.0e6       0.1", "OPTION = 2 is not supported"),
    ("         1       0.0       0.0", "no tie would ever fail"),
])
def test_keyword_tiebreak_options_other_than_the_stress_criterion_are_refused(tmp_path: Path, card: str,
                                                                                message: str) -> None:
    from paradyn.keyword.reader import KeywordError
    from paradyn.keyword.scene import load_keyword
    path = tmp_path / "lap.k"
    path.write_text(_lap_deck("*CONTACT_AUTOMATIC_ONE_WAY_SURFACE_TO_SURFACE_TIEBREAK\n"
                              "         1         2         3         3\n\n\n" + card + "\n"))
    with pytest.raises(KeywordError, match=message):
        load_keyword(path)


def test_a_failed_tie_is_contact(tmp_path: Path) -> None:
    """Pulled in the plane and pressed down (the load 10 degrees below the plane): compression is no
    tension, so the ties fail by shear alone, at F sin(100 deg) = SFLS A; then the plate slides on
    the lower one, its trailing nodes held on it by the contact that follows the ties (free, they
    would sink about 3 % of the thickness by the end; the leading ones slide past the lower plate's
    end and tip over it)."""
    a = np.radians(100.0)
    expected = SFLS * AREA / np.sin(a)
    full = expected * RAMP / (0.8 * END)
    model = _plates((np.sin(a), np.cos(a)), full)
    results = _run(model, tmp_path)
    load, _ = _failure_load(results, full)
    assert abs(load - expected) < 0.01 * expected, (load, expected)
    with h5py.File(results) as f:
        u = f["frames/displacement"][-1]
    x = np.asarray(model.coordinates)
    trailing = np.flatnonzero((x[:, 2] > 0.5 * T) & (x[:, 0] < 1e-9))
    assert trailing.size == 2
    assert u[trailing, 0].min() > 1.0e-4   # sliding
    assert u[trailing, 2].min() > -0.001 * T, u[trailing, 2]


@pytest.mark.parametrize(("kind", "keys"), [("tied", {"normal_failure_stress": 1.0e6}), ("tiebreak", {})])
def test_failure_stresses_belong_to_a_tiebreak(kind: str, keys: dict) -> None:
    """A tiebreak needs a failure stress, and no other kind takes one."""
    scene = paradyn.Scene("keys", end_time=1e-4, output_interval=1e-4)
    scene.add_material("steel", model="elastic", density=7800.0, youngs_modulus=2e11, poisson_ratio=0.3)
    for name, z in (("upper", T), ("lower", 0.0)):
        scene.add_part(name, material="steel", thickness=T,
                       geometry=paradyn.Plate(size=SIZE, elements=GRID, origin=[0.0, 0.0, z]))
    with pytest.raises(paradyn.scene.SceneError, match="tiebreak"):
        scene.add_contact("upper", "lower", kind=kind, **keys)
