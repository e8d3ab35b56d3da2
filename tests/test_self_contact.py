"""Single-surface (self) contact (issue 15 item 1; docs/theory.md, Single-surface contact).

A part is slave to its own shell segments: a node never meets the segments that contain it, and
its nearest-master search skips its own neighbours. The contact thickness is the shell's, capped
at 0.4 of the part's shortest edge (LS-DYNA's default for its single-surface contacts), so a smooth
surface never touches itself however thick it is.

Checks:
- two plates that are one part, single-surface, give bitwise the answer of the same plates as two
  parts in a symmetric pair contact (the same node-segment interactions, summed in the same
  order: the plates' nodes are numbered one plate after the other);
- a smooth plate vibrating under single-surface contact, even with walls thicker than its
  elements, never touches itself: bitwise the run without contact, and no initial penetration;
- the scene's ``kind = "single_surface"`` becomes one self definition per part and a pair per
  two parts; wrong ``parts`` are refused by the scene reader and by both deck validators.
The 100 m/s crush (rings that fold onto themselves) is in tests/stability/test_crush_self_contact.py.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import h5py
import numpy as np
import pytest

import models as M
from contact_cases import STEEL, T, _control, _plate_pair
from paradyn import _schema, deck, scene
from paradyn._schema import ENUMS
from paradyn.deck import Control
from paradyn.mesh import geometry
from paradyn.running import launch

SINGLE = ENUMS["contact_kind"]["single_surface"]


def _plates(v: float = 5.0, one_part: bool = False) -> M.Assembly:
    """Two plates closing at 2 v, as two parts in a pair contact or as one part, single-surface."""
    a_mesh, b_mesh = _plate_pair(1.0e-4, shift=0.004)
    control = _control(40.0e-6, 0.1, M.stable_time_step(a_mesh, STEEL))
    if not one_part:
        return M.contact_model([M.Body(a_mesh, T, (0, 0, v)), M.Body(b_mesh, T, (0, 0, -v))], STEEL, control,
                               tracked=[0, a_mesh.n_nodes])
    both = geometry.Mesh(coordinates=np.concatenate([a_mesh.coordinates, b_mesh.coordinates]),
                         quads=np.concatenate([a_mesh.quads, b_mesh.quads + a_mesh.n_nodes]))
    asm = M.contact_model([M.Body(both, T)], STEEL, control, pairs=[(0, 0)], tracked=[0, a_mesh.n_nodes])
    asm.model.initial_velocity = np.repeat([[0.0, 0.0, v], [0.0, 0.0, -v]], a_mesh.n_nodes, axis=0)
    asm.model.contact_kind = np.array([SINGLE], dtype=np.int32)
    return asm


def test_two_plates_as_one_surface_are_the_pair_contact(tmp_path: Path) -> None:
    pair = M.run(_plates().model, tmp_path / "pair").results
    single = M.run(_plates(one_part=True).model, tmp_path / "single").results
    assert pair.history["contact_penetration"].max() > 0.01 * T   # they do touch
    for name in ("kinetic_energy", "internal_energy", "contact_energy", "contact_penetration",
                 "tracked_displacement"):
        assert np.array_equal(single.history[name], pair.history[name]), name
    assert np.array_equal(single.displacement[-1], pair.displacement[-1])


@pytest.mark.mpi
def test_single_surface_contact_on_several_ranks_is_bitwise(tmp_path: Path) -> None:
    """Local contact between ranks (docs/theory.md, parallel contact) takes a slave's own
    neighbours, which its nearest-master search skips, to their places among the masters a rank
    holds: the two plates as one single-surface part give bitwise the same frames and contact
    histories on 1, 2 and 3 ranks (the plates are cut between ranks by element number)."""
    path = deck.write_deck(_plates(one_part=True).model, tmp_path / "deck.h5")
    runs = {}
    for ranks in (1, 2, 3):
        launch.run_engine(path, tmp_path / f"results_{ranks}.h5", ranks, 1)
        with h5py.File(tmp_path / f"results_{ranks}.h5", "r") as f:
            runs[ranks] = {name: f[name][()] for name in ("/frames/displacement", "/history/contact_energy",
                                                          "/history/contact_penetration")}
    assert runs[1]["/history/contact_penetration"].max() > 0.01 * T
    for ranks in (2, 3):
        for name, values in runs[1].items():
            assert np.array_equal(runs[ranks][name], values), (ranks, name)


@pytest.mark.parametrize("thickness", [0.002, 0.02])
def test_a_smooth_vibrating_plate_never_touches_itself(tmp_path: Path, thickness: float) -> None:
    """A clamped 8 x 8 plate (h = 12.5 mm) given a bending velocity field; t = 20 mm is thicker than
    its elements, where only the 0.4 h cap keeps neighbours out of reach."""
    mesh = M.flat_plate((0.1, 0.1), (8, 8))
    x, y = mesh.coordinates[:, 0], mesh.coordinates[:, 1]
    velocity = np.zeros_like(mesh.coordinates)
    velocity[:, 2] = 20.0 * np.sin(np.pi * x / 0.1) * np.sin(np.pi * y / 0.1)
    edge = (np.isclose(x, 0) | np.isclose(x, 0.1) | np.isclose(y, 0) | np.isclose(y, 0.1))

    def model(self_contact: bool) -> deck.Model:
        control = Control(end_time=2.0e-4, output_interval=5.0e-5, history_interval=5.0e-6)
        asm = M.contact_model([M.Body(mesh, thickness)], STEEL, control,
                              pairs=[(0, 0)] if self_contact else ())
        asm.model.initial_velocity = velocity
        asm.model.fixed_dofs = np.repeat(edge[:, None].astype(np.int32), 6, axis=1)
        if self_contact:
            asm.model.contact_kind = np.array([SINGLE], dtype=np.int32)
        return asm.model

    free = M.run(model(False), tmp_path / "free").results
    single = M.run(model(True), tmp_path / "single").results
    assert free.history["internal_energy"].max() > 0.1 * free.history["kinetic_energy"][0]
    assert np.all(single.history["contact_energy"] == 0.0)
    assert np.all(single.history["contact_penetration"] == 0.0)
    assert np.array_equal(single.displacement, free.displacement)
    assert "initial penetration" not in (tmp_path / "single" / "engine.log").read_text()


SCENE = """
title = "self"
[run]
end_time = 1e-5
output_interval = 1e-5
history_interval = 1e-6
[[material]]
name = "steel"
model = "elastic"
density = 7850.0
youngs_modulus = 2e11
poisson_ratio = 0.3
"""


def _scene(tmp_path: Path, contact: str, n_parts: int = 3) -> Path:
    parts = "".join(f"""
[[part]]
name = "p{i}"
material = "steel"
thickness = 0.002
[part.geometry]
kind = "plate"
size = [0.1, 0.1]
elements = [2, 2]
origin = [0.0, 0.0, {0.05 * i}]
""" for i in range(n_parts))
    path = tmp_path / "scene.toml"
    path.write_text(SCENE + parts + "\n[[contact]]\n" + contact + "\n")
    return path


@pytest.mark.parametrize(("contact", "pairs", "kinds"), [
    ('kind = "single_surface"', [[0, 0], [1, 1], [2, 2], [0, 1], [0, 2], [1, 2]],
     ["single_surface"] * 3 + ["node_to_segment"] * 3),
    ('kind = "single_surface"\nparts = ["p1"]', [[1, 1]], ["single_surface"]),
    ('kind = "single_surface"\nparts = ["p2", "p0"]', [[2, 2], [0, 0], [2, 0]],
     ["single_surface", "single_surface", "node_to_segment"]),
])
def test_scene_single_surface_becomes_self_and_pair_definitions(tmp_path: Path, contact: str, pairs: list,
                                                                kinds: list) -> None:
    model = scene.build_model(scene.load_scene(_scene(tmp_path, contact)))
    assert model.contact_pairs.tolist() == pairs
    assert model.contact_kind.tolist() == [ENUMS["contact_kind"][k] for k in kinds]
    both = ENUMS["contact_passes"]["both"]
    assert model.contact_passes.tolist() == [both] * len(pairs)


@pytest.mark.parametrize(("contact", "message"), [
    ('parts = ["p1"]', 'use kind = "single_surface"'),
    ('parts = ["p1", "p1"]', 'use kind = "single_surface"'),
    ('kind = "single_surface"\nparts = ["p1", "p1"]', "must list different parts"),
    ('kind = "single_surface"\nparts = ["p9"]', "names part 'p9', which is not defined"),
])
def test_scene_refuses_wrong_parts(tmp_path: Path, contact: str, message: str) -> None:
    with pytest.raises(scene.SceneError, match=message.replace("(", r"\(")):
        scene.build_model(scene.load_scene(_scene(tmp_path, contact)))


@pytest.mark.parametrize(("pairs", "kind", "message"), [
    ([0, 1], SINGLE, "names two parts for a single_surface contact"),
    ([1, 1], ENUMS["contact_kind"]["node_to_segment"], "pairs a part with itself"),
])
def test_both_validators_refuse_a_mismatched_definition(tmp_path: Path, pairs: list, kind: int,
                                                        message: str) -> None:
    path = deck.write_deck(_plates().model, tmp_path / "deck.h5")
    with h5py.File(path, "r+") as f:
        f["/contact/pairs"][0] = pairs
        f["/contact/kind"][0] = kind
    with pytest.raises(deck.DeckError, match=message):
        deck.validate_deck(path)
    done = subprocess.run([str(launch.engine_path()), str(path), str(tmp_path / "results.h5")], cwd=tmp_path,
                          env=launch.engine_environment(1), capture_output=True, text=True, timeout=60)
    assert done.returncode == _schema.STATUS_BAD_INPUT and message in done.stderr, done.stderr
