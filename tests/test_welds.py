"""Weld failure (docs/theory.md, "Weld failure"; docs/validation.md): a spot weld (LS-DYNA
*CONSTRAINED_SPOTWELD, a rigid body of its two nodes) lets its nodes go when the force it carries
reaches the failure surface of the LS-DYNA Keyword User's Manual, Vol. I, *CONSTRAINED_SPOTWELD:
(max(fn, 0) / SN)^N + (|fs| / SS)^M >= 1, fn the force along N1 -> N2 (tension), fs the rest.

Two steel strips 20 x 5 x 2 mm, the first clamped at its far end, the second joined to it by two
welds at the corners of their facing ends and pulled at its other corners by two nodal loads
ramped slowly (20 ms, against a lowest period near 1 ms: quasi-static to a few per mille). By
symmetry and equilibrium of the second strip each weld carries one load, so a weld fails where
that load P reaches the analytic value: P = SN in tension, P = SS in shear, and
P = (sin^2 a / SN^2 + cos^2 a / SS^2)^(-1/2) for a pull at angle a off the shear direction (N = M = 2).
"""

from __future__ import annotations

import copy
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.keyword.scene import load_keyword
from paradyn.running import launch
from test_keyword import HEAD, MESH

LENGTH = 0.02    # m, each strip's length (4 shells of 5 mm)
WIDTH = 0.005    # m, the strips' width (1 shell)
RAMP = 0.02      # s, the loads' ramp from 0 to their full value
END = 0.016      # s


def _joint_deck(gap: tuple[float, float], pull: tuple[float, float], card: str) -> str:
    """Two steel strips LENGTH x WIDTH x 2 mm of 4 x 1 shells along x, the first clamped at x = 0,
    the second starting at the first's end offset by gap = (dx, dz), welded corner to corner by
    two *CONSTRAINED_SPOTWELD with the failure fields `card` (SN SS N M TF in 10 columns each);
    each of the second's far corners pulled by pull = (Fx, Fz) N x t / RAMP."""
    dx, dz = gap
    nodes: list[tuple[float, float, float]] = []
    for x0, z0 in ((0.0, 0.0), (LENGTH + dx, dz)):
        nodes += [(x0 + i * LENGTH / 4, j * WIDTH, z0) for i in range(5) for j in range(2)]
    shells = [(10 * strip + 2 * i + 1, 10 * strip + 2 * i + 3, 10 * strip + 2 * i + 4, 10 * strip + 2 * i + 2)
              for strip in range(2) for i in range(4)]
    text = ("*KEYWORD\n*CONTROL_TERMINATION\n" + f"{END:10.4f}\n" +
            "*MAT_ELASTIC\n         1    7800.0     2e+11       0.3\n"
            "*SECTION_SHELL\n         1         2                   3\n     0.002     0.002     0.002     0.002\n"
            "*PART\nfixed\n         1         1         1\n*PART\npulled\n         2         1         1\n*NODE\n")
    text += "".join(f"{k + 1:8d}{x:16.6f}{y:16.6f}{z:16.6f}\n" for k, (x, y, z) in enumerate(nodes))
    text += "*ELEMENT_SHELL\n" + "".join(f"{k + 1:8d}{1 + k // 4:8d}" + "".join(f"{n:8d}" for n in shell) + "\n"
                                        for k, shell in enumerate(shells))
    text += "*BOUNDARY_SPC_NODE\n" + "".join(f"{n:10d}         0         1         1         1         1         1"
                                             "         1\n" for n in (1, 2))
    text += ("*DEFINE_CURVE\n         1\n                 0.0             0.0\n"
             f"{RAMP:20.6f}             1.0\n                 1.0            50.0\n*LOAD_NODE_POINT\n")
    for n in (19, 20):
        text += "".join(f"{n:10d}{dof:10d}         1{value:10.4f}\n" for dof, value in ((1, pull[0]), (3, pull[1]))
                        if value != 0.0)
    text += "*DATABASE_HISTORY_NODE\n        19\n*CONSTRAINED_SPOTWELD\n"
    text += "".join(f"{a:10d}{b:10d}{card}\n" for a, b in ((9, 11), (10, 12)))
    return text + "*END\n"


def _model(tmp_path: Path, gap: tuple[float, float], pull: tuple[float, float], card: str) -> paradyn.deck.Model:
    path = tmp_path / "joint.k"
    path.write_text(_joint_deck(gap, pull, card))
    model = load_keyword(path).model
    model.control.history_interval = 2e-6
    return model


def _run(model: paradyn.deck.Model, folder: Path, ranks: int = 1) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1)
    return folder / "results.h5"


def _failure_load(results: Path, pull: float) -> tuple[float, np.ndarray, np.ndarray]:
    """The load on one node (N) at the first record with failed welds, the failed count's history
    and the tracked node's x displacement."""
    with h5py.File(results) as f:
        t = f["history/time"][:]
        failed = f["history/failed_welds"][:]
        ux = f["history/tracked_displacement"][:, 0, 0]
    first = int(np.argmax(failed > 0))
    assert failed[first] > 0, "no weld failed"
    return pull * t[first] / RAMP, failed, ux


@pytest.mark.parametrize(("name", "gap", "direction", "card", "expected"), [
    # SN = 30 N, tension along N1 -> N2 (x): P = SN
    ("tension", (0.001, 0.0), (1.0, 0.0), "      30.0       0.0       2.0       2.0", 30.0),
    # SS = 5 N, welds across a 2 mm lap (normal z), pulled along x: P = SS
    ("shear", (0.0, 0.002), (1.0, 0.0), "       0.0       5.0       2.0       2.0", 5.0),
    # SN = 20 N, SS = 10 N, pulled 30 degrees out of the plane: P = (0.25/400 + 0.75/100)^-1/2
    ("combined", (0.0, 0.002), (np.cos(np.pi / 6), np.sin(np.pi / 6)),
     "      20.0      10.0       2.0       2.0", 1.0 / np.sqrt(0.25 / 400.0 + 0.75 / 100.0)),
])
def test_a_weld_lets_go_at_its_failure_force(tmp_path: Path, name: str, gap: tuple[float, float],
                                             direction: tuple[float, float], card: str, expected: float) -> None:
    """The load per weld when the two welds fail (together, by symmetry) within 1 % of the analytic
    failure load (a weld force taken as both welds' sum fails at half of it, the compression side
    or the wrong direction never or at another load), and the pulled strip then moves off freely:
    its displacement at the end is more than 10 times the elastic one at failure."""
    peak = 2.0 * expected
    pull = (peak * direction[0], peak * direction[1])
    results = _run(_model(tmp_path, gap, pull, card), tmp_path / name)
    load, failed, ux = _failure_load(results, peak)
    assert load == pytest.approx(expected, rel=0.01)
    assert set(np.unique(failed)) == {0.0, 2.0}
    first = int(np.argmax(failed > 0))
    assert ux[-1] > 10.0 * abs(ux[first]) > 0.0


def test_without_failure_forces_the_welds_hold(tmp_path: Path) -> None:
    """SN = SS = 0 (LS-DYNA: no failure): the same pull at 60 N never breaks the welds, and the
    pulled strip stays within an elastic stretch of its place (under 0.1 mm)."""
    results = _run(_model(tmp_path, (0.001, 0.0), (60.0, 0.0), "       0.0       0.0       0.0       0.0"),
                   tmp_path / "holds")
    with h5py.File(results) as f:
        assert np.all(f["history/failed_welds"][:] == 0.0)
        assert np.abs(f["history/tracked_displacement"][:, 0, 0]).max() < 1e-4


def test_a_weld_lets_go_at_its_failure_time(tmp_path: Path) -> None:
    """TF = 5 ms (LS-DYNA's failure time): no force failure, the welds let go in the first step
    at or after 5 ms; the history counts both from the first record after it."""
    card = "       0.0       0.0       2.0       2.0     0.005"
    results = _run(_model(tmp_path, (0.001, 0.0), (60.0, 0.0), card), tmp_path / "timed")
    with h5py.File(results) as f:
        t = f["history/time"][:]
        failed = f["history/failed_welds"][:]
        dt = f["history/dt"][:]
    assert np.all(failed[t < 0.005 - 1e-12] == 0.0)
    assert np.all(failed[t > 0.005 + 2.0 * dt.max()] == 2.0)


@pytest.fixture(scope="module")
def torn(tmp_path_factory: pytest.TempPathFactory) -> tuple[paradyn.deck.Model, dict[int, Path]]:
    folder = tmp_path_factory.mktemp("torn")
    model = _model(folder, (0.0, 0.002), (17.3205, 10.0), "      20.0      10.0       2.0       2.0")
    return model, {ranks: _run(model, folder / f"ranks{ranks}", ranks) for ranks in (1, 2)}


@pytest.mark.mpi
def test_weld_failure_is_bitwise_the_same_on_two_ranks(torn: tuple[paradyn.deck.Model, dict[int, Path]]) -> None:
    """The weld force is summed exactly over the ranks: the welds fail in the same step, and every
    frame's positions are bit for bit those of one rank."""
    _, runs = torn
    with h5py.File(runs[1]) as one, h5py.File(runs[2]) as two:
        assert np.array_equal(one["history/failed_welds"][:], two["history/failed_welds"][:])
        assert np.array_equal(one["frames/displacement"][:], two["frames/displacement"][:])


def test_restart_after_a_weld_failed_is_the_uninterrupted_run(tmp_path: Path,
                                                            torn: tuple[paradyn.deck.Model, dict[int, Path]]) -> None:
    """The failed state goes into the checkpoint (rigid_body_effect's state words): restarted from
    a checkpoint at 14 ms, after the welds let go at about 11 ms, the run gives the uninterrupted
    run's frames and failed count bit for bit (a restart that forgot the failure would weld the
    plates again where they are)."""
    model, runs = copy.deepcopy(torn[0]), torn[1]
    model.control.checkpoint_interval = 0.014
    folder = tmp_path / "checkpointed"
    results = _run(model, folder)
    target = folder / "restart.h5"
    shutil.copy(results, target)
    with h5py.File(target, "r+") as f:
        f.attrs["complete"] = np.int32(0)
    shutil.copy(folder / "results.checkpoint.h5", folder / "restart.checkpoint.h5")
    launch.run_engine(folder / "deck.h5", target, 1, 1, restart=True)
    with h5py.File(runs[1]) as one, h5py.File(target) as two:
        assert two.attrs["complete"] == 1
        assert one["history/failed_welds"][-1] == 2.0
        for key in ("frames/displacement", "frames/velocity", "history/failed_welds"):
            assert np.array_equal(one[key][:], two[key][:]), key


def _scene_strips() -> paradyn.Scene:
    """The tension case as a scene: the strips as two plates 1 mm apart, two [[weld]] at the
    corners of their facing ends (SN = 30 N), the far corners pulled by 60 N x t / RAMP."""
    scene = paradyn.Scene("welded strips", end_time=END, output_interval=END / 4, history_interval=2e-6)
    scene.add_material("steel", model="elastic", density=7800.0, youngs_modulus=2e11, poisson_ratio=0.3)
    for name, x0 in (("fixed", 0.0), ("pulled", LENGTH + 0.001)):
        scene.add_part(name, material="steel", thickness=0.002,
                       geometry=paradyn.Plate(size=(LENGTH, WIDTH), elements=(4, 1), origin=[x0, 0.0, 0.0]))
    scene.add_fix("fixed", box=[[-1e-6, -1.0, -1.0], [1e-6, 1.0, 1.0]])
    for y in (0.0, WIDTH):
        scene.add_weld("fixed", "pulled", point=[LENGTH + 0.0005, y, 0.0], strength=[30.0, 0.0])
        scene.add_load("pulled", point=[2 * LENGTH + 0.001, y, 0.0], dof="ux", value=60.0, ramp_time=RAMP)
    scene.add_track("tip", part="pulled", point=[2 * LENGTH + 0.001, 0.0, 0.0])
    return scene


def test_the_scene_form_welds_and_lets_go_alike(tmp_path: Path) -> None:
    """Scene.add_weld ([[weld]], the nodes of the two parts nearest the point): the same welds
    let go at the same load as the keyword deck's (within 1 % of SN = 30 N), and the scene's
    TOML file gives the same deck."""
    scene = _scene_strips()
    model = scene.build()
    assert model.rigid_body_failure_force.tolist() == [[30.0, 0.0], [30.0, 0.0]]
    np.testing.assert_allclose(model.rigid_body_failure_normal, [[1.0, 0.0, 0.0]] * 2, atol=1e-12)
    path = scene.to_toml(tmp_path / "scene.toml")
    again = paradyn.scene.load_scene(path)
    assert len(again.welds) == 2 and again.welds[0].strength == (30.0, 0.0)
    load, failed, _ = _failure_load(_run(model, tmp_path / "scene"), 60.0)
    assert load == pytest.approx(30.0, rel=0.01)
    assert failed[-1] == 2.0


def test_a_generalized_weld_reads_its_failure_in_the_deck_units(tmp_path: Path) -> None:
    """*CONSTRAINED_GENERALIZED_WELD_SPOT in mm, ms, kg (forces in kN): card 2's TFAIL 5 ms,
    SN 2 kN, SS 1.5 kN, N 0 (read as 2), M 3 become 0.005 s, 2000 N, 1500 N, (2, 3); the force is
    the set's first node's (12), the normal from it to the second (15): +y; EPSF 0.1 is the failure
    plastic strain."""
    weld = ("*SET_NODE_LIST\n         4\n        12        15\n*CONSTRAINED_GENERALIZED_WELD_SPOT\n"
            "         1         4\n       5.0       0.1       2.0       1.5       0.0       3.0\n")
    path = tmp_path / "generalized.k"
    path.write_text(HEAD.replace("*KEYWORD\n", "*KEYWORD\n*CONTROL_UNITS\n        mm        ms        kg\n")
                    + MESH + weld + "*END\n")
    read = load_keyword(path)
    model = read.model
    assert model.rigid_body_part.tolist() == [-1]
    np.testing.assert_allclose(model.rigid_body_failure_force, [[2000.0, 1500.0]], rtol=1e-12)
    np.testing.assert_allclose(model.rigid_body_failure_exponent, [[2.0, 3.0]])
    np.testing.assert_allclose(model.rigid_body_failure_time, [0.005], rtol=1e-12)
    assert int(np.asarray(model.node_ids)[model.rigid_body_failure_node[0]]) == 12
    np.testing.assert_allclose(model.rigid_body_failure_normal, [[0.0, 1.0, 0.0]], atol=1e-12)
    np.testing.assert_allclose(model.rigid_body_failure_plastic_strain, [0.1])
    assert not any("EPSF" in w for w in read.warnings)
