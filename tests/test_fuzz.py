"""Issue 17: property-based fuzzing (hypothesis) of a valid deck and a valid scene.

A deck damaged at random (an entry set to NaN, infinity, a negative or huge number; a dataset with
a row more or less, another dtype, or gone; a /control attribute changed or gone) must give: the
frontend's DeckError or acceptance, never another exception; the engine a documented exit status
within a bounded time, never a traceback or a hang; a refusal by the frontend matched by the
engine's status 2; and no results file marked complete unless the run ended with status 0. A
scene damaged at random (a key's value replaced by another type or an odd number, or the key
gone) must give a SceneError or DeckError with the scene's path, or a model, nothing else.
"""

from __future__ import annotations

import shutil
import subprocess
import tomllib
from pathlib import Path

import h5py
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from paradyn import deck, scene
from paradyn._schema import CONTROL, DATASETS, EXIT_STATUSES, STATUS_BAD_INPUT, STATUS_OK
from paradyn.mesh import geometry
from paradyn.running import launch

ROOT = Path(__file__).resolve().parents[1]
SMALL_PLATE = ROOT / "cases" / "small_plate" / "scene.toml"
# the engine's refusals that need the mesh's stable step, its geometry or the machine, which the
# frontend does not compute
RUN_GUARDS = ("steps (dt =", "mass_damping x dt", "is below the time step dt", "cross at the start",
              "this node needs about", "over /control mass_scaling_limit")
ODD_NUMBERS = [float("nan"), float("inf"), -float("inf"), -1.0, 0.0, 1e300, -1e300, 2.5, 1e-300, 7.0]


def _base_model() -> deck.Model:
    mesh = geometry.plate((0.04, 0.02), (4, 2))
    return deck.Model(
        coordinates=mesh.coordinates, connectivity=mesh.quads,
        element_part=np.zeros(mesh.n_elements, dtype=np.int32), thickness=np.array([0.001]),
        part_material=np.array([0]), material_model=np.array([1]), density=np.array([7860.0]),
        youngs_modulus=np.array([200e9]), poisson_ratio=np.array([0.3]),
        initial_velocity=np.tile([0.0, 0.0, 1.0], (mesh.n_nodes, 1)),
        load_node=np.array([3]), load_dof=np.array([3]), load_value=np.array([-5.0]), load_ramp_time=np.array([1e-6]),
        tracked_nodes=np.array([3]),
        control=deck.Control(end_time=4e-6, output_interval=2e-6))


@pytest.fixture(scope="module")
def base_deck(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return deck.write_deck(_base_model(), tmp_path_factory.mktemp("fuzz") / "base.h5")


def _damage(f: h5py.File, what: str, path: str, value: float, index: int) -> None:
    if what == "control":
        name = path
        if np.isnan(value):
            f["/control"].attrs.pop(name, None)
        else:
            f["/control"].attrs[name] = value
        return
    if path not in f:
        return
    data = f[path][()]
    if what == "entry" and data.size:
        flat = data.astype(np.float64).ravel()
        flat[index % flat.size] = value
        data = flat.reshape(data.shape)
    elif what == "row_more":
        data = np.concatenate([data, data[-1:]], axis=0) if data.size else data
    elif what == "row_less":
        data = data[:-1]
    elif what == "dtype":
        data = data.astype(np.int32 if data.dtype.kind == "f" else np.float64)
    del f[path]
    if what != "gone":
        f[path] = data


DAMAGE = st.one_of(
    st.tuples(st.sampled_from(["entry", "row_more", "row_less", "dtype", "gone"]),
              st.sampled_from([d.path for d in DATASETS]), st.sampled_from(ODD_NUMBERS), st.integers(0, 100)),
    st.tuples(st.just("control"), st.sampled_from([a.name for a in CONTROL if a.type == "float"]),
              st.sampled_from(ODD_NUMBERS), st.just(0)),
)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(damage=DAMAGE)
def test_a_damaged_deck_gets_a_documented_answer(base_deck: Path, tmp_path_factory: pytest.TempPathFactory,
                                                 damage: tuple[str, str, float, int]) -> None:
    what, name, value, _ = damage
    # a long end time is a long run, not a bad deck (the engine refuses the absurd ones itself)
    assume(not (what == "control" and name == "end_time" and 1e-4 < value < 1e12))
    folder = tmp_path_factory.mktemp("case")
    path = folder / "deck.h5"
    shutil.copyfile(base_deck, path)
    with h5py.File(path, "r+") as f:
        _damage(f, *damage)
    try:
        deck.validate_deck(path)
        frontend_accepts = True
    except deck.DeckError as error:
        frontend_accepts = False
        assert str(path) in str(error)
    done = subprocess.run([str(launch.engine_path()), str(path), str(folder / "results.h5")], cwd=folder,
                          env=launch.engine_environment(1), capture_output=True, text=True, timeout=60)
    assert done.returncode in EXIT_STATUSES, (damage, done.returncode, done.stderr)
    assert "Traceback" not in done.stderr and "HDF5-DIAG" not in done.stderr, damage
    if not frontend_accepts:
        assert done.returncode == STATUS_BAD_INPUT, (damage, done.stdout, done.stderr)
    elif done.returncode == STATUS_BAD_INPUT:   # only the checks that need the stable step are the engine's alone
        assert any(words in done.stderr for words in RUN_GUARDS), (damage, done.stderr)
    results = folder / "results.h5"
    if results.exists() and done.returncode != STATUS_OK:
        with h5py.File(results, "r") as f:
            assert int(f.attrs.get("complete", 0)) == 0, damage


def _scene_keys(table: dict, prefix: tuple = ()) -> list[tuple]:
    keys = []
    for key, value in table.items():
        if isinstance(value, dict):
            keys += _scene_keys(value, (*prefix, key))
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for i, item in enumerate(value):
                keys += _scene_keys(item, (*prefix, key, i))
        else:
            keys.append((*prefix, key))
    return keys


SCENE_KEYS = _scene_keys(tomllib.loads(SMALL_PLATE.read_text()))
ODD_VALUES = st.sampled_from(["text", -1, 0, 10**12, -1e300, 1e-300, True, [1, 2], [], {"a": 1}, "nan", None])


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(key=st.sampled_from(SCENE_KEYS), value=ODD_VALUES)
def test_a_damaged_scene_gets_a_scene_error_or_a_model(tmp_path_factory: pytest.TempPathFactory, key: tuple,
                                                         value: object) -> None:
    data = tomllib.loads(SMALL_PLATE.read_text())
    table = data
    for part in key[:-1]:
        table = table[part]
    if value is None:
        del table[key[-1]]
    else:
        table[key[-1]] = value
    path = tmp_path_factory.mktemp("scene") / "scene.toml"
    path.write_text(_toml(data))
    try:
        model = scene.build_model(scene.load_scene(path))
    except (scene.SceneError, deck.DeckError, geometry.GeometryError) as error:
        assert str(path) in str(error), (key, value, error)
        return
    assert model.n_elements > 0


def _toml(data: dict) -> str:
    """A small TOML writer for the scene's shapes (tables, arrays of tables, scalars, lists)."""
    lines: list[str] = []

    def value(v: object) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return '"' + v.replace('"', '\\"') + '"'
        if isinstance(v, float) and not np.isfinite(v):
            return "nan" if np.isnan(v) else ("inf" if v > 0 else "-inf")
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + "}"
        return repr(v)

    def table(name: str, t: dict) -> None:
        scalars = {k: v for k, v in t.items() if not isinstance(v, dict) and not _is_tables(v)}
        lines.extend(f"{k} = {value(v)}" for k, v in scalars.items())
        for k, v in t.items():
            full = f"{name}.{k}" if name else k
            if isinstance(v, dict) and not (name and k in scalars):
                lines.append(f"[{full}]")
                table(full, v)
            elif _is_tables(v):
                for item in v:
                    lines.append(f"[[{full}]]")
                    table(full, item)

    table("", data)
    return "\n".join(lines) + "\n"


def _is_tables(v: object) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


ENCODINGS = st.sampled_from(["utf-16", "utf-16-le", "utf-32", "latin-1", "cp1252", "shift_jis"])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(content=st.one_of(st.binary(min_size=1, max_size=400),
                         st.tuples(ENCODINGS, st.integers(0, 2000)),
                         st.tuples(st.just("bytes"), st.integers(0, 2000), st.binary(min_size=1, max_size=8))))
def test_a_scene_file_of_any_bytes_gets_a_scene_error_or_a_model(tmp_path_factory: pytest.TempPathFactory,
                                                                 content: object) -> None:
    """Issue 34: files that are not UTF-8 text (binary; the scene saved as UTF-16 by an editor, or
    in a legacy code page with a non-ASCII title; bytes spliced into it) give a SceneError naming
    the file, from the command's early engine start (which reads [run] precision) as from the
    reader, never another exception."""
    from paradyn.running.early_engine import scene_precision

    text = SMALL_PLATE.read_text().replace("Small cantilever plate", "Kragplatte für Stöße — 試験")
    if isinstance(content, bytes):
        data = content
    elif content[0] == "bytes":
        _, at, spliced = content
        raw = text.encode()
        data = raw[:at % len(raw)] + spliced + raw[at % len(raw):]
    else:
        encoding, _ = content
        data = text.encode(encoding, errors="replace")
    path = tmp_path_factory.mktemp("scene") / "scene.toml"
    path.write_bytes(data)
    assert scene_precision(path) in (None, "double", "mixed")
    try:
        model = scene.build_model(scene.load_scene(path))
    except (scene.SceneError, deck.DeckError, geometry.GeometryError) as error:
        assert str(path) in str(error)
        return
    assert model.n_elements > 0
