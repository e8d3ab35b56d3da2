"""Initial penetration (issue 15 item 2): slave nodes that start inside the contact thickness are
found before the run, reported (how many, deepest, where) and handled as the contact asks: moved
onto the surface (the default) or their overlap kept as their gap (docs/theory.md, Contact).

Two parallel steel plates at rest, 10 mm thick, mid-surfaces 6 mm apart: every node of each is
4 mm inside the other's contact thickness (reach (t + t)/2 = 10 mm). Nothing moves them, so the
right answer is that nothing moves: no contact energy, no kinetic energy. Left alone, the penalty
springs would throw the plates apart.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import models as M
import paradyn
from paradyn._schema import ENUMS
from paradyn.deck import Control

T = 0.01
GAP = 0.006   # mid-surface distance; reach 0.01, so 0.004 inside
STEEL = M.Material(young=200.0e9, poisson=0.3, density=7850.0)


def _plates(tmp_path, mode: str | None):
    lower = M.flat_plate((0.1, 0.1), (4, 4))
    upper = M.flat_plate((0.1, 0.1), (4, 4), origin=(0.0, 0.0, GAP))
    control = Control(end_time=2.0e-4, output_interval=1.0e-4, history_interval=1.0e-5)
    asm = M.contact_model([M.Body(lower, T), M.Body(upper, T)], STEEL, control)
    if mode is not None:
        asm.model.contact_initial_penetration = np.array([ENUMS["initial_penetration"][mode]], dtype=np.int32)
    run = M.run(asm.model, tmp_path)
    log = (tmp_path / "engine.log").read_text()
    return run.results, log


def test_moved_onto_the_surface_by_default(tmp_path):
    """The default moves the first pass's slaves (part 0, the lower plate) 4 mm down, onto the
    upper plate's contact surface: the log names the 25 nodes, the depth 4.000e-03 m and the
    action; after the move the other pass finds nothing; the plates then stay at rest (kinetic and
    contact energy below 1e-12 J) 10 mm apart."""
    results, log = _plates(tmp_path, None)
    line = next(x for x in log.splitlines() if "initial penetration in /contact/pairs[0]" in x)
    assert "25 nodes of part 0" in line and "deepest 4.000E-03 m (0.400 of the reach" in line
    assert "moved onto the surface" in line
    assert "still inside" not in log
    h = results.history
    assert np.max(np.abs(h["kinetic_energy"])) < 1e-12
    assert np.max(np.abs(h["contact_energy"])) < 1e-12
    dz = results.frame_arrays(0).displacement[:, 2]   # the move shows as an initial displacement
    assert np.allclose(dz[:25], -0.004, rtol=0, atol=1e-15) and np.all(dz[25:] == 0.0)


def test_overlap_kept_as_the_gap(tmp_path):
    """initial_penetration = "gap": nothing moves, the log says so, and the plates stay at rest:
    each slave's reach is shortened by its overlap, so contact pushes only past it."""
    results, log = _plates(tmp_path, "gap")
    lines = [x for x in log.splitlines() if "initial penetration in /contact/pairs[0]" in x]
    assert len(lines) == 2 and all("kept as the initial gap" in x for x in lines)
    h = results.history
    assert np.max(np.abs(h["kinetic_energy"])) < 1e-12
    assert np.max(np.abs(h["contact_energy"])) < 1e-12


def test_kept_gap_still_pushes_past_the_overlap(tmp_path):
    """The gap mode is not contact switched off: the same plates with the upper one moving down at
    5 m/s touch as soon as it moves past its kept overlap, and push the lower plate down (its
    centre node's velocity turns negative; contact energy rises above zero)."""
    lower = M.flat_plate((0.1, 0.1), (4, 4))
    upper = M.flat_plate((0.1, 0.1), (4, 4), origin=(0.0, 0.0, GAP))
    control = Control(end_time=2.0e-4, output_interval=1.0e-4, history_interval=1.0e-5)
    asm = M.contact_model([M.Body(lower, T), M.Body(upper, T, (0.0, 0.0, -5.0))], STEEL, control,
                          tracked=[12])   # the lower plate's centre node
    asm.model.contact_initial_penetration = np.array([ENUMS["initial_penetration"]["gap"]], dtype=np.int32)
    h = M.run(asm.model, tmp_path).results.history
    assert np.max(h["contact_energy"]) > 0.0
    assert h["tracked_velocity"][-1, 0, 2] < -0.5


def test_kept_gap_is_bitwise_on_several_ranks(tmp_path):
    """Under local contact a rank keeps the overlaps (and clearances) of its own slaves alone, the
    overlaps measured against the master elements near them from every rank (contact_local_setup's
    gap_overlaps, not the global layout): the kept-gap plates of the test above, pushing past their overlap,
    give bitwise the same frames and contact histories on 2 and 3 ranks as on one. The upper plate
    overlaps half of the lower one, so the slaves' overlaps differ (4 mm, less at the edges, 0)."""
    lower = M.flat_plate((0.1, 0.1), (4, 4))
    upper = M.flat_plate((0.1, 0.1), (4, 4), origin=(0.05, 0.0, GAP))
    control = Control(end_time=2.0e-4, output_interval=1.0e-4, history_interval=1.0e-5)
    asm = M.contact_model([M.Body(lower, T), M.Body(upper, T, (0.0, 0.0, -5.0))], STEEL, control)
    asm.model.contact_initial_penetration = np.array([ENUMS["initial_penetration"]["gap"]], dtype=np.int32)
    runs = [paradyn.run(asm.model, tmp_path / str(ranks), ranks=ranks, threads=1, post=False) for ranks in (1, 2, 3)]
    reference = runs[0]
    assert np.max(reference.history["contact_energy"]) > 0.0
    last = reference.n_frames - 1
    for other in runs[1:]:
        for key in ("contact_energy", "contact_penetration", "contact_force"):
            assert np.array_equal(other.history[key], reference.history[key]), key
        assert np.array_equal(other.frame_arrays(last).displacement, reference.frame_arrays(last).displacement)
        assert np.array_equal(other.frame_arrays(last).velocity, reference.frame_arrays(last).velocity)


def _scene_text(mode: str, height: float) -> str:
    return f'''
title = "t"
[run]
end_time = 1e-4
output_interval = 5e-5
history_interval = 1e-5
[[material]]
name = "steel"
model = "elastic"
density = 7850.0
youngs_modulus = 200e9
poisson_ratio = 0.3
[[part]]
name = "a"
material = "steel"
thickness = 0.01
[part.geometry]
kind = "plate"
size = [0.1, 0.1]
elements = [2, 2]
[[part]]
name = "b"
material = "steel"
thickness = 0.01
[part.geometry]
kind = "plate"
size = [0.1, 0.1]
elements = [2, 2]
origin = [0.0, 0.0, {height}]
[[contact]]
parts = ["a", "b"]
initial_penetration = "{mode}"
'''


@pytest.mark.parametrize("mode", ["move", "gap"])
def test_scene_key_reaches_the_deck(tmp_path, mode):
    """[[contact]] initial_penetration in a scene sets /contact/initial_penetration."""
    from paradyn import scene

    path = tmp_path / "scene.toml"
    path.write_text(_scene_text(mode, 0.05))
    model = scene.build_model(scene.load_scene(path))
    assert model.contact_initial_penetration.tolist() == [ENUMS["initial_penetration"][mode]]


def test_paradyn_run_prints_the_penetration_at_the_end(tmp_path, capsys):
    """Never silent: paradyn-run repeats the engine's warning after the accuracy line, where a
    person watching the terminal reads it (issue 15)."""
    from paradyn import cli

    path = tmp_path / "scene.toml"
    path.write_text(_scene_text("move", 0.006))
    status = cli.main([str(path), "-o", str(tmp_path / "run"), "-n", "1", "-t", "1", "-q", "--no-plots", "--no-vtk"])
    assert status == 0
    out = capsys.readouterr().out.splitlines()
    accuracy = next(i for i, line in enumerate(out) if line.startswith("  accuracy:"))
    assert any("warning: initial penetration in /contact/pairs[0]: 9 nodes of part 0" in line
               for line in out[accuracy + 1:])


def _tilted_plates_with_a_skirt() -> M.Model:
    """A tilted upper plate (part 1, z = 4 mm + 0.1 y) over a flat lower one (part 0), 6 x 6
    elements each, and a skirt (part 2, in no contact pair, 6 x 3 elements) hanging on the lower
    plate's edge y = 0, whose 7 nodes it shares: numbered last, the skirt's elements lie on the
    last rank of 3, which holds those nodes through them alone."""
    lower = M.flat_plate((0.1, 0.1), (6, 6))
    upper = M.flat_plate((0.1, 0.1), (6, 6))
    upper.coordinates[:, 2] = 0.004 + 0.1 * upper.coordinates[:, 1]
    skirt = M.flat_plate((0.1, 0.05), (6, 3), origin=(0.0, -0.05, 0.0))
    control = Control(end_time=2.0e-5, output_interval=1.0e-5, history_interval=1.0e-5)
    model = M.contact_model([M.Body(lower, T), M.Body(upper, T), M.Body(skirt, T)], STEEL, control).model
    total = len(model.coordinates)
    n = total - 7   # the skirt's last row (its last 7 nodes) is the lower plate's first row
    model.connectivity = np.where(model.connectivity >= n, model.connectivity - n, model.connectivity)
    for field in dataclasses.fields(model):   # every per-node array loses the skirt's last row
        value = getattr(model, field.name)
        if isinstance(value, np.ndarray) and value.ndim > 0 and len(value) == total:
            setattr(model, field.name, value[:n])
    return model


@pytest.mark.mpi
def test_same_report_and_moves_on_one_and_three_ranks(tmp_path):
    """Each rank checks the slave nodes of its own elements against the other part's elements near
    them (contact_checks). The lower plate's edge y = 0 is 6 mm inside the reach and rows farther
    up less or not at all, so the deepest depth is shared by a row of nodes (the lowest id is
    named) and the rows are spread over the ranks' element blocks; the edge's nodes are also held
    by the rank of the skirt, which must move them too. On 3 ranks the engine names the same count,
    depth, node and position as on one, moves every node by the same bits, and runs to the same
    end."""
    import paradyn

    model = _tilted_plates_with_a_skirt()
    reports, moves, ends = [], [], []
    for ranks in (1, 3):
        folder = tmp_path / f"ranks{ranks}"
        results = paradyn.run(model, folder, ranks=ranks, threads=1, post=False)
        log = (folder / "engine.log").read_text()
        reports.append([x for x in log.splitlines() if "initial penetration in" in x])
        moves.append(results.frame_arrays(0).displacement)
        ends.append(results.frame_arrays(results.n_frames - 1).displacement)
    # moved, the other pass after the move, and a round-off remainder of the first pass
    assert len(reports[0]) == 3 and "28 nodes of part 0" in reports[0][0] and "at node 0 near" in reports[0][0]
    assert "nodes of part 1" in reports[0][1] and "still inside after the move" in reports[0][2]
    assert reports[1] == reports[0]
    assert np.min(moves[0][:7, 2]) < -0.005 and np.array_equal(moves[1], moves[0])
    assert np.array_equal(ends[1], ends[0])
