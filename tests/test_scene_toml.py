"""Scene files that read back (issue 34): :meth:`paradyn.Scene.to_toml` writes, with ``tomli_w``,
text that ``tomllib`` (the scene reader's parser) reads to the same tables, for every document the
parser accepts (hypothesis) and for every scene the scene reader accepts, ``[study]`` included."""

from __future__ import annotations

import datetime
import tempfile
import tomllib
from pathlib import Path
from typing import Any

import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import paradyn
from paradyn import scene
from paradyn.scene.toml_writing import scene_toml

# any key (quoted where it must be: '@', '.', spaces, quotes, control characters), any value TOML holds
_KEYS = st.text(max_size=8)
_SCALARS = st.one_of(
    st.booleans(), st.integers(-(2**63), 2**63 - 1), st.floats(allow_nan=False), st.text(max_size=12),
    st.dates(min_value=datetime.date(1, 1, 1)), st.times(), st.datetimes(min_value=datetime.datetime(1, 1, 1)),
)
_VALUES = st.recursive(_SCALARS, lambda inner: st.lists(inner, max_size=4) | st.dictionaries(_KEYS, inner, max_size=4),
                       max_leaves=16)
_DOCUMENTS = st.dictionaries(_KEYS, _VALUES, max_size=6)


@given(_DOCUMENTS)
@settings(max_examples=300, deadline=None)
def test_every_document_the_parser_reads_is_written_back_to_itself(document: dict[str, Any]) -> None:
    assert tomllib.loads(scene_toml(document)) == document


def test_the_cases_of_the_issue_read_back() -> None:
    """The four kinds of text the project's own writer got wrong: a key with '@', an array of
    tables inside a table, control characters in a string, dotted and quoted keys."""
    tables = {"title": "tab\there, bell\a, nul\x00, escape\x1b and a quote \" and \\",
              "study": {"reference_values": {"tip@final": 1e-3, "a.b": 2.0, "with space": 3.0, "": 4.0},
                        "runs": [{"mesh": 2}, {"mesh": 4, "integration_points": 3}],
                        "knobs": {"time_step_safety": [0.9, 0.45]}},
              "x": {"y.z": {"deep": [{"a": [1, {"b": 2}]}]}}}
    assert tomllib.loads(scene_toml(tables)) == tables


def _scene_document(title: str, material: str, part: str, end_time: float, reference_values: dict[str, float],
                    runs: list[dict[str, int]]) -> dict[str, Any]:
    return {
        "title": title,
        "run": {"end_time": end_time, "output_interval": end_time / 4},
        "material": [{"name": material, "model": "elastic", "density": 7860.0, "youngs_modulus": 2e11,
                      "poisson_ratio": 0.3}],
        "part": [{"name": part, "material": material, "thickness": 0.002,
                  "geometry": {"kind": "plate", "size": [0.2, 0.1], "elements": [4, 2]}}],
        "fix": [{"part": part, "box": [[-1e-6, -1e-6, -1e-6], [1e-6, 0.2, 1e-6]]}],
        "track": [{"name": f"{part}@tip", "part": part, "point": [0.2, 0.1, 0.0]}],
        "study": {"reference_values": reference_values, "runs": runs, "knobs": {"mesh": [1, 2]}},
    }


@given(title=st.text(), material=st.text(min_size=1), part=st.text(min_size=1),
       end_time=st.floats(min_value=1e-9, max_value=1e3),
       reference_values=st.dictionaries(st.text(), st.floats(allow_nan=False, allow_infinity=False), max_size=3),
       runs=st.lists(st.dictionaries(st.sampled_from(["mesh", "integration_points"]), st.integers(1, 5), min_size=1),
                     max_size=3))
@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
def test_every_scene_the_reader_accepts_is_written_back_to_itself(title: str, material: str, part: str,
                                                                  end_time: float,
                                                                  reference_values: dict[str, float],
                                                                  runs: list[dict[str, int]]) -> None:
    document = _scene_document(title, material, part, end_time, reference_values, runs)
    with tempfile.TemporaryDirectory() as folder:
        source, copy = Path(folder) / "source.toml", Path(folder) / "copy.toml"
        source.write_text(tomli_w.dumps(document), encoding="utf-8")
        loaded = paradyn.Scene.from_toml(source)          # the reader accepts it
        loaded.to_toml(copy)
        assert tomllib.loads(copy.read_text(encoding="utf-8")) == document
        assert paradyn.Scene.from_toml(copy).to_dict() == loaded.to_dict()
        again = scene.load_scene(copy)
        assert again.title == title and again.materials[0].name == material and again.parts[0].name == part


def test_a_built_scene_reads_back_through_its_file(tmp_path: Path) -> None:
    s = paradyn.Scene("quote \" and newline \n", end_time=1e-4, output_interval=2.5e-5)
    s.add_material("st@el", model="elastic", density=7860.0, youngs_modulus=2e11, poisson_ratio=0.3)
    s.add_part("p.1", material="st@el", thickness=0.002, geometry=paradyn.Plate((0.2, 0.1), (4, 2)))
    path = s.to_toml(tmp_path / "scene.toml")
    assert paradyn.Scene.from_toml(path).to_dict() == s.to_dict()
