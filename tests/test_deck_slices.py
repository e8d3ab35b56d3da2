"""Each rank reads only its share of the deck (issue 19, item 5; docs/formats.md, "The deck in the
engine").

The engine reads the mesh's datasets in blocks: rank r of P reads elements and nodes
floor(r n / P) + 1 .. floor((r + 1) n / P) (parallel HDF5 hyperslabs), then holds its elements and
the rows of the nodes they touch; its PARADYN-DECK line says how many rows each rank read and
holds. The checks run on those rows and are agreed over the ranks: a bad value or a broken
relation on rows that only the last rank reads gives the message one rank gives, naming the same
(lowest) entry, and the deck fingerprint a checkpoint carries is the same on any rank count.
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import benchmark, deck
from paradyn.mesh import geometry
from paradyn.running import launch

pytestmark = pytest.mark.mpi

RANKS = 3
NX, NY = 6, 3   # 18 elements, 28 nodes: node ids row by row, 7 per row


def _model(partition: str = "blocks", mesh: geometry.Mesh | None = None) -> deck.Model:
    mesh = mesh or geometry.plate((0.06, 0.03), (NX, NY))
    return deck.Model(
        coordinates=mesh.coordinates,
        connectivity=mesh.quads,
        element_part=np.zeros(mesh.n_elements, dtype=np.int32),
        thickness=np.array([0.001]),
        part_material=np.array([0]),
        material_model=np.array([1]),
        density=np.array([7860.0]),
        youngs_modulus=np.array([200e9]),
        poisson_ratio=np.array([0.3]),
        initial_velocity=np.tile([0.0, 0.0, 1.0], (mesh.n_nodes, 1)),
        tracked_nodes=np.array([mesh.n_nodes - 1]),
        control=deck.Control(end_time=4e-6, output_interval=2e-6, partition=partition),
    )


def _engine(deck_path: Path, ranks: int, *extra: str) -> subprocess.CompletedProcess[str]:
    if ranks > 1 and shutil.which("mpirun") is None:
        pytest.skip("mpirun is not installed")
    command = launch.engine_command(deck_path, deck_path.with_name(f"results_{ranks}.h5"), ranks, 1)
    return subprocess.run([*command, *extra], cwd=deck_path.parent, env=launch.engine_environment(1, ranks),
                          capture_output=True, text=True, timeout=300)


def _engine_on(deck_path: Path, ranks: int) -> dict[str, list[int]]:
    """Run the engine on ``ranks`` and return its PARADYN-DECK line."""
    done = _engine(deck_path, ranks)
    assert done.returncode == 0, done.stderr
    return _deck_line(done.stdout)


def _deck_line(stdout: str) -> dict[str, list[int]]:
    line = next(text for text in stdout.splitlines() if text.startswith("PARADYN-DECK "))
    return {key: [int(v) for v in value.split(",")] for key, value in
            (field.split("=") for field in line.split()[1:])}


def _block_sizes(n: int, ranks: int) -> list[int]:
    return [(r + 1) * n // ranks - r * n // ranks for r in range(ranks)]


@pytest.mark.parametrize("partition", ["blocks", "rcb"])
def test_each_rank_reads_only_its_block(tmp_path: Path, partition: str) -> None:
    """On 3 ranks every rank reads its block of the 18 element rows and of the 28 node rows (no
    rank reads a mesh dataset whole) and then holds its elements (blocks: those it read; rcb:
    those bisection gives it, 6 each) and only the nodes they touch; on 1 rank the one rank reads
    and holds everything."""
    model = _model(partition)
    path = deck.write_deck(model, tmp_path / "deck.h5")
    n_elements, n_nodes = len(model.connectivity), len(model.coordinates)
    one = _engine(path, 1)
    assert one.returncode == 0, one.stderr
    assert _deck_line(one.stdout) == {"element_rows_read": [n_elements], "node_rows_read": [n_nodes],
                                      "elements_held": [n_elements], "nodes_held": [n_nodes],
                                      "element_id_sums": [n_elements * (n_elements + 1) // 2]}
    done = _engine(path, RANKS)
    assert done.returncode == 0, done.stderr
    line = _deck_line(done.stdout)
    assert line["element_rows_read"] == _block_sizes(n_elements, RANKS) == [6, 6, 6]
    assert line["node_rows_read"] == _block_sizes(n_nodes, RANKS) == [9, 9, 10]
    if partition == "blocks":
        assert line["elements_held"] == line["element_rows_read"]
        assert line["nodes_held"] == [14, 14, 14]   # two rows of 7 nodes around each row of 6 elements
    else:
        assert sum(line["elements_held"]) == n_elements and max(line["elements_held"]) == 6
        assert max(line["nodes_held"]) < n_nodes
    with h5py.File(path.with_name("results_1.h5"), "r") as a, h5py.File(path.with_name(f"results_{RANKS}.h5")) as b:
        assert np.array_equal(a["/frames/displacement"][()], b["/frames/displacement"][()])
        assert np.any(a["/frames/displacement"][()] != 0.0)


def _set(name: str, index: tuple[int, ...], value: float) -> Callable[[h5py.File], None]:
    def damage(f: h5py.File) -> None:
        data = f[name][()]
        data[index] = value
        del f[name]
        f.create_dataset(name, data=data)
    return damage


def _both(*damages: Callable[[h5py.File], None]) -> Callable[[h5py.File], None]:
    def damage(f: h5py.File) -> None:
        for one in damages:
            one(f)
    return damage


def _unused_last_node(f: h5py.File) -> None:
    """One more node, far from the mesh, that no element names (node 28, read by the last rank)."""
    for name in [f"/nodes/{key}" for key in f["/nodes"]]:
        data = f[name][()]
        del f[name]
        extra = data[-1:].copy()
        if name == "/nodes/coordinates":
            extra[0, 0] += 1.0
        f.create_dataset(name, data=np.concatenate([data, extra]))


def _duplicate_of_first(f: h5py.File) -> None:
    """The last element (read by the last rank) names the first element's nodes in another order:
    its lowest node's home is rank 0."""
    data = f["/elements/connectivity"][()]
    data[-1] = data[0][::-1]
    del f["/elements/connectivity"]
    f.create_dataset("/elements/connectivity", data=data)


def _concave_last(f: h5py.File) -> None:
    """The last node (a corner of the last element only) moved inside its element's other three:
    the last element turns concave there."""
    data = f["/nodes/coordinates"][()]
    data[27] = [0.052, 0.022, 0.0]
    del f["/nodes/coordinates"]
    f.create_dataset("/nodes/coordinates", data=data)


def _wall_behind_last_node(f: h5py.File) -> None:
    """A rigid wall whose plane cuts the plate's far corner: only the last node is behind it."""
    group = f.create_group("rigid_walls")
    group.create_dataset("point", data=np.array([[0.0595, 0.03, 0.0]]))
    group.create_dataset("normal", data=np.array([[-1.0, -1.0, 0.0]]))
    group.create_dataset("velocity", data=np.zeros((1, 3)))
    group.create_dataset("penalty_scale", data=np.array([0.1]))


# (case id, damage, what the message must name)
CASES: list[tuple[str, Callable[[h5py.File], None], str]] = [
    ("nan_coordinate_last_rank", _set("/nodes/coordinates", (27, 1), np.nan),
     "/nodes/coordinates[27, 1] = NaN must be finite"),
    ("lowest_of_two_ranks",
     _both(_set("/nodes/coordinates", (27, 1), np.nan), _set("/nodes/coordinates", (12, 0), np.inf)),
     "/nodes/coordinates[12, 0] = Infinity must be finite"),
    ("connectivity_last_rank", _set("/elements/connectivity", (17, 2), 99), "/elements/connectivity[17, 2] = 99"),
    ("repeated_node_last_rank", _set("/elements/connectivity", (17, 3), 19), "/elements/connectivity[17] ="),
    ("duplicate_across_ranks", _duplicate_of_first, "has the same nodes as element 0"),
    ("concave_last_rank", _concave_last, "element 17 (part 0, nodes"),
    ("unused_last_node", _unused_last_node, "/nodes/coordinates[28] belongs to no element (1 such nodes)"),
    ("wall_behind_last_node", _wall_behind_last_node, "puts node 27 behind the wall"),
]


@pytest.fixture(scope="module")
def good_deck(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return deck.write_deck(_model(), tmp_path_factory.mktemp("good") / "deck.h5")


@pytest.mark.parametrize("case, damage, named", [pytest.param(*c, id=c[0]) for c in CASES])
def test_a_bad_row_of_another_rank_gives_the_one_rank_message(good_deck: Path, tmp_path: Path, case: str,
                                                              damage: Callable[[h5py.File], None],
                                                              named: str) -> None:
    """A bad value or a broken relation on rows the last of 3 ranks reads (or across ranks: a
    duplicate of element 0, two bad values on two ranks) stops every rank with status 2 and the
    message one rank gives, naming the lowest offending entry; no results file is written."""
    path = tmp_path / "deck.h5"
    shutil.copyfile(good_deck, path)
    with h5py.File(path, "r+") as f:
        damage(f)
    messages = {}
    for ranks in (1, RANKS):
        done = _engine(path, ranks)
        assert done.returncode == 2, (ranks, done.stdout, done.stderr)
        errors = [line for line in done.stderr.splitlines() if line.startswith("paradyn-engine: error:")]
        assert len(errors) == 1, done.stderr
        messages[ranks] = errors[0]
        assert not path.with_name(f"results_{ranks}.h5").exists()
    assert named in messages[1], messages[1]
    assert messages[RANKS] == messages[1]


def _fingerprints(checkpoint: Path) -> dict[str, float]:
    with h5py.File(checkpoint, "r") as f:
        return {k: float(v) for k, v in f.attrs.items() if k.startswith("fingerprint_")}


def test_fingerprint_is_the_same_on_any_rank_count(tmp_path: Path) -> None:
    """The deck fingerprint is chained over the ranks' blocks in rank order, so a checkpoint
    written on 3 ranks carries the 1-rank fingerprints (every group); a restart on 3 ranks with a
    deck changed in the last rank's rows is refused naming /nodes."""
    model = _model()
    model.control.checkpoint_interval = 2e-6
    path = deck.write_deck(model, tmp_path / "deck.h5")
    prints = {}
    for ranks in (1, RANKS):
        done = _engine(path, ranks)
        assert done.returncode == 0, done.stderr
        prints[ranks] = _fingerprints(path.with_name(f"results_{ranks}.checkpoint.h5"))
    assert {"fingerprint_nodes", "fingerprint_elements", "fingerprint_control"} <= set(prints[1])
    assert prints[RANKS] == prints[1]
    with h5py.File(path, "r+") as f:
        f["/nodes/initial_velocity"][27, 2] = 1.5
    done = _engine(path, RANKS, "--restart")
    assert done.returncode == 2, done.stderr
    assert "was written for another deck: its /nodes differs" in done.stderr


def _jittered_plate(nx: int, ny: int) -> deck.Model:
    """A plate of nx x ny elements whose inner nodes are moved by up to a fifth of an element in
    x and y (a fixed pseudo-random pattern), so that centroids rarely share a coordinate."""
    mesh = geometry.plate((0.01 * nx, 0.01 * ny), (nx, ny))
    x = np.array(mesh.coordinates, dtype=float)
    inner = (x[:, 0] > 1e-9) & (x[:, 0] < 0.01 * nx - 1e-9) & (x[:, 1] > 1e-9) & (x[:, 1] < 0.01 * ny - 1e-9)
    shift = 0.002 * np.sin(np.arange(len(x))[:, None] * [1.3, 2.9])
    x[inner, :2] += shift[inner]
    return _model("rcb", geometry.Mesh(x, mesh.quads))


@pytest.mark.parametrize("mesh, ranks", [("grid", 3), ("grid", 4), ("jittered", 3), ("jittered", 5)])
def test_distributed_rcb_gives_the_serial_owners(tmp_path: Path, mesh: str, ranks: int) -> None:
    """partition = "rcb" bisects the centroids distributed over the ranks' blocks (no rank holds
    them all), yet each rank ends with exactly the elements of the serial bisection
    (domain_decomposition's rcb_partition through paradyn._kernels): per rank the same count,
    the same sum of ids and the same nodes. The grid has ties in every coordinate (the id breaks
    them); the jittered plate has 15 x 9 distinct centroids (several selection rounds)."""
    model = _model("rcb") if mesh == "grid" else _jittered_plate(15, 9)
    path = deck.write_deck(model, tmp_path / "deck.h5")
    line = _engine_on(path, ranks)
    owner = benchmark.element_owners(model, ranks)
    connectivity = np.asarray(model.connectivity)
    ids = np.arange(1, len(owner) + 1)
    assert line["elements_held"] == [int(np.sum(owner == r)) for r in range(ranks)]
    assert line["element_id_sums"] == [int(ids[owner == r].sum()) for r in range(ranks)]
    assert line["nodes_held"] == [len(np.unique(connectivity[owner == r])) for r in range(ranks)]
    assert line["element_rows_read"] == _block_sizes(len(owner), ranks)
