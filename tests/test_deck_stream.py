"""The deck stream (docs/formats.md, "Deck stream"): the engine writes from it the file h5py writes,
refuses a broken stream without leaving a file, and a run loads h5py only once its engine runs."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import deck, scene
from paradyn.deck import stream as deck_stream
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]
# the effects tour has loads, pressure, a rigid wall, gravity and prescribed velocities; the pipe
# whip contacts, tracked nodes and names; the keyword deck the file ids
SCENES = ("cases/effects_tour/scene.toml", "cases/pipe_whip/scene.toml", "cases/pipe_whip_keyword/pipe_whip.k")


def _model(source: str) -> deck.Model:
    if source.endswith(".k"):
        from paradyn.keyword.scene import read_keyword

        return read_keyword(ROOT / source, quiet=True)
    return scene.build_model(scene.load_scene(ROOT / source))


def _send(folder: Path, stream: bytes, then: bytes = b"") -> subprocess.CompletedProcess:
    """The engine --await-deck --check fed ``deck``, the stream and ``then``."""
    command = [str(launch.engine_path()), str(folder / "deck.h5"), str(folder / "results.h5"), "--await-deck",
               "--check"]
    return subprocess.run(command, input=b"deck\n" + stream + then, capture_output=True, timeout=120,
                          env=launch.engine_environment(1))


def _contents(path: Path) -> dict[str, tuple]:
    """Every dataset and attribute of a file: its HDF5 type class, string kind, shape and bytes."""
    found: dict[str, tuple] = {}

    def attributes(prefix: str, obj: h5py.HLObject) -> None:
        for name in obj.attrs:
            attribute = obj.attrs.get_id(name)
            kind = attribute.get_type()
            text = kind.get_class() == h5py.h5t.STRING
            found[f"{prefix}@{name}"] = (kind.get_class(), kind.get_size() if not text else kind.is_variable_str(),
                                         kind.get_cset() if text else None, attribute.shape, repr(obj.attrs[name]))

    def visit(name: str, obj: h5py.HLObject) -> None:
        if isinstance(obj, h5py.Dataset):
            found[name] = (obj.dtype.str, obj.shape, obj[()].tobytes())
        attributes(name, obj)

    with h5py.File(path, "r") as f:
        attributes("", f)
        f.visititems(visit)
    return found


@pytest.mark.parametrize("source", SCENES)
def test_the_engine_writes_from_the_stream_the_deck_h5py_writes(tmp_path: Path, source: str) -> None:
    model = _model(source)
    by_h5py = deck.write_deck(model, tmp_path / "h5py.h5")
    ran = _send(tmp_path, b"".join(deck_stream.encode(model)), b"go\n")
    assert ran.returncode == 0, ran.stderr.decode()
    assert b"PARADYN-CHECK" in ran.stdout
    written, expected = _contents(tmp_path / "deck.h5"), _contents(by_h5py)
    assert written.keys() == expected.keys()
    for name, value in expected.items():
        assert written[name] == value, name
    mine, theirs = deck.read_deck(tmp_path / "deck.h5"), deck.read_deck(by_h5py)   # and the reader takes it
    for spec in deck.DATASETS:
        a, b = getattr(mine, spec.python), getattr(theirs, spec.python)
        assert (a is None and b is None) or np.array_equal(a, b), spec.python
    assert mine.control == theirs.control and mine.title == theirs.title
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.h5", "h5py.h5"]   # nothing else left


def test_a_unicode_title_and_names_come_through(tmp_path: Path) -> None:
    model = _model(SCENES[1])
    model.title = "Rohrschlag, Fig. 1: pipe whip 管 (ü, é)"
    model.part_names = ["lower pipe ü", "upper \u00e9 pipe"]
    ran = _send(tmp_path, b"".join(deck_stream.encode(model)), b"go\n")
    assert ran.returncode == 0, ran.stderr.decode()
    again = deck.read_deck(tmp_path / "deck.h5")
    assert again.title == model.title and list(again.part_names) == model.part_names


@pytest.mark.parametrize("cut", ["inside", "before_end", "bad_line", "bad_length"])
def test_a_broken_stream_stops_the_engine_and_leaves_no_file(tmp_path: Path, cut: str) -> None:
    stream = b"".join(deck_stream.encode(_model(SCENES[1])))
    broken = {"inside": stream[: len(stream) // 2], "before_end": stream.removesuffix(b"end\n"),
              "bad_line": stream.replace(b"dataset /nodes/coordinates float64", b"dataset /nodes/coordinates real"),
              "bad_length": re.sub(rb"(attribute / title string 0\n)\d+\n", rb"\1-3\n", stream, count=1)}
    assert broken[cut] != stream
    ran = _send(tmp_path, broken[cut])
    assert ran.returncode == 2
    message = ran.stderr.decode()
    assert "deck stream" in message and "docs/formats.md" in message
    assert ("bad dataset line" in message) == (cut == "bad_line")
    assert ("bad string length" in message) == (cut == "bad_length")
    assert list(tmp_path.iterdir()) == []


def test_a_stream_without_go_writes_the_deck_and_does_not_run(tmp_path: Path) -> None:
    """The frontend gave up after sending the deck: the engine ends with status 0, without running."""
    ran = _send(tmp_path, b"".join(deck_stream.encode(_model(SCENES[1]))))
    assert ran.returncode == 0 and b"PARADYN-CHECK" not in ran.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["deck.h5"]


def test_a_nul_in_a_name_is_refused_before_anything_is_sent(tmp_path: Path) -> None:
    model = _model(SCENES[1])
    model.part_names = ["lower\0pipe", "upper"]
    with pytest.raises(deck.DeckError, match="NUL"):
        deck.validate_model(model)


def test_a_run_loads_h5py_only_once_its_engine_runs() -> None:
    """docs/performance.md, "Fixed costs": paradyn-run's modules up to the deck load no h5py (20 ms),
    which comes while the engine runs."""
    code = ("import sys; import paradyn.commands, paradyn.cli, paradyn.running.workflow, paradyn.scene, paradyn.deck, "
            "paradyn.deck.stream; print('h5py' in sys.modules)")
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    assert loaded.stdout.strip() == "False"
