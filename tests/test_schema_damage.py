"""Every rule of the deck schema, broken one at a time, is refused by both validators.

A small valid deck (two parts, a J2 and an elastic material, loads, a contact pair, tracked
nodes, a rigid wall, a base acceleration, every optional dataset and /control attribute present)
is damaged once per rule that ``schema/deck.toml`` declares (``paradyn._schema.RULES``): a required
dataset or attribute removed, the wrong type class, the wrong shape or row count, each bound
crossed, an unknown enum code, an index out of range, a non-finite value, each cross-field relation
broken. The damages are derived from the schema tables, so a new dataset or bound is covered
without editing this file; a new relation needs its damage in RELATION_DAMAGES (the coverage test
says so).

For each damaged deck, the frontend (``paradyn.deck.validate_deck``) must raise DeckError and the
engine (run directly on one rank) must exit with status 2 (bad input) without creating a results
file, and both messages must name the same dataset or attribute.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import _schema, deck
from paradyn._schema import CONTROL, DATASETS, ENUMS, RELATIONS, RULES, SIZES
from paradyn.mesh import geometry
from paradyn.running import launch

Damage = Callable[[h5py.File], None]
_DATASET = {d.path: d for d in DATASETS}
_CONTROL = {a.name: a for a in CONTROL}
_ENTITY_SYMBOL = {s.entity: s.symbol for s in SIZES.values()}


def _base_model() -> deck.Model:
    """Two 2 x 1 strips 1.5 mm apart: part 0 (rate-dependent J2 steel, so that its row meets every
    condition of the /materials datasets) below, part 1 (elastic aluminium) above, with gravity, a
    pressure on part 1, a prescribed velocity and a base acceleration, over two load curves; a third
    material, piecewise_linear with a hardening curve and a rate curve (curves 2 and 3), used by no
    part, meets the conditions of its own datasets; a rigid lid above the strips (part 2, the
    fourth material: one face of a rigid solid, surface only, its mass on its nodes); and a wire
    (part 3, a truss of the aluminium) from the lower strip to the upper."""
    lower = geometry.plate((0.02, 0.01), (2, 1))
    upper = geometry.plate((0.02, 0.01), (2, 1), origin=(0.0, 0.0, 0.0015))
    lid = geometry.plate((0.02, 0.01), (1, 1), origin=(0.0, 0.0, 0.004))
    n = lower.n_nodes
    coordinates = np.vstack([lower.coordinates, upper.coordinates, lid.coordinates])
    n_all = len(coordinates)
    fixed = np.zeros((n_all, 6), dtype=np.int32)
    fixed[[0, 3], :] = 1
    return deck.Model(
        coordinates=coordinates,
        connectivity=np.vstack([lower.quads, upper.quads + n, lid.quads + 2 * n, [[2, n + 2, n + 2, n + 2]]]),
        element_part=np.array([0, 0, 1, 1, 2, 3]),
        thickness=np.array([0.001, 0.0012, 0.002, 0.0005]),
        part_material=np.array([0, 1, 3, 1]),
        integration_points=np.array([5, 3, 1, 1]),
        hourglass_coefficient=np.array([0.1, 0.05, 0.1, 0.1]),
        hourglass_form=np.array([2, 1, 3, 3]),
        surface_only=np.array([0, 0, 1, 0]),
        element_kind=np.array([1, 1, 1, ENUMS["element_kind"]["truss"]]),
        cross_section_area=np.array([0.0, 0.0, 0.0, 2e-7]),
        material_model=np.array([ENUMS["material_model"]["j2_rate"], deck.ELASTIC,   # plastic, with a rate
                                 ENUMS["material_model"]["piecewise_linear"], ENUMS["material_model"]["rigid"]]),
        density=np.array([7860.0, 2700.0, 7800.0, 7860.0]),
        youngs_modulus=np.array([200e9, 70e9, 210e9, 200e9]),
        poisson_ratio=np.array([0.3, 0.33, 0.3, 0.3]),
        yield_stress=np.array([250e6, 0.0, 300e6, 0.0]),
        tangent_modulus=np.array([1e9, 0.0, 0.0, 0.0]),
        hardening_mixing=np.array([0.5, 1.0, 1.0, 1.0]),
        rate_c=np.array([40.4, 0.0, 0.0, 0.0]),
        rate_p=np.array([5.0, 0.0, 0.0, 0.0]),
        hardening_curve=np.array([-1, -1, 2, -1]),
        rate_curve=np.array([-1, -1, 3, -1]),
        initial_velocity=np.tile([0.0, 0.0, -1.0], (n_all, 1)) * (np.arange(n_all) >= n)[:, None],
        initial_angular_velocity=np.zeros((n_all, 3)),
        fixed_dofs=fixed,
        node_rigid_body=np.where(np.arange(n_all) >= 2 * n, 0, -1),   # a rigid lid: the faces of a solid
        added_mass=np.where(np.arange(n_all) >= 2 * n, 0.01, 0.0),
        rigid_body_part=np.array([2]),
        rigid_body_fixed_dofs=np.array([[0, 0, 1, 0, 0, 0]]),
        rotation_tie_node=np.array([n + 1]),   # the upper strip's middle node turns with the lower's first element
        rotation_tie_masters=lower.quads[:1],
        rotation_tie_weights=np.array([[0.25, 0.25, 0.25, 0.25]]),
        node_ids=np.arange(101, 101 + n_all),
        element_ids=np.array([7, 9, 11, 13, 15, 17]),
        part_ids=np.array([3, 4, 5, 6]),
        load_node=np.array([2, 8]),
        load_dof=np.array([3, 6]),
        load_value=np.array([-5.0, 0.01]),
        load_ramp_time=np.array([1e-6, 0.0]),
        tracked_nodes=np.array([5, 11]),
        contact_pairs=np.array([[0, 1]]),
        contact_penalty_scale=np.array([0.1]),
        contact_static_friction=np.array([0.2]),
        contact_dynamic_friction=np.array([0.1]),
        contact_friction_decay=np.array([0.5]),
        contact_passes=np.array([2]),
        contact_kind=np.array([1]),
        rigid_wall_point=np.array([[0.0, 0.0, -0.01]]),
        rigid_wall_normal=np.array([[0.0, 0.0, 2.0]]),
        rigid_wall_velocity=np.array([[0.0, 0.0, 0.5]]),
        rigid_wall_penalty_scale=np.array([0.2]),
        rigid_wall_friction=np.array([0.1]),
        rigid_wall_node_wall=np.array([0]),
        rigid_wall_node=np.array([0]),
        curve_first_point=np.array([0, 2, 3, 5]),
        curve_time=np.array([0.0, 1e-6, 0.0, 0.0, 0.1, 0.0, 100.0]),
        curve_value=np.array([0.0, 1.0, 1.0, 300e6, 350e6, 1.0, 2.0]),
        pressure_part=np.array([1]),
        pressure_value=np.array([1e3]),
        pressure_curve=np.array([0]),
        prescribed_node=np.array([1]),
        prescribed_dof=np.array([1]),
        prescribed_value=np.array([0.1]),
        prescribed_curve=np.array([1]),
        base_acceleration_direction=np.array([[0.0, 3.0, 4.0]]),
        base_acceleration_value=np.array([2.0]),
        base_acceleration_curve=np.array([0]),
        control=deck.Control(end_time=2e-6, output_interval=1e-6, history_interval=5e-7, time_step=0.0,
                             time_step_safety=0.9, mass_damping=0.0, progress_interval=0.5,
                             contact_sort_interval=0, checkpoint_interval=0.0, partition="blocks",
                             contact_gather="near", precision="double", gravity_x=0.0, gravity_y=0.0, gravity_z=-9.81,
                             effect_switches={switch: "on" for switch in _schema.EFFECT_SWITCHES}),
        title="damage base", part_names=["steel strip", "aluminium strip", "rigid lid", "wire"],
        material_names=["steel", "aluminium", "curved steel", "rigid steel"],
        tracked_names=["lower tip", "upper tip"],
    )


# ----------------------------------------------------------------------------------------------
# damages, one per kind of rule


def _rewrite(path: str, change: Callable[[np.ndarray], np.ndarray]) -> Damage:
    def damage(f: h5py.File) -> None:
        data = change(f[path][()])
        del f[path]
        f.create_dataset(path, data=data)
    return damage


def _set_first(path: str, value: float) -> Damage:
    """Entry [0] (or [0, 0]) of the first row that the dataset's rules are checked on (row 0, the
    j2_rate material, for most conditioned rows; the piecewise_linear material for its own)."""
    spec = _DATASET[path]
    row = 0
    if spec.checked_when is not None:
        condition = _schema.CONDITIONS[spec.checked_when]
        selector = getattr(_base_model(), next(d.python for d in DATASETS if d.path == condition.dataset))
        row = int(np.flatnonzero(np.isin(selector, condition.codes))[0])

    def change(data: np.ndarray) -> np.ndarray:
        data = data.astype(np.float64 if isinstance(value, float) and data.dtype.kind == "f" else data.dtype)
        data[(row,) + (0,) * (data.ndim - 1)] = value
        return data
    return _rewrite(path, change)


def _crossed(spec: _schema.DatasetSpec | _schema.AttributeSpec, side: str) -> float:
    """A value just outside the bound: the bound itself where it is excluded, else one beyond."""
    bound = spec.lower if side == "lower" else spec.upper
    assert bound is not None
    if not bound.inclusive:
        return float(bound.value)
    return float(bound.value) + (-1.0 if side == "lower" else 1.0)


def _unknown_code(enum: str) -> int:
    return max(ENUMS[enum].values()) + 1


def _dataset_damage(path: str, rule: str) -> Damage:
    spec = _DATASET[path]
    if rule in ("missing", "required_when"):
        return lambda f: f.__delitem__(path)
    if rule == "class":
        return _rewrite(path, lambda a: a.astype(np.float64 if spec.type == "int" else np.int64))
    if rule == "shape":   # one column too many, or a column axis on a one-dimensional dataset
        return _rewrite(path, lambda a: np.concatenate([a, a[:, :1]], axis=1) if a.ndim == 2 else a[:, None])
    if rule == "rows":
        return _rewrite(path, lambda a: a[:-1])
    if rule == "empty":
        return _rewrite(path, lambda a: a[:0])
    if rule in ("lower", "upper"):
        value = _crossed(spec, rule)
        return _set_first(path, int(value) if spec.type == "int" else value)
    if rule == "enum":
        return _set_first(path, _unknown_code(str(spec.enum)))
    if rule == "reference":
        return _set_first(path, len(_base_model_sizes()[_ENTITY_SYMBOL[str(spec.reference)]]))
    if rule == "finite":
        return _set_first(path, float("nan"))
    raise KeyError(f"no damage for rule {rule} of dataset {path}")


def _base_model_sizes() -> dict[str, range]:
    model = _base_model()
    return {symbol: range(int(getattr(model, symbol))) for symbol in SIZES}


def _set_control(name: str, value: object) -> Damage:
    return lambda f: f["/control"].attrs.__setitem__(name, value)


def _control_damage(name: str, rule: str) -> Damage:
    spec = _CONTROL[name]
    if rule == "missing":
        return lambda f: f["/control"].attrs.__delitem__(name)
    if rule == "class":
        return _set_control(name, np.float64(2.0) if spec.type == "string" else "two")
    if rule in ("lower", "upper"):
        return _set_control(name, np.float64(_crossed(spec, rule)))
    if rule == "enum":
        return _set_control(name, "metis")
    if rule == "finite":
        return _set_control(name, np.float64(np.inf))
    raise KeyError(f"no damage for rule {rule} of /control attribute {name}")


def _version_damage(rule: str) -> Damage:
    attribute = _schema.VERSION_ATTRIBUTE
    return {"missing": lambda f: f.attrs.__delitem__(attribute),
            "class": lambda f: f.attrs.__setitem__(attribute, np.float64(_schema.DECK_VERSION)),
            "value": lambda f: f.attrs.__setitem__(attribute, np.int32(_schema.DECK_VERSION + 1))}[rule]


def _add_unused_node(f: h5py.File) -> None:
    for spec in DATASETS:
        if spec.shape[0] == "n_nodes" and spec.path in f:
            _rewrite(spec.path, lambda a: np.concatenate([a, a[-1:]], axis=0))(f)


def _repeat_first_node(f: h5py.File) -> None:
    data = f["/elements/connectivity"][()]
    data[0, 1] = data[0, 0]
    f["/elements/connectivity"][...] = data


def _duplicate_an_element(f: h5py.File) -> None:
    data = f["/elements/connectivity"][()]
    data[1] = data[0][::-1]   # the same nodes in another order is the same element
    f["/elements/connectivity"][...] = data


def _fold_an_element(f: h5py.File) -> None:
    """Element 0's third corner moved inside it: concave there."""
    xyz, conn = f["/nodes/coordinates"][()], f["/elements/connectivity"][()]
    a, b, c, d = conn[0]
    xyz[c] = 0.25 * (xyz[a] + xyz[b] + xyz[d] + xyz[a])
    f["/nodes/coordinates"][...] = xyz


def _tangent_equal_to_youngs(f: h5py.File) -> None:
    f["/materials/tangent_modulus"][0] = f["/materials/youngs_modulus"][0]


def _pair_with_itself(f: h5py.File) -> None:
    f["/contact/pairs"][0, 1] = f["/contact/pairs"][0, 0]


def _zero_wall_normal(f: h5py.File) -> None:
    f["/rigid_walls/normal"][0] = 0.0


def _wall_above_the_model(f: h5py.File) -> None:
    f["/rigid_walls/point"][0, 2] = 0.001   # between the strips: the lower one starts behind the wall


def _sphere_without_radius(f: h5py.File) -> None:
    f["/rigid_walls/shape"][0] = 4   # a sphere: the radius stays 0


def _node_row_of_no_wall(f: h5py.File) -> None:
    f["/rigid_wall_nodes/wall"][0] = 1   # the deck has one wall


def _curves_out_of_order(f: h5py.File) -> None:
    f["/curves/first_point"][1] = f["/curves/first_point"][0]


def _curve_time_repeated(f: h5py.File) -> None:
    f["/curves/time"][1] = f["/curves/time"][0]


def _rigid_node_loose(f: h5py.File) -> None:
    f["/nodes/rigid_body"][-1] = -1   # a node of the rigid lid's element outside its body


def _truss_updates_thickness(f: h5py.File) -> None:
    """The wire (part 3, a truss) asks for the thickness update, the one-point quadrilateral's."""
    if "/parts/thickness_update" in f:
        del f["/parts/thickness_update"]
    f["/parts/thickness_update"] = np.array([0, 0, 0, 1], dtype=np.int32)


def _hardening_curve_softens(f: h5py.File) -> None:
    f["/curves/value"][4] = 0.9 * f["/curves/value"][3]   # curve 2: the yield stress falls


# The schema's [relations]: hand-written on both sides, so each needs its own damage here.
RELATION_DAMAGES: dict[str, Damage] = {
    "distinct_element_nodes": _repeat_first_node,
    "distinct_elements": _duplicate_an_element,
    "convex_elements": _fold_an_element,
    "node_in_element": _add_unused_node,
    "tangent_below_youngs": _tangent_equal_to_youngs,
    "contact_parts_differ": _pair_with_itself,
    "rigid_wall_normal_nonzero": _zero_wall_normal,
    "rigid_wall_nodes_in_front": _wall_above_the_model,
    "rigid_wall_geometry": _sphere_without_radius,
    "rigid_wall_nodes_wall": _node_row_of_no_wall,
    "curve_first_points": _curves_out_of_order,
    "curve_times_increase": _curve_time_repeated,
    "rigid_bodies_whole": _rigid_node_loose,
    "material_curves": _hardening_curve_softens,
    "thickness_update_elements": _truss_updates_thickness,
}


def damage_for(what: str, name: str, rule: str) -> tuple[Damage, str]:
    """The damage that breaks one rule, and the name both messages must contain."""
    if what == "version":
        return _version_damage(rule), name
    if what == "dataset":
        return _dataset_damage(name, rule), name
    if what == "control":
        return _control_damage(name, rule), f"/control attribute {name}"
    if what == "relation":
        return RELATION_DAMAGES[rule], RELATIONS[rule].path
    raise KeyError(what)


DECLARED = [(what, name, rule) for (what, name), rules in RULES.items() for rule in rules]


# ----------------------------------------------------------------------------------------------
# tests


@pytest.fixture(scope="module")
def base_deck(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return deck.write_deck(_base_model(), tmp_path_factory.mktemp("base") / "deck.h5")


def _run_engine(deck_path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(launch.engine_path()), str(deck_path), str(deck_path.with_name("results.h5"))],
                          cwd=deck_path.parent, env=launch.engine_environment(1), capture_output=True, text=True,
                          timeout=60)


def test_every_declared_rule_has_a_damage() -> None:
    """The rules exercised below are exactly those the schema declares: every (what, rule) kind
    has a damage, and every relation of schema/deck.toml has one in RELATION_DAMAGES."""
    assert set(RELATION_DAMAGES) == set(RELATIONS)
    exercised = set()
    for what, name, rule in DECLARED:
        damage_for(what, name, rule)
        exercised.add((what, name, rule))
    declared = {(what, name, rule) for (what, name), rules in RULES.items() for rule in rules}
    assert exercised == declared
    assert {rule for what, _, rule in DECLARED if what == "relation"} == set(RELATIONS)


def test_base_deck_is_valid_for_both(base_deck: Path, tmp_path: Path) -> None:
    """The control case: the undamaged deck passes the frontend and runs in the engine."""
    deck.validate_deck(base_deck)
    path = tmp_path / "deck.h5"
    shutil.copyfile(base_deck, path)
    done = _run_engine(path)
    assert done.returncode == _schema.STATUS_OK, done.stderr
    with h5py.File(path, "r") as f:   # every optional dataset and attribute is present
        assert all(spec.path in f for spec in DATASETS)
        assert all(spec.name in f["/control"].attrs for spec in CONTROL)


@pytest.fixture(scope="module")
def engine_verdicts(base_deck: Path, tmp_path_factory: pytest.TempPathFactory
                    ) -> dict[tuple[str, str, str], tuple[Path, subprocess.CompletedProcess[str]]]:
    """Every damaged deck and the engine's answer to it. The engine spends most of its half second
    on a tiny deck waiting for MPI to start, not computing, so the runs go side by side."""
    folder = tmp_path_factory.mktemp("damaged")
    decks = {}
    for k, rule in enumerate(DECLARED):
        path = folder / f"{k:03d}" / "deck.h5"
        path.parent.mkdir()
        shutil.copyfile(base_deck, path)
        with h5py.File(path, "r+") as f:
            damage_for(*rule)[0](f)
        decks[rule] = path
    with ThreadPoolExecutor(max_workers=8) as pool:
        runs = dict(zip(decks, pool.map(_run_engine, decks.values()), strict=True))
    return {rule: (decks[rule], runs[rule]) for rule in decks}


@pytest.mark.parametrize("what, name, rule", [pytest.param(*r, id=f"{r[0]}:{r[1]}:{r[2]}") for r in DECLARED])
def test_both_validators_refuse_the_damage(engine_verdicts: dict[tuple[str, str, str], tuple[
        Path, subprocess.CompletedProcess[str]]], what: str, name: str, rule: str) -> None:
    needle = damage_for(what, name, rule)[1]
    path, done = engine_verdicts[(what, name, rule)]
    with pytest.raises(deck.DeckError) as refused:
        deck.validate_deck(path)
    assert re.search(re.escape(needle) + r"\b", str(refused.value)), str(refused.value)
    assert done.returncode == _schema.STATUS_BAD_INPUT, (done.returncode, done.stdout, done.stderr)
    errors = [line for line in done.stderr.splitlines() if line.startswith("paradyn-engine: error:")]
    assert len(errors) == 1, done.stderr
    assert re.search(re.escape(needle) + r"\b", errors[0]), errors[0]
    assert not path.with_name("results.h5").exists()
