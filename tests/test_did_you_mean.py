"""Misspelt names (issue 34): every unknown or misspelt key of a scene file and of the Python API
names the closest allowed one, and a misspelt required keyword argument gives a ParaDyn error that
says so, not Python's bare TypeError about a missing argument."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

import paradyn
from paradyn import scene
from paradyn.arguments import ArgumentError, closest
from paradyn.scene import reading
from paradyn.scene.row_tables import ROW_TABLES
from paradyn.studies.design import StudyError
from paradyn.studies.spec import spec_from_table

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"


def _typo(key: str) -> str:
    """A misspelling: two different neighbouring letters swapped near the middle (a short key: its
    last letter doubled)."""
    for i in range(len(key) // 2, len(key)):
        if len(key) >= 4 and key[i - 1] != key[i]:
            return key[:i - 1] + key[i] + key[i - 1] + key[i + 1:]
    return key + key[-1]


def _tables() -> dict:
    return tomllib.loads(SMALL_PLATE.read_text())


# every key of every table of a scene file, misspelt, is named back
_KEYS = ([("run", k) for k in reading._RUN_KEYS] + [("material", k) for k in ("name", *reading._MATERIAL_KEYS)]
         + [("part", k) for k in reading._PART_KEYS] + [("fix", k) for k in reading._FIX_KEYS]
         + [("load", k) for k in reading._LOAD_KEYS] + [("track", k) for k in reading._TRACK_KEYS])


@pytest.mark.parametrize(("table", "key"), _KEYS)
def test_a_misspelt_key_of_a_scene_file_is_named(tmp_path: Path, table: str, key: str) -> None:
    tables = _tables()
    entry = tables[table] if table == "run" else tables[table][0]
    entry[_typo(key)] = entry.pop(key, 1.0)
    with pytest.raises(scene.SceneError, match=f"unknown key '{_typo(key)}' .*did you mean '{key}'\\?"):
        reading.scene_from_tables(tables, SMALL_PLATE)


@pytest.mark.parametrize("table", sorted(ROW_TABLES))
def test_a_misspelt_key_of_a_row_table_is_named(table: str) -> None:
    s = paradyn.Scene("rows", end_time=1e-4, output_interval=1e-5)
    for row_key in ROW_TABLES[table]:
        key = row_key.name
        if closest(_typo(key), [k.name for k in ROW_TABLES[table]]) != key:
            continue   # a swap that lands nearer another key of the table (none today)
        with pytest.raises(scene.SceneError, match=f"did you mean '{key}'\\?"):
            s.add(table, **{_typo(key): 1.0})


def test_misspelt_values_and_names_are_named(tmp_path: Path) -> None:
    cases = [
        ("material", "model", "elasic", "did you mean 'elastic'"),
        ("part", "material", "stel", "did you mean 'steel'"),
        ("part", "hourglass_form", "viscus", "did you mean 'viscous'"),
        ("fix", "part", "plat", "did you mean 'plate'"),
        ("load", "dof", "Uz", "did you mean 'uz'"),
        ("fix", "dofs", ["uz", "rxx"], "did you mean 'rx'"),
    ]
    for table, key, value, words in cases:
        tables = _tables()
        tables[table][0][key] = value
        with pytest.raises(scene.SceneError, match=words):
            reading.scene_from_tables(tables, SMALL_PLATE)
    tables = _tables()
    tables["materials"] = tables.pop("material")
    with pytest.raises(scene.SceneError, match=r"unknown key 'materials' .*did you mean 'material'"):
        reading.scene_from_tables(tables, SMALL_PLATE)


def test_a_misspelt_required_argument_is_a_paradyn_error_that_names_it() -> None:
    s = paradyn.Scene("plate", end_time=1e-4, output_interval=1e-5)
    with pytest.raises(scene.SceneError, match=r"paradyn\.Scene\.add_material\(\): missing required argument "
                                              r"'density' \('densty' was given: a misspelling of 'density'\?\)"):
        s.add_material("steel", model="elastic", densty=7860.0, youngs_modulus=2e11, poisson_ratio=0.3)
    with pytest.raises(TypeError):   # still a TypeError for code that catches that
        s.add_material("steel", model="elastic", densty=7860.0, youngs_modulus=2e11, poisson_ratio=0.3)
    with pytest.raises(scene.SceneError, match="'end_tim' was given: a misspelling of 'end_time'"):
        paradyn.Scene("plate", end_tim=1e-4, output_interval=1e-5)
    with pytest.raises(scene.SceneError, match="'sise' was given: a misspelling of 'size'"):
        paradyn.Plate(sise=(0.2, 0.1), elements=(4, 2))
    with pytest.raises(scene.SceneError, match="missing required argument 'material'"):
        s.add_part("p", thickness=0.002, geometry=paradyn.Plate((0.2, 0.1), (4, 2)))


def test_misspelt_optional_arguments_are_named(tmp_path: Path) -> None:
    s = paradyn.Scene("plate", end_time=1e-4, output_interval=1e-5)
    with pytest.raises(scene.SceneError, match="unknown key 'histroy_interval' in \\[run\\]; did you mean "
                                              "'history_interval'"):
        paradyn.Scene("plate", end_time=1e-4, output_interval=1e-5, histroy_interval=1e-6)
    s.add_material("steel", model="elastic", density=7860.0, youngs_modulus=2e11, poisson_ratio=0.3)
    with pytest.raises(scene.SceneError, match="did you mean 'hourglass_coefficient'"):
        s.add_part("p", material="steel", thickness=0.002, geometry=paradyn.Plate((0.2, 0.1), (4, 2)),
                   hourglass_coeficient=0.1)
    with pytest.raises(scene.SceneError, match="no row table \\[\\[rigid_wal\\]\\]; did you mean 'rigid_wall'"):
        s.add("rigid_wal", point=[0, 0, 0], normal=[0, 0, 1])
    with pytest.raises(ArgumentError, match=re.escape("paradyn.run(): unknown argument 'thread' (did you mean "
                                                      "'threads'?)")):
        paradyn.run(SMALL_PLATE, tmp_path, thread=1)
    assert not any(tmp_path.iterdir())   # refused before anything was written
    with pytest.raises(ArgumentError, match=r"paradyn\.run\(\): missing required argument 'out'"):
        paradyn.run(SMALL_PLATE)


def test_misspelt_study_keys_are_named() -> None:
    with pytest.raises(ArgumentError, match=r"paradyn\.study\(\): missing required argument 'out'"):
        paradyn.study(SMALL_PLATE)
    with pytest.raises(StudyError, match="unknown study option 'knbos'; did you mean 'knobs'"):
        spec_from_table({}, "scene.toml").merged(knbos={"mesh": [1, 2]})
    with pytest.raises(StudyError, match="unknown key 'desing' in \\[study\\]; did you mean 'design'"):
        spec_from_table({"desing": "grid"}, "scene.toml")
    with pytest.raises(StudyError, match="did you mean 'richardson'"):
        spec_from_table({"reference": "richardsen"}, "scene.toml")
    with pytest.raises(StudyError, match="did you mean 'core_s'"):
        spec_from_table({"cost": "cores"}, "scene.toml")
