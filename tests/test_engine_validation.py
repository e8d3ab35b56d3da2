"""Both validators reject malformed decks (docs/formats.md: "Both sides validate").

A valid deck of a tiny model is written with ``paradyn.deck.write_deck``; each case damages a copy
with h5py. The engine (run directly, one rank) must exit with status 2, print one
``paradyn-engine: error:`` line naming the dataset, and create no results file; the frontend's
``validate_deck`` must raise a DeckError naming the same dataset.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import cli, deck
from paradyn._schema import DATASETS
from paradyn.mesh import geometry
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]


def _tiny_model() -> deck.Model:
    mesh = geometry.plate((0.02, 0.01), (2, 1))
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
        tracked_nodes=np.array([5]),
        control=deck.Control(end_time=2e-6, output_interval=1e-6),
    )


@pytest.fixture(scope="module")
def good_deck(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return deck.write_deck(_tiny_model(), tmp_path_factory.mktemp("good") / "deck.h5")


def _replace(f: h5py.File, path: str, data: np.ndarray) -> None:
    del f[path]
    f.create_dataset(path, data=data)


def _missing_thickness(f: h5py.File) -> None:
    del f["/parts/thickness"]


def _coordinates_n_by_2(f: h5py.File) -> None:
    _replace(f, "/nodes/coordinates", f["/nodes/coordinates"][()][:, :2])


def _negative_thickness(f: h5py.File) -> None:
    f["/parts/thickness"][0] = -0.001


def _nan_coordinate(f: h5py.File) -> None:
    f["/nodes/coordinates"][3, 1] = np.nan


def _connectivity_out_of_range(f: h5py.File) -> None:
    f["/elements/connectivity"][1, 2] = 99


def _wrong_version(f: h5py.File) -> None:
    f.attrs["paradyn_deck_version"] = np.int32(2)


def _fractional_version(f: h5py.File) -> None:
    f.attrs["paradyn_deck_version"] = np.float64(1.7)


def _unknown_partition(f: h5py.File) -> None:
    f["/control"].attrs["partition"] = "metis"


def _numeric_partition(f: h5py.File) -> None:
    f["/control"].attrs["partition"] = np.float64(2.0)


# (case id, damage, the dataset or attribute both messages must name)
CASES: list[tuple[str, Callable[[h5py.File], None], str]] = [
    ("missing_thickness", _missing_thickness, "/parts/thickness"),
    ("coordinates_n_by_2", _coordinates_n_by_2, "/nodes/coordinates"),
    ("negative_thickness", _negative_thickness, "/parts/thickness"),
    ("nan_coordinate", _nan_coordinate, "/nodes/coordinates"),
    ("connectivity_out_of_range", _connectivity_out_of_range, "/elements/connectivity"),
    ("wrong_version", _wrong_version, "paradyn_deck_version"),
    ("fractional_version", _fractional_version, "paradyn_deck_version"),
    ("unknown_partition", _unknown_partition, "partition"),
    ("numeric_partition", _numeric_partition, "partition"),
]


def _damaged(good: Path, folder: Path, damage: Callable[[h5py.File], None]) -> Path:
    path = folder / "deck.h5"
    shutil.copyfile(good, path)
    with h5py.File(path, "r+") as f:
        damage(f)
    return path


def _run_engine(deck_path: Path, results: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(launch.engine_path()), str(deck_path), str(results)], cwd=deck_path.parent,
                          env=launch.engine_environment(1), capture_output=True, text=True, timeout=120)


def test_engine_accepts_the_undamaged_deck(good_deck: Path, tmp_path: Path) -> None:
    """The control case: the deck every damaged copy starts from runs to completion."""
    path = tmp_path / "deck.h5"
    shutil.copyfile(good_deck, path)
    done = _run_engine(path, tmp_path / "results.h5")
    assert done.returncode == 0, done.stderr
    assert "PARADYN-DONE" in done.stdout
    with h5py.File(tmp_path / "results.h5", "r") as f:
        assert int(f.attrs["complete"]) == 1
    deck.validate_deck(path)


@pytest.mark.parametrize("case, damage, name", [
    pytest.param(*c, id=c[0]) for c in CASES])
def test_engine_rejects_a_damaged_deck(good_deck: Path, tmp_path: Path, case: str,
                                       damage: Callable[[h5py.File], None], name: str) -> None:
    """docs/formats.md: the engine rejects a bad deck with one message naming the dataset and
    exits with status 2 without creating a results file."""
    path = _damaged(good_deck, tmp_path, damage)
    results = tmp_path / "results.h5"
    done = _run_engine(path, results)
    assert done.returncode == 2, (done.returncode, done.stdout, done.stderr)
    errors = [line for line in done.stderr.splitlines() if line.startswith("paradyn-engine: error:")]
    assert len(errors) == 1, done.stderr
    assert name in errors[0]
    assert not results.exists()
    assert "PARADYN-START" not in done.stdout


@pytest.mark.parametrize("case, damage, name", [pytest.param(*c, id=c[0]) for c in CASES])
def test_frontend_rejects_a_damaged_deck(good_deck: Path, tmp_path: Path, case: str,
                                         damage: Callable[[h5py.File], None], name: str) -> None:
    """docs/formats.md: paradyn.deck.validate_deck raises DeckError naming the dataset."""
    path = _damaged(good_deck, tmp_path, damage)
    with pytest.raises(deck.DeckError, match=re.escape(name)):
        deck.validate_deck(path)


def test_unknown_partition_message_names_value_and_choices(good_deck: Path, tmp_path: Path) -> None:
    """docs/formats.md (/control partition): an unknown method is refused with exit status 2,
    naming the attribute, the value and the methods to use instead; no results file."""
    path = _damaged(good_deck, tmp_path, _unknown_partition)
    results = tmp_path / "results.h5"
    done = _run_engine(path, results)
    assert done.returncode == 2
    error = done.stderr.strip()
    for word in ("/control attribute partition", '"metis"', '"blocks"', '"rcb"', "leave it out"):
        assert word in error, (word, error)
    assert not results.exists()
    with pytest.raises(deck.DeckError, match=r"partition = 'metis' is unknown; use 'blocks' or 'rcb'"):
        deck.validate_deck(path)


@pytest.mark.parametrize("value, method", [
    pytest.param("blocks", "blocks", id="variable_length_utf8"),
    pytest.param(np.bytes_(b"rcb"), "rcb", id="fixed_length_ascii"),
    pytest.param(None, deck.DEFAULT_PARTITION, id="absent"),
])
def test_engine_reads_the_partition_attribute(good_deck: Path, tmp_path: Path, value: object,
                                              method: str) -> None:
    """docs/formats.md: partition is a string attribute, as h5py writes a str (variable length,
    UTF-8) or as a fixed-length string; absent means the default. The engine reports the method
    on its PARADYN-START line and the frontend reads the same value back."""
    def edit(f: h5py.File) -> None:
        if value is not None:
            f["/control"].attrs["partition"] = value
        elif "partition" in f["/control"].attrs:
            del f["/control"].attrs["partition"]

    path = _damaged(good_deck, tmp_path, edit)
    done = _run_engine(path, tmp_path / "results.h5")
    assert done.returncode == 0, done.stderr
    start = launch.parse_line(next(line for line in done.stdout.splitlines() if line.startswith("PARADYN-START")))
    assert start is not None and start[1]["partition"] == method
    assert deck.read_deck(path).control.partition == (None if value is None else method)


def test_paradyn_run_rejects_a_scene_with_a_typo(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """docs/scene.md: an unknown key is an error naming the key; paradyn-run exits with status 2
    and launches nothing."""
    text = (ROOT / "cases" / "small_plate" / "scene.toml").read_text()
    assert "thickness = 0.002\n" in text
    typo = text.replace("thickness = 0.002\n", "thickness = 0.002\nhourglas_coefficient = 0.1\n", 1)
    scene_path = tmp_path / "typo" / "scene.toml"
    scene_path.parent.mkdir()
    scene_path.write_text(typo)
    out = tmp_path / "out"
    status = cli.main([str(scene_path), "-o", str(out), "-q", "-n", "1", "-t", "1", "--no-plots"])
    assert status == 2
    err = capsys.readouterr().err
    assert err.startswith("paradyn-run: error:")
    assert "hourglas_coefficient" in err
    assert "hourglass_coefficient" in err          # the allowed keys are listed
    assert not (out / "results.h5").exists() and not (out / "deck.h5").exists()


def _unused_node(f: h5py.File) -> None:
    """One more node, with every per-node dataset, that no element uses."""
    for name in (spec.path for spec in DATASETS if spec.shape[0] == "n_nodes"):
        if name in f:
            _replace(f, name, np.concatenate([f[name][()], f[name][-1:]]))


def test_engine_refuses_a_node_that_belongs_to_no_element(good_deck: Path, tmp_path: Path) -> None:
    """docs/formats.md (relation node_in_element): such a node has no mass. The engine used to
    accept it (exit 0, the node written at [0, 0, 0]); now it exits with status 2 naming the
    dataset and the node, as the frontend does."""
    path = _damaged(good_deck, tmp_path, _unused_node)
    with h5py.File(path, "r") as f:
        unused = f["/nodes/coordinates"].shape[0] - 1
    done = _run_engine(path, tmp_path / "results.h5")
    assert done.returncode == 2, (done.returncode, done.stderr)
    assert f"/nodes/coordinates[{unused}] belongs to no element" in done.stderr
    assert not (tmp_path / "results.h5").exists()
    with pytest.raises(deck.DeckError, match=re.escape(f"/nodes/coordinates[{unused}] belongs to no element")):
        deck.validate_deck(path)


def test_engine_refuses_a_negative_progress_interval(good_deck: Path, tmp_path: Path) -> None:
    """docs/formats.md: progress_interval must be > 0. The engine used to run with -1; now it
    exits with status 2 naming the attribute, as the frontend does."""
    path = _damaged(good_deck, tmp_path, lambda f: f["/control"].attrs.__setitem__("progress_interval", -1.0))
    done = _run_engine(path, tmp_path / "results.h5")
    assert done.returncode == 2, (done.returncode, done.stderr)
    assert "/control attribute progress_interval = -1" in done.stderr and "must be > 0" in done.stderr
    with pytest.raises(deck.DeckError, match=r"/control attribute progress_interval = -1 must be > 0"):
        deck.validate_deck(path)
