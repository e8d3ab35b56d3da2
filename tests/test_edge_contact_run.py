"""Edge-to-edge contact in the engine (issue 35 item 2; docs/contact-edges.md): two thin steel strips,
walls of t = 0.08 mm (the thin_1000 pipes' wall), crossed at right angles and meeting edge first at
20 m/s at the automatic step. Strip A hangs in the x-z plane above strip B, which stands in the y-z
plane; their element edges cross between the nodes (every node is half an element, 1 mm, from the
crossing), so no node ever comes within reach of the other strip's surface. The runs have the
automatic step with its automatic contact limit (``contact_closing_limit`` 0.05 by default,
docs/contact-edges.md): the strips' edges, near and closing at 20 m/s, cut the step to
0.05 t / (20 m/s) = 0.2 us. Without that limit a node moves 0.085 t a step and the edge contact's
penalty, capped for stability at the stable fraction of m / dt^2, lets the first impact reach 0.26 t;
with the set travel limit 0.1 (twice the fastest node's speed) it reaches 0.084 t.

Checks:
- node-to-segment contact alone (the default) does not see the strips: A's lower edge goes through
  B's upper edge (the strips end up overlapping by more than a wall), and no contact force acts;
- with ``edges = true`` the strips stay apart: the deepest penetration stays below 0.2 t (the
  stability suite's criterion) and A's lower edge ends above B's upper edge;
- the deck kind ``edge_to_edge`` (what ``edges = true`` writes), and a single-surface contact of
  both strips with edges, give bitwise the same frames and contact histories on one and two ranks
  (the edge passes run in the replicated scheme there).
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import deck, scene
from paradyn._schema import ENUMS
from paradyn.running import launch

T = 8.0e-5          # wall (m): R / 1000 of the pipe-whip pipes
H = 2.0e-3          # element size (m)
GAP = 1.0e-4        # clearance between the contact surfaces at the start (m)


def _scene(edges: bool, single: bool = False, limits: str = "") -> str:
    z0 = T + GAP     # A's lower edge: a wall (two half walls) plus the gap above B's upper edge at z = 0
    return f"""
title = "edge-first crossing of two thin strips"
[run]
end_time = 6.0e-5
output_interval = 1.0e-5
history_interval = 1.0e-6
{limits}

[[material]]
name = "steel"
model = "j2_plasticity"
density = 7860.0
youngs_modulus = 200e9
poisson_ratio = 0.28
yield_stress = 250e6
tangent_modulus = 0.0

[[part]]
name = "a"
material = "steel"
thickness = {T}
initial_velocity = [0.0, 0.0, -20.0]
[part.geometry]
kind = "plate"
size = [0.02, 0.004]
elements = [10, 2]
origin = [-0.009, 0.0, {z0}]
u_axis = [1.0, 0.0, 0.0]
v_axis = [0.0, 0.0, 1.0]

[[part]]
name = "b"
material = "steel"
thickness = {T}
[part.geometry]
kind = "plate"
size = [0.02, 0.004]
elements = [10, 2]
origin = [0.0, -0.009, -0.004]
u_axis = [0.0, 1.0, 0.0]
v_axis = [0.0, 0.0, 1.0]

[[contact]]
parts = ["a", "b"]
edges = {"true" if edges else "false"}
{'kind = "single_surface"' if single else ""}
"""


def _model(tmp_path: Path, edges: bool, single: bool = False, limits: str = "") -> deck.Model:
    path = tmp_path / f"strips_{edges}_{single}_{len(limits)}.toml"
    path.write_text(_scene(edges, single, limits))
    return scene.build_model(scene.load_scene(path))


def _run(tmp_path: Path, edges: bool, ranks: int = 1, single: bool = False, limits: str = "") -> dict[str, np.ndarray]:
    model = _model(tmp_path, edges, single, limits)
    folder = tmp_path / f"run_{edges}_{ranks}_{single}_{len(limits)}"
    folder.mkdir(exist_ok=True)
    path = deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(path, folder / "results.h5", ranks, 1)
    with h5py.File(folder / "results.h5", "r") as f:
        out = {name: f[name][()] for name in ("/frames/displacement", "/frames/velocity",
                                              "/history/contact_penetration", "/history/contact_energy",
                                              "/history/dt")}
    # the nodes of the two elements at the crossing: A's lower edge within an element of x = 0, B's
    # upper edge within an element of y = 0
    x = model.coordinates[None, :, :] + out["/frames/displacement"][:, :, :3]
    n_a = model.n_nodes // 2
    x0 = model.coordinates
    near_a = np.flatnonzero((np.arange(model.n_nodes) < n_a) & (np.abs(x0[:, 0]) < 1.5 * H))
    near_b = np.flatnonzero((np.arange(model.n_nodes) >= n_a) & (np.abs(x0[:, 1]) < 1.5 * H))
    out["a_lowest"] = x[:, near_a, 2].min(axis=1)
    out["b_highest"] = x[:, near_b, 2].max(axis=1)
    return out


def test_scene_edges_write_the_edge_kind(tmp_path: Path) -> None:
    assert _model(tmp_path, True).contact_kind.tolist() == [ENUMS["contact_kind"]["edge_to_edge"]]
    assert _model(tmp_path, False).contact_kind.tolist() == [ENUMS["contact_kind"]["node_to_segment"]]


def test_thin_strips_crossing_edge_first_stay_apart_only_with_edges(tmp_path: Path) -> None:
    plain = _run(tmp_path, False)
    edged = _run(tmp_path, True)
    # node-to-segment: no node sees the other strip; A's edge passes B's by more than a wall
    assert plain["/history/contact_penetration"].max() == 0.0
    assert plain["a_lowest"][-1] < plain["b_highest"][-1] - T
    # edges: apart, the penetration under the suite's 0.2 t, A's edge above B's at the crossing
    penetration = edged["/history/contact_penetration"].max()
    assert 0.0 < penetration < 0.2 * T, penetration / T
    assert np.all(edged["a_lowest"] > edged["b_highest"])
    assert edged["/history/dt"].min() == pytest.approx(0.05 * T / 20.0, rel=0.02)   # the closing limit's step


def test_the_limits_set_how_deep_the_strips_meet(tmp_path: Path) -> None:
    """The automatic limit off: 0.26 t (under the stability suite's 0.2 t only with a limit); the set
    travel limit 0.1 (closing bounded by twice the fastest node): 0.084 t, shallower than the
    automatic 0.174 t (docs/contact-edges.md)."""
    off = _run(tmp_path, True, limits="contact_closing_limit = 0.0")
    travel = _run(tmp_path, True, limits="contact_travel_limit = 0.1")
    auto = _run(tmp_path, True)
    depth = {name: r["/history/contact_penetration"].max() / T for name, r in
             (("off", off), ("travel", travel), ("auto", auto))}
    assert depth["off"] > 0.2 > depth["auto"] > depth["travel"] > 0.0, depth


@pytest.mark.mpi
@pytest.mark.parametrize("single", [False, True], ids=["pair", "single_surface"])
def test_edge_contact_is_bitwise_on_one_and_two_ranks(tmp_path: Path, single: bool) -> None:
    """edge_to_edge, and a single_surface contact of both strips with edges (each strip's
    single_surface_edges definition and their edge_to_edge pair): the same frames and contact histories
    on one and two ranks; the single surface keeps the strips apart as the pair does."""
    one = _run(tmp_path, True, ranks=1, single=single)
    two = _run(tmp_path, True, ranks=2, single=single)
    if single:
        kinds = _model(tmp_path, True, True).contact_kind.tolist()
        assert sorted(kinds) == sorted([ENUMS["contact_kind"]["single_surface_edges"]] * 2
                                       + [ENUMS["contact_kind"]["edge_to_edge"]])
        assert one["/history/contact_penetration"].max() < 0.2 * T
        assert np.all(one["a_lowest"] > one["b_highest"])
    assert one["/history/contact_penetration"].max() > 0.0
    # the exact histories and the frames (the kinetic energy is a sum over each rank's nodes: not exact)
    for name in ("/frames/displacement", "/frames/velocity", "/history/contact_penetration", "/history/contact_energy"):
        assert np.array_equal(one[name], two[name]), name
