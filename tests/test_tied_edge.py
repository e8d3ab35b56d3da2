"""A shell edge tied to a surface transmits moments (LS-DYNA *CONTACT_TIED_SHELL_EDGE_TO_SURFACE;
docs/theory.md, "Rotation ties"; issue 32).

A T-joint: a steel flange 100 x 40 x 2 mm (8 x 4 shells, x along its length) clamped at x = 0,
and a web 100 x 40 x 2 mm (8 x 4 shells) standing on the flange's centre line, its bottom edge on
the flange's mid-surface; only the joint holds the web. The web's top corner at x = 100 mm is
pulled sideways (y) by 10 N, ramped over 2 ms and held, with mass damping to a quasi-static state
at 5 ms. The moment of that pull about the joint line goes into the flange through the joint.

- Reference: the same T with shared nodes (each web node on the joint welded to the flange node
  it lies on: a rigid body of two coincident nodes, which is the merged node to rounding).
- Tied: the web joined by a tied contact (its places) and rotation ties (its rotations): the tip
  deflection within 1 % of the reference's (issue 32: 2 %).
- Tied without the rotation ties: a hinge along the joint line, the web swings away (more than
  3 times the reference's deflection at the end, and growing): the moment needs the rotation ties.
"""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

import paradyn
from paradyn.deck.rigid_bodies import complete_rigid_bodies
from paradyn.deck.rotation_ties import add_rotation_ties
from paradyn.keyword.scene import load_keyword
from paradyn.running import launch
from test_keyword import HEAD, MESH

L, B, H, T = 0.1, 0.04, 0.04, 0.002
PULL = 10.0
END = 5e-3


def _t_joint(join: str, web_elements: int = 8) -> paradyn.deck.Model:
    scene = paradyn.Scene("T-joint", end_time=END, output_interval=END / 5, history_interval=END / 100,
                          mass_damping=3.0e3)
    scene.add_material("steel", model="elastic", density=7850.0, youngs_modulus=200e9, poisson_ratio=0.3)
    scene.add_part("flange", material="steel", thickness=T,
                   geometry=paradyn.Plate(size=(L, B), elements=(8, 4), origin=[0.0, -B / 2, 0.0]))
    scene.add_part("web", material="steel", thickness=T,
                   geometry=paradyn.Plate(size=(L, H), elements=(web_elements, 4), origin=[0.0, 0.0, 0.0],
                                          u_axis=[1.0, 0.0, 0.0], v_axis=[0.0, 0.0, 1.0]))
    scene.add_fix("flange", box=[[-1e-6, -1.0, -1.0], [1e-6, 1.0, 1.0]])
    scene.add_load("web", point=[L, 0.0, H], dof="uy", value=PULL, ramp_time=2e-3)
    scene.add_track("tip", part="web", point=[L, 0.0, H])
    if join != "welded":
        scene.add_contact("web", "flange", kind="tied")
    model = scene.build()
    x, part = np.asarray(model.coordinates), np.asarray(model.element_part)
    conn = np.asarray(model.connectivity)
    if join == "welded":
        flange, web = np.unique(conn[part == 0]), np.unique(conn[part == 1])
        pairs = [[int(f), int(w)] for w in web if abs(x[w, 2]) < 1e-12
                 for f in flange if np.linalg.norm(x[f] - x[w]) < 1e-12]
        assert len(pairs) == 9
        complete_rigid_bodies(model, nodal=pairs)
    elif join == "tied":
        assert add_rotation_ties(model, 1, 0) == web_elements + 1
    paradyn.deck.validate_model(model)
    return model


def _tip(model: paradyn.deck.Model, folder: Path) -> np.ndarray:
    folder.mkdir(parents=True, exist_ok=True)
    paradyn.deck.write_deck(model, folder / "deck.h5")
    launch.run_engine(folder / "deck.h5", folder / "results.h5", 1, 1)
    with h5py.File(folder / "results.h5") as f:
        return f["history/tracked_displacement"][:, 0, :]


@pytest.fixture(scope="module")
def tips(tmp_path_factory: pytest.TempPathFactory) -> dict[str, np.ndarray]:
    folder = tmp_path_factory.mktemp("tjoint")
    runs = {join: _tip(_t_joint(join), folder / join) for join in ("welded", "tied", "hinged")}
    runs["tied_12"] = _tip(_t_joint("tied", 12), folder / "tied_12")
    return runs


def test_a_tied_edge_bends_as_the_shared_node_joint(tips: dict[str, np.ndarray]) -> None:
    """The tip's sideways deflection at the quasi-static end within 1 % of the shared-node T's
    (issue 32 asks 2 %; measured +0.06 %), and with a web of 12 shells along x, its nodes between
    the flange's, too (+0.25 %, the web's finer mesh included). A tie that turned the clamped
    flange nodes it shares a segment with (a held rotation taking impulses) is off by 1.4 %."""
    reference = tips["welded"][-1, 1]
    assert reference > 1e-5
    assert tips["tied"][-1, 1] == pytest.approx(reference, rel=0.01)
    assert tips["tied_12"][-1, 1] == pytest.approx(reference, rel=0.01)


def test_without_rotation_ties_the_joint_is_a_hinge(tips: dict[str, np.ndarray]) -> None:
    """The tied contact alone holds places, not rotations: the web swings about the joint line,
    more than 3 times the reference's deflection by the end and still going."""
    hinged = tips["hinged"][:, 1]
    assert hinged[-1] > 3.0 * tips["welded"][-1, 1]
    assert hinged[-1] > 1.5 * hinged[len(hinged) // 2]


@pytest.mark.mpi
def test_rotation_ties_are_bitwise_the_same_on_two_ranks(tmp_path: Path) -> None:
    """The tied nodes' values are gathered from their owners alone and every rank holds the ties
    alike: the frames on 2 ranks are those of 1 rank bit for bit."""
    model = _t_joint("tied", 12)
    model.control.end_time = 1e-3
    frames = {}
    for ranks in (1, 2):
        folder = tmp_path / f"ranks{ranks}"
        folder.mkdir()
        paradyn.deck.write_deck(model, folder / "deck.h5")
        launch.run_engine(folder / "deck.h5", folder / "results.h5", ranks, 1)
        with h5py.File(folder / "results.h5") as f:
            frames[ranks] = f["frames/displacement"][:]
    assert np.array_equal(frames[1], frames[2])


def test_the_keyword_ties_a_shell_edge_with_its_rotations(tmp_path: Path) -> None:
    """*CONTACT_TIED_SHELL_EDGE_TO_SURFACE_OFFSET (slave part 2, a web standing on the plate of
    the keyword tests along y = 0.25 m): its two bottom nodes tied to the plate's elements with
    their rotations, at the bilinear shape functions of their places (node 31 at x = 0, the first
    element's edge midpoint: 1/2, 0, 0, 1/2 ... ); *CONTACT_TIED_NODES_TO_SURFACE ties places only."""
    web = ("*PART\nweb\n         2         1         1\n*NODE\n"
           "      31             0.0            0.25             0.0\n"
           "      32             1.0            0.25             0.0\n"
           "      33             1.0            0.25             0.5\n"
           "      34             0.0            0.25             0.5\n"
           "*ELEMENT_SHELL\n     201       2      31      32      33      34\n")
    for keyword, ties in (("*CONTACT_TIED_SHELL_EDGE_TO_SURFACE_OFFSET", 2),
                          ("*CONTACT_TIED_NODES_TO_SURFACE_OFFSET", 0)):
        path = tmp_path / "edge.k"
        path.write_text(HEAD + MESH + web + keyword + "\n         2         1         3         3\n\n\n*END\n")
        model = load_keyword(path).model
        nodes = [] if model.rotation_tie_node is None else list(model.rotation_tie_node)
        assert len(nodes) == ties
        if ties:
            ids = np.asarray(model.node_ids)
            assert sorted(ids[nodes].tolist()) == [31, 32]
            first = nodes.index(int(np.flatnonzero(ids == 31)[0]))
            weights = dict(zip(ids[model.rotation_tie_masters[first]].tolist(),
                               model.rotation_tie_weights[first].tolist(), strict=True))
            assert weights == pytest.approx({11: 0.5, 12: 0.0, 15: 0.0, 14: 0.5})
