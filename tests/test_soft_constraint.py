"""The soft-constraint penalty (``[[contact]] soft_constraint``, /contact/soft_constraint; LS-DYNA's
SOFT = 1 with SOFSCL; docs/theory.md, Contact): the spring is at least s m / (2 dt^2), m the lightest
node of the slave and its segment, dt the step, and never above the stable m / (4 dt^2).

Two free 6 x 6 steel plates 0.1 m square, walls t = 1 mm, 0.1 mm apart, closing at 2 x 20 m/s at a
set step dt = 0.2 us. Facing interior nodes of mass m = rho t h^2 form the node-pair oscillator of
tests/test_contact_impact.py (each node pushed by 2 k: slave and master), omega = 2 sqrt(k / m),
deepest penetration 2 v / omega. The bulk-modulus penalty k0 = 0.1 K A / d is 1.96e8 N/m here; the
soft constraint's k = 0.05 m / dt^2 = 2.7e9 N/m is 14 times stiffer, so the centre pair's deepest
penetration is 2 v dt / (2 sqrt(0.05)) = 17.9 um (measured 17.89 um) against 2 v / (2 sqrt(k0 / m)) = 67 um.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import models as M
from contact_cases import STEEL
from paradyn import _schema
from paradyn.deck import Control
from paradyn.keyword.scene import load_keyword
from paradyn.mesh import geometry
from test_keyword import HEAD, TWO_PARTS, _deck

T = 1.0e-3
GAP = 1.0e-4
V = 20.0
DT = 2.0e-7
N = 6
H = 0.1 / N
CENTRE = (N + 1) * (N // 2) + N // 2      # the plate's middle node


def _run(tmp_path: Path, soft: float):
    a = M.flat_plate((0.1, 0.1), (N, N), origin=(0.0, 0.0, -0.5 * (T + GAP)))
    b = geometry.Mesh(coordinates=a.coordinates * np.array([1.0, 1.0, -1.0]), quads=a.quads[:, ::-1].copy())
    control = Control(end_time=1.5e-5, output_interval=5.0e-6, history_interval=DT, time_step=DT)
    asm = M.contact_model([M.Body(a, T, (0, 0, V)), M.Body(b, T, (0, 0, -V))], STEEL, control,
                          tracked=[CENTRE, a.n_nodes + CENTRE])
    asm.model.contact_soft_constraint = np.array([soft])
    return M.run(asm.model, tmp_path).results


def _centre_penetration(results) -> float:
    """The deepest closing of the two centre nodes past their contact reach (t + t) / 2."""
    z = results.history["tracked_displacement"][:, :, 2]
    distance = (0.5 * (T + GAP) + z[:, 1]) - (-0.5 * (T + GAP) + z[:, 0])
    return float(T - distance.min())


def test_the_soft_constraint_sets_the_spring_from_the_node_masses(tmp_path: Path) -> None:
    m = STEEL.density * T * H * H
    k0 = M.segment_stiffness(M.flat_plate((0.1, 0.1), (N, N)), STEEL, 0.1)[0]
    k_soft = 0.5 * 0.1 * m / DT**2
    assert k_soft > 10.0 * k0                       # the case is one the soft constraint decides
    expected = 2.0 * V / (2.0 * np.sqrt(k_soft / m))
    soft = _centre_penetration(_run(tmp_path / "soft", 0.1))
    assert soft == pytest.approx(expected, rel=0.03)
    bulk_only = 2.0 * V / (2.0 * np.sqrt(k0 / m))
    assert soft < 0.3 * bulk_only                   # sqrt(14) = 3.7 times shallower


def test_a_soft_constraint_past_the_cap_is_held_at_the_stable_spring(tmp_path: Path) -> None:
    """s = 1 asks for m / (2 dt^2); the stable cap m / (4 dt^2) holds it: omega = 2 sqrt(0.25) / dt."""
    expected = 2.0 * V / (2.0 * np.sqrt(0.25 / DT**2))
    assert _centre_penetration(_run(tmp_path, 1.0)) == pytest.approx(expected, rel=0.05)


@pytest.mark.parametrize(("card_a", "expected"), [("         1      0.25\n", 0.25), ("         1       0.0\n", 0.1),
                                                  ("         0      0.25\n", 0.0), ("", 0.0)],
                         ids=["sofscl", "zero-is-default", "soft-0", "no-card"])
def test_keyword_soft_1_reads_as_the_soft_constraint(tmp_path: Path, card_a: str, expected: float) -> None:
    """SOFT = 1 on card A gives soft_constraint = SOFSCL (0.0 read as LS-DYNA's default 0.1); without
    SOFT = 1 the scale is off, and SOFSCL is not warned about (LS-DYNA reads it only with SOFT = 1)."""
    cards = "         1         2         3         3\n       0.3\n\n" + card_a
    read = load_keyword(_deck(tmp_path, HEAD + TWO_PARTS + "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n" + cards))
    assert read.model.contact_soft_constraint.tolist() == [expected]
    assert not [w for w in read.warnings if "SOFSCL" in w]
    assert read.model.contact_kind.tolist() == [_schema.ENUMS["contact_kind"]["node_to_segment"]]


def test_a_restart_keeps_the_soft_constraints_step(tmp_path: Path) -> None:
    """The soft constraint's step (the largest so far) is in the checkpoint: the pipe whip at its
    automatic step (trimmed at 0.3 ms to end on the end time, below the largest so far) with penalty
    scale 0.01 and soft_constraint 0.5, restarted from 0.3 ms, equals the uninterrupted run bit for
    bit, and the soft constraint changes the run (it acts)."""
    import shutil

    import h5py

    from paradyn import deck, scene
    from paradyn.running import launch

    def pipe_whip(name: str, soft: float, **control: float) -> Path:
        model = scene.build_model(scene.load_scene(Path(__file__).resolve().parents[1] / "cases" / "pipe_whip"
                                                   / "scene.toml"))
        model.control.end_time = 4e-4
        model.control.output_interval = 1e-4
        model.control.time_step = 0.0            # the automatic step
        for key, value in control.items():
            setattr(model.control, key, value)
        model.contact_soft_constraint = np.full(len(model.contact_pairs), soft)
        model.contact_penalty_scale = np.full(len(model.contact_pairs), 0.01)   # k0 below the soft spring
        return deck.write_deck(model, tmp_path / name)

    def displacement(path: Path) -> np.ndarray:
        with h5py.File(path, "r") as f:
            return f["/frames/displacement"][()]

    launch.run_engine(pipe_whip("plain.h5", 0.0), tmp_path / "plain_results.h5")
    launch.run_engine(pipe_whip("reference.h5", 0.5), tmp_path / "reference_results.h5")
    stepped = pipe_whip("deck.h5", 0.5, checkpoint_interval=1.5e-4)
    launch.run_engine(stepped, tmp_path / "results.h5")
    shutil.copy(tmp_path / "results.h5", tmp_path / "restart.h5")
    shutil.copy(tmp_path / "results.checkpoint.h5", tmp_path / "restart.checkpoint.h5")
    with h5py.File(tmp_path / "restart.h5", "r+") as f:
        f.attrs["complete"] = np.int32(0)
    launch.run_engine(stepped, tmp_path / "restart.h5", 1, 1, restart=True)
    reference = displacement(tmp_path / "reference_results.h5")
    assert not np.array_equal(reference, displacement(tmp_path / "plain_results.h5"))
    assert np.array_equal(displacement(tmp_path / "restart.h5"), reference)
