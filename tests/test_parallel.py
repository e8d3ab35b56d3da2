"""Bitwise reproducibility across MPI ranks and OpenMP threads (docs/theory.md, parallel design).

The small plate deck runs on 1 rank x 1 thread (the reference), 2 and 4 ranks (launch adds
--oversubscribe when there are fewer cores) and 1 rank x 2 threads. Every node sums its element
corners in ascending global element order, so the field frames must be bitwise equal. A plastic
contact deck does the same for each partition method (/control partition), element fields
included.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import h5py
import numpy as np
import pytest

import models as M
from paradyn import benchmark, deck, scene
from paradyn.running import launch

pytestmark = pytest.mark.mpi

ROOT = Path(__file__).resolve().parents[1]
LAYOUTS = [(2, 1), (4, 1), (1, 2)]
EXACT_HISTORY = ("time", "external_work", "contact_energy", "tracked_displacement", "tracked_velocity")
SUMMED_HISTORY = ("kinetic_energy", "internal_energy", "hourglass_energy")
FRAME_FIELDS = ("displacement", "velocity", "element_membrane_stress", "element_von_mises", "element_plastic_strain",
                "acceleration", "nodal_contact_force", "element_layer_stress", "element_membrane_strain",
                "element_internal_energy_density", "element_surface_strain", "element_thickness")


def _read(path: Path) -> dict[str, np.ndarray]:
    with h5py.File(path, "r") as f:
        data = {key: f[f"/frames/{key}"][()] for key in FRAME_FIELDS}
        data["frame_time"] = f["/frames/time"][()]
        data.update({f"mesh/{k}": f["/mesh"][k][()] for k in f["/mesh"]})
        data.update({f"history/{k}": f["/history"][k][()] for k in f["/history"]})
        data.update({f"run/{k}": v for k, v in f["/run"].attrs.items()})
    return data


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[tuple[int, int], dict[str, np.ndarray]]:
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    folder = tmp_path_factory.mktemp("parallel")
    deck_path = deck.write_deck(scene.build_model(scene.load_scene(ROOT / "cases" / "small_plate" / "scene.toml")),
                                folder / "deck.h5")
    out = {}
    for ranks, threads in [(1, 1), *LAYOUTS]:
        results = folder / f"results_{ranks}x{threads}.h5"
        launch.run_engine(deck_path, results, ranks, threads, log_path=folder / f"engine_{ranks}x{threads}.log")
        out[(ranks, threads)] = _read(results)
    return out


@pytest.mark.parametrize("layout", LAYOUTS, ids=lambda layout: f"{layout[0]}x{layout[1]}")
def test_layout_is_what_was_asked(runs: dict, layout: tuple[int, int]) -> None:
    """docs/formats.md /run attributes: ranks and threads of the run."""
    data = runs[layout]
    assert (int(data["run/ranks"]), int(data["run/threads"])) == layout
    assert int(data["run/cycles"]) == int(runs[(1, 1)]["run/cycles"])


@pytest.mark.parametrize("layout", LAYOUTS, ids=lambda layout: f"{layout[0]}x{layout[1]}")
def test_frames_are_bitwise_equal(runs: dict, layout: tuple[int, int]) -> None:
    """docs/theory.md: displacements bitwise identical on 1, 2 and 4 ranks and 1 or 2 threads.
    Every rank writes its own rows of each frame and of /mesh (parallel HDF5), so equality with
    the 1-rank file also shows that every row was written once, in its place."""
    reference, data = runs[(1, 1)], runs[layout]
    for key in ("frame_time", *FRAME_FIELDS, "mesh/coordinates", "mesh/connectivity", "mesh/part", "mesh/thickness"):
        assert data[key].shape == reference[key].shape, key
        assert np.array_equal(data[key], reference[key]), key
    assert np.any(reference["displacement"] != 0.0)
    assert np.any(reference["element_von_mises"] != 0.0)


@pytest.mark.parametrize("layout", LAYOUTS, ids=lambda layout: f"{layout[0]}x{layout[1]}")
def test_history_is_bitwise_equal_apart_from_energy_sums(runs: dict, layout: tuple[int, int]) -> None:
    """Times, tracked nodes and the external work are bitwise equal; the summed energies agree
    to round-off (1e-14 of the largest energy)."""
    reference, data = runs[(1, 1)], runs[layout]
    for name in EXACT_HISTORY:
        assert np.array_equal(data[f"history/{name}"], reference[f"history/{name}"]), name
    scale = max(np.abs(reference[f"history/{name}"]).max() for name in SUMMED_HISTORY)
    for name in SUMMED_HISTORY:
        np.testing.assert_allclose(data[f"history/{name}"], reference[f"history/{name}"], rtol=0,
                                   atol=1e-14 * scale, err_msg=name)


ENERGY_SUM = ("engine limitation (explicit_solver write_record): kinetic, internal and hourglass "
              "energies are summed per rank and combined with MPI_Reduce, so the order of the sum "
              "depends on the rank count (differences of a few ulp)")


@pytest.mark.parametrize("layout", [
    pytest.param((1, 2), id="1x2"),
])
def test_history_energies_are_bitwise_equal(runs: dict, layout: tuple[int, int]) -> None:
    """The whole /history group bitwise equal to the 1 x 1 run, the energies included. Only for
    threads: across ranks the energies are summed per rank then reduced, so they differ by a few
    ulp (ENERGY_SUM); the test above bounds that difference."""
    reference, data = runs[(1, 1)], runs[layout]
    for name in SUMMED_HISTORY:
        assert np.array_equal(data[f"history/{name}"], reference[f"history/{name}"]), name


@pytest.mark.mpi
def test_scaling_benchmark_reports_every_layout(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """paradyn-scaling (issue 5): one row per layout with wall time, element-cycles/s, speed-up,
    efficiency and the phases, written as JSON; every layout gives the first one's displacements
    bitwise, and the command says so with its exit status."""
    scene_path = Path(__file__).resolve().parents[1] / "cases" / "small_plate" / "scene.toml"
    status = benchmark.main([str(scene_path), "--layouts", "1x1,2x1,1x2", "--repeat", "3", "-o", str(tmp_path)])
    assert status == 0
    report = json.loads((tmp_path / "scaling.json").read_text())
    assert [(r["ranks"], r["threads"]) for r in report["layouts"]] == [(1, 1), (2, 1), (1, 2)]
    base = report["layouts"][0]["round_wall_s"]
    for row in report["layouts"]:
        assert row["same_displacements"] is True
        assert row["wall_s"] > 0 and row["element_cycles_per_s"] > 0
        assert row["efficiency"] == pytest.approx(row["speed_up"] / (row["ranks"] * row["threads"]))
        assert set(row["phase_s"]) == {"elements", "contact", "communication", "output", "other"}
        assert row["peak_memory_mb"] > 0
        # three rounds; the reported run is the median one, the speed-up the median of the rounds'
        assert len(row["round_wall_s"]) == 3 and row["wall_s"] == sorted(row["round_wall_s"])[1]
        assert row["round_speed_up"] == pytest.approx([b / w for b, w in zip(base, row["round_wall_s"], strict=True)])
        assert row["speed_up"] == pytest.approx(sorted(row["round_speed_up"])[1])
        # one rank is balanced by definition; two ranks are at least as busy as their mean
        assert row["load_imbalance"] == 1.0 if row["ranks"] == 1 else row["load_imbalance"] >= 1.0
    assert report["layouts"][0]["speed_up"] == 1.0
    out = capsys.readouterr().out
    assert "| 2 x 1 |" in out and "speed-up of 2 x 1 in each round:" in out
    # every rank logs its phases (docs/formats.md), so a wait can be traced to the rank it waited for
    log = (tmp_path / "engine_2x1.log").read_text()
    assert all(f"PARADYN-PHASES rank={rank} elements_s=" in log for rank in (0, 1))


# ----------------------------------------------------------------------------------------------
# partition methods (docs/formats.md /control partition)


ELEMENT_FIELDS = ("element_membrane_stress", "element_von_mises", "element_plastic_strain", "element_thickness")
PARTITION_LAYOUTS = [("rcb", 2), ("rcb", 4), ("blocks", 2)]


def _plastic_impact() -> deck.Model:
    """Two 6 x 6 steel plates 2 mm thick, 0.01 mm apart, the upper one offset by a quarter
    element and thrown obliquely at (4, 2, -20) m/s at the lower one (friction 0.3), J2 with a
    20 MPa yield stress so that the impact yields the elements unevenly: every element field of
    the frames differs from element to element."""
    plate, t, gap = 0.1, 0.002, 1.0e-5
    z = 0.5 * (t + gap)
    lower = M.flat_plate((plate, plate), (6, 6), origin=(-0.5 * plate, -0.5 * plate, -z))
    upper = M.flat_plate((plate, plate), (6, 6), origin=(-0.5 * plate + plate / 24, -0.5 * plate, z))
    control = deck.Control(end_time=20.0e-6, output_interval=4.0e-6)
    model = M.contact_model([M.Body(lower, t), M.Body(upper, t, (4.0, 2.0, -20.0))],
                            M.Material(young=200.0e9, poisson=0.3, density=7850.0), control,
                            static_friction=0.3).model
    model.material_model = np.array([deck.J2_PLASTICITY])
    model.yield_stress, model.tangent_modulus, model.hardening_mixing = [20.0e6], [1.0e9], [1.0]
    model.normalise()
    return model


@pytest.fixture(scope="module")
def partitioned(tmp_path_factory: pytest.TempPathFactory) -> dict[tuple[str, int], dict]:
    if shutil.which("mpirun") is None and shutil.which("mpiexec") is None:
        pytest.skip("mpirun is not installed")
    folder = tmp_path_factory.mktemp("partitions")
    model = _plastic_impact()
    out = {}
    for method, ranks in [("blocks", 1), *PARTITION_LAYOUTS]:
        model.control.partition = method
        deck_path = deck.write_deck(model, folder / f"deck_{method}.h5")
        results = folder / f"results_{method}_{ranks}.h5"
        run = launch.run_engine(deck_path, results, ranks, 1, log_path=folder / f"engine_{method}_{ranks}.log")
        with h5py.File(results, "r") as f:
            data = {k: f["/frames"][k][()] for k in ("displacement", "velocity", *ELEMENT_FIELDS)}
            data["contact_energy"] = f["/history/contact_energy"][()]
        data["partition"] = run.start.get("partition")
        data["owner"] = benchmark.element_owners(model, ranks)
        out[(method, ranks)] = data
    return out


@pytest.mark.parametrize("layout", PARTITION_LAYOUTS, ids=lambda layout: f"{layout[0]}-{layout[1]}ranks")
def test_partition_gives_the_one_rank_answer_bitwise(partitioned: dict, layout: tuple[str, int]) -> None:
    """docs/theory.md (parallel design): whatever rank owns an element, every node sums its
    corners in ascending global element order, and rank 0 places every gathered element value
    at its global id. A plastic oblique plate impact with friction on 2 and 4 ranks, partitioned
    by recursive coordinate bisection (each rank owns elements of both plates, not one range of
    ids) and by blocks, gives the 1-rank displacements, velocities, element stresses, plastic
    strains and thicknesses and contact energy bitwise."""
    reference, data = partitioned[("blocks", 1)], partitioned[layout]
    method, ranks = layout
    assert data["partition"] == method
    owner = data["owner"]
    assert np.array_equal(np.unique(owner), np.arange(ranks))
    if method == "rcb":
        assert np.any(np.diff(owner) < 0)   # not contiguous: the gather must place by id
    for key in ("displacement", "velocity", *ELEMENT_FIELDS, "contact_energy"):
        assert data[key].shape == reference[key].shape, key
        assert np.array_equal(data[key], reference[key]), key
    for key in ELEMENT_FIELDS:               # the fields vary, so a misplaced value shows
        assert np.unique(reference[key][-1]).size > 0.9 * reference[key].shape[1], key


@pytest.mark.parametrize("method, shared", [("blocks", 9), ("rcb", 5)])
def test_partition_stats_of_the_small_plate(method: str, shared: int) -> None:
    """Reference: hand count on the small plate (8 x 4 elements numbered row by row, 9 x 5
    nodes): on 2 ranks blocks cut along a row line (9 shared nodes), rcb across the long side
    (5); one neighbour each."""
    model = scene.build_model(scene.load_scene(ROOT / "cases" / "small_plate" / "scene.toml"))
    model.control.partition = method
    assert benchmark.partition_stats(model, 2) == (shared, 1)
    assert benchmark.partition_stats(model, 1) == (0, 0)


def test_scaling_benchmark_partition_option(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """paradyn-scaling --partition rcb writes the method into the deck it runs and the report,
    with the shared nodes of each layout, and the answer stays the 1-rank one."""
    scene_path = ROOT / "cases" / "small_plate" / "scene.toml"
    status = benchmark.main([str(scene_path), "--layouts", "1x1,2x1", "--partition", "rcb", "-o", str(tmp_path)])
    assert status == 0
    report = json.loads((tmp_path / "scaling.json").read_text())
    assert report["partition"] == "rcb"
    assert [(r["ranks"], r["shared_nodes"], r["same_displacements"]) for r in report["layouts"]] == [
        (1, 0, True), (2, 5, True)]
    assert deck.read_deck(tmp_path / "deck.h5").control.partition == "rcb"
    assert "partition rcb on 2 ranks: 5 shared nodes" in capsys.readouterr().out


def test_scaling_benchmark_end_time_shortens_every_run(tmp_path: Path) -> None:
    """paradyn-scaling --end-time runs each layout to that time (the deck it writes says so, and
    the results end there), and refuses a time that is not positive."""
    scene_path = ROOT / "cases" / "small_plate" / "scene.toml"
    end = 0.25 * scene.load_scene(scene_path).run.end_time
    assert benchmark.main([str(scene_path), "--layouts", "1x1", "--end-time", str(end), "-o", str(tmp_path)]) == 0
    assert deck.read_deck(tmp_path / "deck.h5").control.end_time == end
    with pytest.raises(SystemExit):
        benchmark.main([str(scene_path), "--end-time", "0", "-o", str(tmp_path)])


@pytest.mark.mpi
def test_part_plastic_work_is_bitwise_the_same_on_two_threads(tmp_path: Path) -> None:
    """The per-element plastic work is computed on the threads and summed in element order
    (solver_output.f90, part_energies), so /history/part_plastic_work of the pipe whip (J2, 16
    element groups) is bitwise the same on 1 and 2 threads, and not zero (the pipes yield)."""
    model = scene.build_model(scene.load_scene(ROOT / "cases" / "pipe_whip" / "scene.toml"))
    deck_path = deck.write_deck(model, tmp_path / "deck.h5")
    work = {}
    for threads in (1, 2):
        results = tmp_path / f"results_{threads}.h5"
        launch.run_engine(deck_path, results, 1, threads)
        with h5py.File(results, "r") as f:
            work[threads] = f["/history/part_plastic_work"][()]
    assert work[1][-1].max() > 0.0
    assert np.array_equal(work[1], work[2])
