"""Tied contact (``[[contact]] kind = "tied"``; docs/theory.md, Tied contact).

A lap joint: two steel strips 2 mm thick, stacked at their half thicknesses (the tie's reach) and
overlapping by 40 mm, with meshes that do not match (the pulled strip's nodes fall inside the held
strip's elements). The held strip is clamped at its far end, the pulled strip loaded in x at its
far end (a ramp, then held, with mass damping for a quasi-static state); the out-of-plane dofs
are held, so the joint works in its plane (a membrane). Only the tie connects the strips.

Checks:
- the pulled strip's 20 nodes over the held strip follow their tied points (the held strip's
  displacement there, by its element's shape functions) within 1e-3 of the thickness, and at the
  quasi-static end the force the tie transmits (the definition's force on its first part,
  ``/history/contact_force``) equals the applied load within 2 % (the pulled strip's only other
  force is the load);
- the tie starts free of force: unloaded strips inside each other's contact thickness are not
  moved apart by the start-up checks (which skip tied definitions) and do not move;
- nodes out of reach stay free: the pulled strip raised by 5 % of the reach is not tied and
  moves off under the load, with no contact force;
- 1 rank and 2 ranks (local contact, the elements given by blocks or by coordinate bisection,
  so that tied points' segments are ghosts of the other rank; and the replicated scheme) give
  bitwise the same frames, contact force and contact energy.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

import paradyn
from paradyn import deck
from paradyn.running import launch

T = 0.002           # shell thickness (m)
W = 0.05            # strip width (m)
LENGTH = 0.2        # each strip's length (m)
OVERLAP = 0.04      # the overlap (m)
LOAD = 200.0        # total pull (N)
END_TIME = 2.0e-3


def _lap_joint(load: float = LOAD, z: float = T) -> paradyn.Scene:
    """The pulled strip (first part, slave) at height z over the held strip (second, master)."""
    scene = paradyn.Scene("lap joint", end_time=END_TIME, output_interval=END_TIME / 4, mass_damping=3.0e4)
    scene.add_material("steel", model="elastic", density=7850.0, youngs_modulus=200e9, poisson_ratio=0.3)
    start = LENGTH - OVERLAP
    scene.add_part("pulled", material="steel", thickness=T,
                   geometry=paradyn.Plate(size=(LENGTH, W), elements=(16, 4), origin=[start, 0.0, z]))
    scene.add_part("held", material="steel", thickness=T, geometry=paradyn.Plate(size=(LENGTH, W), elements=(20, 5)))
    scene.add_contact("pulled", "held", kind="tied")
    scene.add_fix("held", box=[[-1e-6, -1e-6, -1e-6], [1e-6, W + 1e-6, 1e-6]])
    for part, height in (("pulled", z), ("held", 0.0)):   # a membrane: the out-of-plane dofs held
        scene.add_fix(part, box=[[-1.0, -1.0, height - 1e-6], [1.0, 1.0, height + 1e-6]], dofs=["uz", "rx", "ry"])
    if load:
        for y, weight in zip(np.linspace(0.0, W, 5), [0.125, 0.25, 0.25, 0.25, 0.125], strict=True):
            scene.add_load("pulled", point=[start + LENGTH, y, z], dof="ux", value=weight * load,
                           ramp_time=END_TIME / 4)
    return scene


def _tie_gaps(res: Any, frame: int) -> np.ndarray:
    """|u_node - u(tied point)| of the pulled strip's nodes over the held strip: the held strip's
    displacement at the node's (x, y) by the bilinear shape functions of the element under it."""
    u = np.asarray(res.displacement[frame])
    x = res.coordinates
    pulled = np.unique(res.connectivity[res.element_part == res.part_index("pulled")])
    held = res.connectivity[res.element_part == res.part_index("held")]
    lo, hi = x[held].min(axis=1), x[held].max(axis=1)
    gaps = []
    for node in pulled:
        p = x[node]
        under = np.flatnonzero(np.all((p[:2] >= lo[:, :2] - 1e-12) & (p[:2] <= hi[:, :2] + 1e-12), axis=1))
        if under.size == 0:
            continue
        e = held[under[0]]
        xi = 2.0 * (p[0] - x[e, 0].min()) / np.ptp(x[e, 0]) - 1.0
        eta = 2.0 * (p[1] - x[e, 1].min()) / np.ptp(x[e, 1]) - 1.0
        shape = 0.25 * np.array([(1 - xi) * (1 - eta), (1 + xi) * (1 - eta), (1 + xi) * (1 + eta),
                                 (1 - xi) * (1 + eta)])
        gaps.append(np.linalg.norm(u[node] - shape @ u[e]))
    return np.array(gaps)


@pytest.fixture(scope="module")
def lap(tmp_path_factory: pytest.TempPathFactory) -> dict:
    folder = tmp_path_factory.mktemp("tied")
    return {"folder": folder, "res": paradyn.run(_lap_joint(), folder / "one", ranks=1, threads=1, post=False)}


def test_the_strips_move_together_and_transmit_the_load(lap: dict) -> None:
    res = lap["res"]
    gaps = _tie_gaps(res, -1)
    assert gaps.size == 4 * 5                      # the pulled strip's 4 columns of 5 over the held one
    assert np.asarray(res.displacement[-1])[:, 0].max() > 1.0e-6   # the joint did stretch (about 3.6 um)
    assert gaps.max() < 1.0e-3 * T, gaps.max()
    force = res.history["contact_force"][-1, 0]
    assert abs(-force[0] - LOAD) < 0.02 * LOAD, force
    assert np.abs(force[1:]).max() < 0.02 * LOAD, force


def test_the_tie_starts_without_force(tmp_path: Path) -> None:
    """Unloaded strips 10 % closer than the reach (inside each other's contact thickness): a
    node_to_segment contact would move them apart before the run and push; tied, nothing moves."""
    res = paradyn.run(_lap_joint(load=0.0, z=0.9 * T), tmp_path, ranks=1, threads=1, post=False)
    assert np.array_equal(np.asarray(res.displacement[0]), np.zeros_like(res.coordinates))   # no initial move
    assert np.abs(np.asarray(res.displacement[-1])).max() < 1.0e-9 * T
    assert res.history["contact_penetration"].max() == 0.0


def test_nodes_out_of_reach_stay_free(tmp_path: Path) -> None:
    res = paradyn.run(_lap_joint(z=1.05 * T), tmp_path, ranks=1, threads=1, post=False)
    assert np.abs(res.history["contact_force"]).max() == 0.0
    pulled = np.unique(res.connectivity[res.element_part == res.part_index("pulled")])
    # damped, it drifts off at F / (damping m): about 70 um by the end, ten times the tied joint's stretch
    assert np.asarray(res.displacement[-1])[pulled, 0].min() > 5.0e-5


@pytest.mark.mpi
def test_other_layouts_give_the_one_rank_answer_bitwise(lap: dict) -> None:
    """Local contact on 2 ranks by element blocks and by coordinate bisection, and the replicated
    scheme (contact_gather = "all"), against the one-rank run of the same deck."""
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    folder = lap["folder"]
    model = _lap_joint().build()
    runs = {}
    for name, ranks, partition, gather in (("one", 1, None, None), ("blocks", 2, "blocks", None),
                                           ("rcb", 2, "rcb", None), ("all", 2, None, "all")):
        model.control.partition, model.control.contact_gather = partition, gather
        deck_path = deck.write_deck(model, folder / f"deck_{name}.h5")
        launch.run_engine(deck_path, folder / f"results_{name}.h5", ranks, 1)
        with h5py.File(folder / f"results_{name}.h5", "r") as f:
            runs[name] = {key: f[key][()] for key in ("/frames/displacement", "/history/contact_force",
                                                       "/history/contact_energy")}
    assert abs(-runs["one"]["/history/contact_force"][-1, 0, 0] - LOAD) < 0.02 * LOAD
    for name in ("blocks", "rcb", "all"):
        for key, values in runs["one"].items():
            assert np.array_equal(runs[name][key], values), (name, key)
