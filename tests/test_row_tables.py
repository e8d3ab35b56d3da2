"""Scene tables driven by the schema alone (paradyn.scene.row_tables, docs/scene.md "Row tables").

A row symbol with ``scene_table`` in schema/deck.toml makes a ``[[table]]`` of the scene whose keys,
types, bounds, defaults, messages, deck arrays and ``paradyn.Scene.add`` come from its datasets;
``[[rigid_wall]]`` is one. The [[material]] keys come from the /materials datasets the same way.
"""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

import paradyn
from paradyn import scene
from paradyn.scene.row_tables import ROW_TABLES, key_required, scene_words


def _plate() -> paradyn.Scene:
    s = paradyn.Scene("walls", end_time=1e-5, output_interval=5e-6)
    s.add_material("steel", model="elastic", density=7860.0, youngs_modulus=200e9, poisson_ratio=0.3)
    s.add_part("plate", material="steel", thickness=0.002, geometry=paradyn.Plate(size=(0.1, 0.1), elements=(2, 2)))
    return s


def test_the_rigid_wall_table_is_its_datasets() -> None:
    keys = {k.name: k for k in ROW_TABLES["rigid_wall"]}
    assert list(keys) == ["point", "normal", "shape", "edge", "size", "radius", "length", "velocity",
                          "penalty_scale", "friction", "birth_time", "death_time"]
    # required: no default its own bounds accept; the others take the schema's default
    assert [name for name, k in keys.items() if k.required] == ["point", "normal"]
    assert key_required(keys["point"].spec) and not key_required(keys["penalty_scale"].spec)


def test_add_checks_and_builds_rows_as_the_schema_says(tmp_path: Path) -> None:
    s = _plate()
    s.add("rigid_wall", point=[0.0, 0.0, -0.01], normal=[0.0, 0.0, 1.0])
    s.add_rigid_wall(point=[0.0, 0.0, 0.5], normal=[0.0, 0.0, -2.0], velocity=[0.0, 0.0, -1.0], penalty_scale=0.2)
    model = s.build()
    np.testing.assert_array_equal(model.rigid_wall_point, [[0.0, 0.0, -0.01], [0.0, 0.0, 0.5]])
    np.testing.assert_array_equal(model.rigid_wall_velocity, [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
    np.testing.assert_array_equal(model.rigid_wall_penalty_scale, [0.1, 0.2])   # the schema's default, then given
    assert model.n_rigid_walls == 2
    written = tomllib.loads(s.to_toml(tmp_path / "walls.toml").read_text())
    assert [w["point"] for w in written["rigid_wall"]] == [[0.0, 0.0, -0.01], [0.0, 0.0, 0.5]]
    again = scene.load_scene(tmp_path / "walls.toml")
    assert again.rows["rigid_wall"][1]["penalty_scale"] == 0.2


@pytest.mark.parametrize("keys, words", [
    ({"point": [0.0, 0.0, 0.0]}, "missing required key 'normal' in [[rigid_wall]] #1"),
    ({"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0], "penalty_scale": 0.7},
     "'penalty_scale' in [[rigid_wall]] #1 = 0.7 must be in (0, 0.5]"),
    ({"point": [0.0, 0.0], "normal": [0.0, 0.0, 1.0]}, "'point' in [[rigid_wall]] #1 must be a list of 3"),
    ({"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0], "speed": 1.0}, "unknown key 'speed' in [[rigid_wall]] #1"),
])
def test_a_bad_row_is_refused_naming_the_key(keys: dict, words: str) -> None:
    with pytest.raises(scene.SceneError) as refused:
        _plate().add("rigid_wall", **keys)
    assert words in str(refused.value)


def test_an_unknown_row_table_is_refused() -> None:
    with pytest.raises(scene.SceneError, match=r"no row table \[\[wall\]\]; the row tables are: rigid_wall"):
        _plate().add("wall", point=[0.0, 0.0, 0.0])


def test_deck_messages_name_the_scene_entry() -> None:
    assert scene_words("/rigid_walls/normal[2] is the zero vector") == \
        "/rigid_walls/normal[2] ([[rigid_wall]] #3 'normal') is the zero vector"
    assert scene_words("/parts/thickness[0] must be > 0") == "/parts/thickness[0] must be > 0"


def test_material_keys_apply_to_the_models_their_datasets_are_checked_for() -> None:
    """yield_stress is a /materials dataset checked for plastic models only (checked_when): an
    elastic material refuses it; a plastic one requires it (its default 0 fails its bound > 0)."""
    s = _plate()
    with pytest.raises(scene.SceneError, match=r"'yield_stress' in \[\[material\]\] #2 'soft' only applies to "
                                               r"model = \"j2_plasticity\""):
        s.add_material("soft", model="elastic", density=1.0, youngs_modulus=1.0, poisson_ratio=0.3, yield_stress=1.0)
    with pytest.raises(scene.SceneError, match=r"missing required key 'yield_stress' in \[\[material\]\] #2"):
        s.add_material("soft", model="j2_plasticity", density=1.0, youngs_modulus=1.0, poisson_ratio=0.3)
    s.add_material("soft", model="j2_plasticity", density=1.0, youngs_modulus=10.0, poisson_ratio=0.3,
                   yield_stress=1.0)
    assert s.validate().materials[1].hardening_mixing == 1.0   # the schema's default
