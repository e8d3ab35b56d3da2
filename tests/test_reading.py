"""paradyn.results.reading: frames read on demand and names from results.h5 before the deck
(synthetic files of tests/test_results.py, docs/formats.md version 1). The module layout that keeps
reading, plots and writers free of import circles is checked in tests/test_layers.py."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
from numpy.testing import assert_array_equal

import paradyn
from paradyn.results.reading import FrameField
from test_results import N_FRAMES, write_synthetic

PACKAGE = Path(paradyn.__file__).resolve().parent
FRAME_DATASETS = {
    "displacement": "/frames/displacement",
    "velocity": "/frames/velocity",
    "membrane_stress": "/frames/element_membrane_stress",
    "von_mises": "/frames/element_von_mises",
    "plastic_strain": "/frames/element_plastic_strain",
}


def test_a_frame_read_after_open_is_the_file_s_frame(tmp_path: Path) -> None:
    """Every field of every frame, read after open (one frame, one row, every frame), is bitwise
    what h5py reads from the dataset."""
    s = write_synthetic(tmp_path)
    res = paradyn.read(s.results)
    with h5py.File(s.results, "r") as f:
        assert_array_equal(res.time_values, f["/frames/time"][()])
        assert res.n_frames == N_FRAMES
        for k in range(-1, N_FRAMES):
            arrays = res.frame_arrays(k)
            assert arrays.index == k % N_FRAMES and arrays.time == f["/frames/time"][k]
            for name, ds in FRAME_DATASETS.items():
                assert_array_equal(getattr(arrays, name), f[ds][k], err_msg=name)
                assert_array_equal(getattr(res, name)[k], f[ds][k], err_msg=name)
        assert_array_equal(res.velocity[2, [1, 4], 2], f["/frames/velocity"][2][[1, 4], 2])
        assert_array_equal(np.asarray(res.von_mises), f["/frames/element_von_mises"][()])
        assert_array_equal(res.displacement[:, 3], f["/frames/displacement"][:, 3])
    assert_array_equal(2.0 * res.von_mises, 2.0 * np.asarray(res.von_mises))
    assert [frame.shape for frame in res.plastic_strain] == [(8,)] * N_FRAMES
    with pytest.raises(IndexError, match="holds 5 frames"):
        res.displacement[N_FRAMES]


def test_frames_stay_in_the_file_until_asked_for(tmp_path: Path) -> None:
    """Opening keeps no frame field in memory: a frame changed in the file after open is read as
    it is now (the history, small, is read at open)."""
    s = write_synthetic(tmp_path)
    res = paradyn.read(s.results)
    assert all(isinstance(getattr(res, name), FrameField) for name in FRAME_DATASETS)
    assert res.displacement.shape == (N_FRAMES, 15, 3) and len(res.membrane_stress) == N_FRAMES
    history_before = res.history["kinetic_energy"].copy()
    with h5py.File(s.results, "r+") as f:
        f["/frames/displacement"][2] = 7.0
        f["/history/kinetic_energy"][:] = -1.0
    assert np.all(res.displacement[2] == 7.0) and np.all(res.frame_arrays(2).displacement == 7.0)
    assert np.all(res.frame(2).point_data["displacement"] == 7.0)
    assert_array_equal(res.history["kinetic_energy"], history_before)


def test_an_incomplete_file_gives_only_its_whole_frames(tmp_path: Path) -> None:
    s = write_synthetic(tmp_path, complete=False, frames_written=3)
    res = paradyn.read(s.results, allow_incomplete=True)
    assert res.n_frames == 3 and res.displacement.shape[0] == 3
    with h5py.File(s.results, "r") as f:
        assert_array_equal(res.displacement[-1], f["/frames/displacement"][2])
    with pytest.raises(IndexError):
        res.frame_arrays(3)


def _write_names_into_results(path: Path, title: str, parts: list[str], effects: str) -> None:
    with h5py.File(path, "r+") as f:
        f.attrs["title"] = title
        f["mesh"].attrs.create("part_names", parts, dtype=h5py.string_dtype())
        f.require_group("run").attrs["effects"] = effects


def test_title_part_names_and_effects_come_from_the_results_file_first(tmp_path: Path) -> None:
    """docs/outputs.md, Names: the engine's root title, /mesh part_names and /run effects win over
    the deck's; tracked point names still come from the deck."""
    s = write_synthetic(tmp_path)
    _write_names_into_results(s.results, "from the engine", ["lower", "upper"], "shell_elements,contact")
    res = paradyn.read(s.results)
    assert res.title == "from the engine" and res.part_names == ["lower", "upper"]
    assert res.effects == ["shell_elements", "contact"]
    assert res.tracked_names == ["tip low", "tip,high"] and res.deck_path == s.deck
    s.deck.unlink()
    alone = paradyn.read(s.results)
    assert (alone.title, alone.part_names, alone.effects) == ("from the engine", ["lower", "upper"],
                                                              ["shell_elements", "contact"])
    assert alone.tracked_names == ["tracked_0", "tracked_1"]


def test_without_names_in_the_results_the_deck_gives_them(tmp_path: Path) -> None:
    s = write_synthetic(tmp_path)
    res = paradyn.read(s.results)
    assert res.title == "synthetic plate" and res.part_names == ["left plate", "right"]
    s.deck.unlink()
    assert paradyn.read(s.results).effects == []
