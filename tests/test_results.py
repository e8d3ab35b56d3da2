"""Tests of paradyn.results and paradyn.results.plots on small synthetic files (docs/formats.md, v1)."""

from __future__ import annotations

import csv
import json
import os
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree

os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")

import h5py
import numpy as np
import pytest
from numpy.testing import assert_allclose

from paradyn.results import (
    IncompleteResultsError,
    ResultsError,
    energy_report,
    plots,
    read,
    write_history_csv,
    write_summary,
    write_vtk_series,
)

# --------------------------------------------------------------------------------------------
# Synthetic files
# --------------------------------------------------------------------------------------------

NX, NY = 4, 2  # quads along x and y; columns 0-1 are part 0, columns 2-3 part 1
END_TIME = 2.0e-3
N_FRAMES = 5
N_RECORDS = 21
RATE = 50.0  # uz = RATE * t * x  (m)
TRACKED = np.array([NX, (NX + 1) * (NY + 1) - 1])  # the two nodes at x = NX, y = 0 and y = NY
RUN_ATTRS = {
    "cycles": 1000,
    "dt_s": 2.0e-6,
    "dt_stable_s": 2.2e-6,
    "wall_s": 1.5,
    "ranks": 2,
    "threads": 4,
    "elements": NX * NY,
    "nodes": (NX + 1) * (NY + 1),
    "element_cycles_per_s": NX * NY * 1000 / 1.5,
    "phase_elements_s": 1.0,
    "phase_contact_s": 0.1,
    "phase_communication_s": 0.2,
    "phase_output_s": 0.15,
    "phase_other_s": 0.05,
}


@dataclass
class Synthetic:
    results: Path
    deck: Path
    coordinates: np.ndarray
    connectivity: np.ndarray
    part: np.ndarray
    frame_times: np.ndarray
    history_times: np.ndarray


def _mesh() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    xs, ys = np.meshgrid(np.arange(NX + 1, dtype=float), np.arange(NY + 1, dtype=float))
    coords = np.column_stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)])
    conn, part = [], []
    for j in range(NY):
        for i in range(NX):
            n0 = j * (NX + 1) + i
            conn.append([n0, n0 + 1, n0 + NX + 2, n0 + NX + 1])
            part.append(0 if i < NX // 2 else 1)
    return coords, np.array(conn, dtype=np.int32), np.array(part, dtype=np.int32)


def _displacement(coords: np.ndarray, t: np.ndarray) -> np.ndarray:
    disp = np.zeros((t.size, coords.shape[0], 3))
    disp[:, :, 2] = RATE * t[:, None] * coords[None, :, 0]
    return disp


def _energies(t: np.ndarray) -> dict[str, np.ndarray]:
    s = t / END_TIME
    return {
        "kinetic_energy": 100.0 * (1.0 - s),
        "internal_energy": 90.0 * s,
        "hourglass_energy": 5.0 * s,
        "contact_energy": np.zeros_like(s),
        "external_work": np.zeros_like(s),
    }  # total = 100 - 5 s: balance error 5 / 100


def write_synthetic(
    directory: Path,
    *,
    complete: bool = True,
    frames_written: int = N_FRAMES,
    version: int = 1,
    deck_names: str | None = "vlen",
    tracked_names: list[str] | None = None,
) -> Synthetic:
    """Write ``results.h5`` and ``deck.h5`` into ``directory`` following docs/formats.md."""
    directory.mkdir(parents=True, exist_ok=True)
    coords, conn, part = _mesh()
    n_el = conn.shape[0]
    t_frames = np.linspace(0.0, END_TIME, N_FRAMES)
    t_hist = np.linspace(0.0, END_TIME, N_RECORDS)
    disp = _displacement(coords, t_frames)
    vel = np.zeros_like(disp)
    vel[:, :, 2] = RATE * coords[None, :, 0]
    k = np.arange(N_FRAMES)[:, None]
    e = np.arange(n_el)[None, :]
    von_mises = 1.0e6 * (k + 1) + e
    plastic = 0.01 * k * e
    stress = np.stack([von_mises, -von_mises, 0.5 * von_mises], axis=-1)

    results = directory / "results.h5"
    with h5py.File(results, "w") as h5:
        h5.attrs["paradyn_results_version"] = np.int32(version)
        h5.attrs["complete"] = np.int32(1 if complete else 0)
        h5["/mesh/coordinates"] = coords
        h5["/mesh/connectivity"] = conn
        h5["/mesh/part"] = part
        h5["/frames/time"] = t_frames  # the time may be ahead of the fields in a partial file
        h5["/frames/displacement"] = disp[:frames_written]
        h5["/frames/velocity"] = vel[:frames_written]
        h5["/frames/element_membrane_stress"] = stress[:frames_written]
        h5["/frames/element_von_mises"] = von_mises[:frames_written]
        h5["/frames/element_plastic_strain"] = plastic[:frames_written]
        h5["/history/time"] = t_hist
        for name, values in _energies(t_hist).items():
            h5[f"/history/{name}"] = values
        tracked_disp = _displacement(coords, t_hist)[:, TRACKED]
        h5["/history/tracked_displacement"] = tracked_disp
        h5["/history/tracked_velocity"] = 2.0 * tracked_disp
        if complete:
            run = h5.create_group("run")
            for key, value in RUN_ATTRS.items():
                run.attrs[key] = value

    deck = directory / "deck.h5"
    with h5py.File(deck, "w") as h5:
        h5.attrs["paradyn_deck_version"] = np.int32(1)
        h5["/nodes/coordinates"] = coords
        h5["/elements/connectivity"] = conn
        h5["/elements/part"] = part
        h5["/parts/thickness"] = np.array([1e-3, 2e-3])
        h5["/parts/material"] = np.array([0, 0])
        h5["/materials/model"] = np.array([1])
        h5["/materials/density"] = np.array([7800.0])
        h5["/materials/youngs_modulus"] = np.array([2e11])
        h5["/materials/poisson_ratio"] = np.array([0.3])
        h5["/output/tracked_nodes"] = TRACKED
        ctrl = h5.create_group("control")
        ctrl.attrs["end_time"] = END_TIME
        ctrl.attrs["output_interval"] = END_TIME / (N_FRAMES - 1)
        if deck_names == "vlen":
            h5.attrs["title"] = "synthetic plate"
            h5["parts"].attrs.create("names", ["left plate", "right"], dtype=h5py.string_dtype())
            names = tracked_names if tracked_names is not None else ["tip low", "tip,high"]
            h5["output"].attrs.create("tracked_names", names, dtype=h5py.string_dtype())
        elif deck_names == "bytes":
            h5.attrs["title"] = np.bytes_(b"synthetic plate")
            h5["parts"].attrs["names"] = np.array([b"left plate", b"right"], dtype="S")
            h5["output"].attrs["tracked_names"] = np.array([b"tip low", b"tip,high"], dtype="S")
    return Synthetic(results, deck, coords, conn, part, t_frames, t_hist)


@pytest.fixture
def synthetic(tmp_path: Path) -> Synthetic:
    return write_synthetic(tmp_path / "run")


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------


def test_read_arrays_and_names_from_deck_beside(synthetic: Synthetic) -> None:
    r = read(synthetic.results)
    assert r.complete and r.version == 1
    assert (r.n_nodes, r.n_elements, r.n_parts, r.n_frames, r.n_records, r.n_tracked) == (
        15, 8, 2, N_FRAMES, N_RECORDS, 2,
    )
    assert_allclose(r.frame_times, synthetic.frame_times)
    assert_allclose(r.displacement, _displacement(synthetic.coordinates, synthetic.frame_times))
    assert r.part_names == ["left plate", "right"]
    assert r.tracked_names == ["tip low", "tip,high"]
    assert r.title == "synthetic plate"
    assert r.end_time == END_TIME
    assert r.deck_path == synthetic.deck
    assert r.run["cycles"] == 1000 and isinstance(r.run["cycles"], int)


def test_names_from_fixed_length_bytes(tmp_path: Path) -> None:
    s = write_synthetic(tmp_path, deck_names="bytes")
    r = read(s.results)
    assert r.part_names == ["left plate", "right"]
    assert r.tracked_names == ["tip low", "tip,high"]
    assert r.title == "synthetic plate"


def test_fallback_names_without_names_in_deck(tmp_path: Path) -> None:
    s = write_synthetic(tmp_path, deck_names=None)
    r = read(s.results)
    assert r.part_names == ["part_0", "part_1"]
    assert r.tracked_names == [f"node_{TRACKED[0]}", f"node_{TRACKED[1]}"]
    s.deck.unlink()
    r = read(s.results)
    assert r.part_names == ["part_0", "part_1"]
    assert r.tracked_names == ["tracked_0", "tracked_1"]
    assert r.deck_path is None and r.end_time is None


def test_explicit_deck_must_exist(synthetic: Synthetic, tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="no deck at"):
        read(synthetic.results, deck=tmp_path / "missing.h5")


def test_incomplete_file_rejected_with_clear_message(tmp_path: Path) -> None:
    s = write_synthetic(tmp_path, complete=False, frames_written=3)
    with pytest.raises(IncompleteResultsError, match="allow_incomplete=True") as info:
        read(s.results)
    assert "did not finish" in str(info.value)
    r = read(s.results, allow_incomplete=True)
    assert not r.complete
    assert r.n_frames == 3  # the time was written ahead of the fields: keep whole frames only
    assert_allclose(r.frame_times, s.frame_times[:3])
    assert r.run == {}
    summary = write_summary(r, tmp_path / "summary.json")
    assert summary["complete"] is False and summary["wall_s"] is None


def test_not_a_results_file(tmp_path: Path, synthetic: Synthetic) -> None:
    with pytest.raises(ResultsError, match="is a ParaDyn deck"):
        read(synthetic.deck)
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as h5:
        h5["x"] = [1.0]
    with pytest.raises(ResultsError, match="paradyn_results_version"):
        read(other)
    text = tmp_path / "notes.h5"
    text.write_text("hello")
    with pytest.raises(ResultsError, match="cannot be opened as HDF5"):
        read(text)
    with pytest.raises(FileNotFoundError, match="no results file"):
        read(tmp_path / "absent.h5")


def test_unsupported_version(tmp_path: Path) -> None:
    s = write_synthetic(tmp_path, version=2)
    with pytest.raises(ResultsError, match="version 2"):
        read(s.results)


def test_frame_grid(synthetic: Synthetic) -> None:
    r = read(synthetic.results)
    grid = r.frame(-1)
    assert grid.n_points == 15 and grid.n_cells == 8
    disp = _displacement(synthetic.coordinates, synthetic.frame_times)
    expected = synthetic.coordinates + disp[-1]
    assert_allclose(grid.points, expected[grid.point_data["node_id"]])
    assert_allclose(grid.point_data["displacement"][:, 2], RATE * END_TIME * grid.points[:, 0])
    flat = r.frame(-1, deformed=False)
    assert_allclose(flat.points, synthetic.coordinates[flat.point_data["node_id"]])
    right = r.frame(2, part="right")
    assert right.n_cells == 4 and right.n_points == 9
    assert set(right.cell_data["part"]) == {1}
    with pytest.raises(IndexError, match="holds 5 frames"):
        r.frame(5)


# --------------------------------------------------------------------------------------------
# Writers
# --------------------------------------------------------------------------------------------


def test_vtk_series_round_trip(synthetic: Synthetic, tmp_path: Path) -> None:
    import pyvista as pv

    r = read(synthetic.results)
    out = tmp_path / "out"
    pvds = write_vtk_series(r, out)
    assert [p.name for p in pvds] == ["left_plate.pvd", "right.pvd"]
    assert len(list((out / "vtk").glob("*.vtu"))) == 2 * N_FRAMES
    root = ElementTree.parse(pvds[0]).getroot()
    files = [d.get("file") for d in root.iter("DataSet")]
    assert files == [f"vtk/left_plate_{k:05d}.vtu" for k in range(N_FRAMES)]

    all_disp = _displacement(synthetic.coordinates, synthetic.frame_times)
    for pvd, part in zip(pvds, (0, 1), strict=True):
        reader = pv.get_reader(pvd)
        assert_allclose(reader.time_values, synthetic.frame_times, rtol=0, atol=0)
        for k, t in enumerate(reader.time_values):
            reader.set_active_time_value(t)
            block = reader.read()
            grid = block[0]
            assert grid.n_points == 9 and grid.n_cells == 4
            assert set(np.unique(grid.celltypes)) == {pv.CellType.QUAD}
            nodes = grid.point_data["node_id"]
            assert_allclose(grid.points, synthetic.coordinates[nodes] + all_disp[k, nodes])
            assert_allclose(grid.point_data["displacement"], all_disp[k, nodes])
            assert grid.cell_data["membrane_stress"].shape == (4, 3)
            assert set(grid.cell_data["part"]) == {part}
            elements = grid.cell_data["element_id"]
            assert_allclose(grid.cell_data["von_mises"], 1.0e6 * (k + 1) + elements)
            assert "plastic_strain" in grid.cell_data and "velocity" in grid.point_data
    first = pv.read(pvds[1])
    assert first[0].n_points == 9


def test_vtk_series_removes_stale_frames(synthetic: Synthetic, tmp_path: Path) -> None:
    r = read(synthetic.results)
    out = tmp_path / "out"
    stale = out / "vtk" / "right_00099.vtu"
    stale.parent.mkdir(parents=True)
    stale.write_text("old")
    write_vtk_series(r, out)
    assert not stale.exists()


def test_history_csv(synthetic: Synthetic, tmp_path: Path) -> None:
    r = read(synthetic.results)
    path = write_history_csv(r, tmp_path / "history.csv")
    with path.open(newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    assert header[:11] == [
        "time [s]", "kinetic_energy [J]", "internal_energy [J]", "hourglass_energy [J]",
        "contact_energy [J]", "external_work [J]", "total_energy [J]", "contact_penetration [m]", "dt [s]",
        "dt_stable [s]", "dt_element [-]",
    ]
    # the supports' reaction and its moment (zeros in this synthetic file, written before them), then
    # the tracked points
    assert header[11:17] == ["reaction_fx [N]", "reaction_fy [N]", "reaction_fz [N]", "reaction_mx [N m]",
                             "reaction_my [N m]", "reaction_mz [N m]"]
    assert header[17:] == [f"{n}_{c} [{u}]" for n in ("tip_low", "tip_high") for c, u in
                           (("dx", "m"), ("dy", "m"), ("dz", "m"), ("vx", "m/s"), ("vy", "m/s"), ("vz", "m/s"))]
    values = np.array(rows[1:], dtype=float)
    assert values.shape == (N_RECORDS, 17 + 12)
    assert_allclose(values[:, 0], synthetic.history_times, rtol=0, atol=0)  # exact round trip
    assert_allclose(values[:, 6], 100.0 - 5.0 * synthetic.history_times / END_TIME)
    x_tip = synthetic.coordinates[TRACKED[1], 0]
    assert_allclose(values[:, header.index("tip_high_dz [m]")], RATE * synthetic.history_times * x_tip)
    vz = values[:, header.index("tip_high_vz [m/s]")]
    assert_allclose(vz, 2 * RATE * synthetic.history_times * x_tip)


def test_energy_report(synthetic: Synthetic) -> None:
    report = energy_report(read(synthetic.results))
    assert report["initial"]["kinetic"] == pytest.approx(100.0)
    assert report["final"]["internal"] == pytest.approx(90.0)
    assert report["final"]["hourglass"] == pytest.approx(5.0)
    assert report["final"]["total"] == pytest.approx(95.0)
    assert report["balance_error"] == pytest.approx(0.05)
    assert report["hourglass_ratio"] == pytest.approx(5.0 / 90.0)


def test_summary_has_every_key(synthetic: Synthetic, tmp_path: Path) -> None:
    r = read(synthetic.results)
    path = tmp_path / "summary.json"
    returned = write_summary(r, path, extra={"case": "plate"})
    on_disk = json.loads(path.read_text())
    assert on_disk == returned
    required = {
        "wall_s", "cycles", "dt_s", "elements", "nodes", "ranks", "threads",
        "element_cycles_per_s", "phase_s", "energy", "effects", "dt_stable_s", "complete",
        "end_time",
    }
    assert required <= on_disk.keys()
    assert on_disk["phase_s"] == {
        "elements": 1.0, "contact": 0.1, "communication": 0.2, "output": 0.15, "other": 0.05,
    }
    assert on_disk["cycles"] == 1000 and on_disk["ranks"] == 2 and on_disk["complete"] is True
    assert on_disk["end_time"] == END_TIME
    assert on_disk["effects"] == [] and on_disk["case"] == "plate"   # the synthetic file has no effect table
    assert on_disk["energy"]["balance_error"] == pytest.approx(0.05)
    assert list(tmp_path.glob(".summary.json.*")) == []  # no temporary file left behind


# --------------------------------------------------------------------------------------------
# Pictures
# --------------------------------------------------------------------------------------------

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _is_png(path: Path) -> bool:
    return path.is_file() and path.stat().st_size > 1000 and path.read_bytes()[:8] == PNG_SIGNATURE


def test_pngs(synthetic: Synthetic, tmp_path: Path) -> None:
    r = read(synthetic.results)
    assert _is_png(plots.plot_tracked_histories(r, tmp_path / "tracked.png"))
    assert _is_png(plots.plot_tracked_histories(r, tmp_path / "tracked_v.png", component="vz"))
    assert _is_png(plots.plot_energies(r, tmp_path / "energy.png"))
    assert _is_png(plots.render_deformed(r, tmp_path / "deformed.png"))
    r.plot("deformed", scalars="von_mises").savefig(tmp_path / "vm.png")
    assert _is_png(tmp_path / "vm.png")
    with pytest.raises(ValueError, match="component"):
        plots.plot_tracked_histories(r, tmp_path / "x.png", component="dw")
    with pytest.raises(ValueError, match="no field 'stress'"):
        plots.render_deformed(r, tmp_path / "x.png", scalars="stress")


def test_accuracy_line_warns_above_its_thresholds(synthetic: Synthetic) -> None:
    """Issue 15, guards a person sees: the synthetic run loses 5 % of its energy (balance error 0.05,
    above 0.01) and keeps its hourglass at 5/90 of internal (below 0.1): one warning, for the
    balance; the line shows every indicator the run has."""
    from paradyn.results.reports import WARN_ABOVE, accuracy_indicators, accuracy_text

    results = read(synthetic.results)
    indicators = accuracy_indicators(results)
    assert indicators["energy_balance_error"] == pytest.approx(0.05)
    assert indicators["peak_hourglass_over_internal"] == pytest.approx(5.0 / 90.0)
    text = accuracy_text(results)
    lines = text.splitlines()
    assert lines[0].startswith("  accuracy: energy balance error 0.05, peak hourglass / internal 0.0556")
    warnings = [line for line in lines if "warning:" in line]
    assert len(warnings) == 1
    assert warnings[0].startswith("  warning: energy balance error is 0.05, above 0.01; try a smaller [run] "
                                  "time_step_safety")
    assert WARN_ABOVE["peak_hourglass_over_internal"] == 0.10
