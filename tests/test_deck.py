"""Deck writing, reading and validation against docs/formats.md."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import h5py
import numpy as np
import pytest

from paradyn import deck
from paradyn._schema import DATASETS
from paradyn.mesh import geometry


def _model(plastic: bool = False) -> deck.Model:
    mesh = geometry.plate((0.2, 0.1), (4, 2))
    n = mesh.n_nodes
    fixed = np.zeros((n, 6), dtype=np.int32)
    fixed[[0, 5, 10], :] = 1
    return deck.Model(
        coordinates=mesh.coordinates,
        connectivity=mesh.quads,
        element_part=np.array([0, 0, 0, 0, 1, 1, 1, 1]),
        thickness=np.array([0.002, 0.003]),
        part_material=np.array([0, 1]),
        integration_points=np.array([5, 3]),
        hourglass_coefficient=np.array([0.1, 0.05]),
        material_model=np.array([1, 2 if plastic else 1]),
        density=np.array([7860.0, 2700.0]),
        youngs_modulus=np.array([200e9, 70e9]),
        poisson_ratio=np.array([0.3, 0.33]),
        yield_stress=np.array([0.0, 250e6]) if plastic else None,
        tangent_modulus=np.array([0.0, 1e9]) if plastic else None,
        hardening_mixing=np.array([1.0, 0.5]) if plastic else None,
        initial_velocity=np.tile([0.0, 0.0, 1.0], (n, 1)),
        fixed_dofs=fixed,
        load_node=np.array([4]),
        load_dof=np.array([3]),
        load_value=np.array([-10.0]),
        load_ramp_time=np.array([1e-5]),
        tracked_nodes=np.array([4, 14]),
        control=deck.Control(end_time=1e-3, output_interval=1e-4, history_interval=1e-5, time_step=1e-6),
        title="two strips",
        part_names=["left", "right"],
        material_names=["steel", "aluminium"],
        tracked_names=["corner", "far"],
    )


def test_round_trip(tmp_path: Path) -> None:
    model = _model(plastic=True)
    path = deck.write_deck(model, tmp_path / "deck.h5")
    back = deck.read_deck(path)
    for name in ("coordinates", "connectivity", "element_part", "thickness", "part_material",
                 "integration_points", "hourglass_coefficient", "material_model", "density",
                 "youngs_modulus", "poisson_ratio", "yield_stress", "tangent_modulus", "hardening_mixing",
                 "initial_velocity", "initial_angular_velocity", "fixed_dofs", "load_node", "load_dof",
                 "load_value", "load_ramp_time", "tracked_nodes"):
        np.testing.assert_array_equal(getattr(back, name), getattr(model, name), err_msg=name)
    assert back.control == model.control
    assert (back.title, back.part_names, back.material_names, back.tracked_names) == (
        "two strips", ["left", "right"], ["steel", "aluminium"], ["corner", "far"])
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind
    with h5py.File(path) as f:
        assert f.attrs["paradyn_deck_version"] == 1
        assert f["/elements/connectivity"].dtype.kind == "i"
        assert f["/nodes/coordinates"].dtype == np.float64


def test_optional_datasets_absent_get_defaults(tmp_path: Path) -> None:
    model = _model()
    model.load_node = model.load_dof = np.zeros(0, dtype=np.int32)
    model.load_value = model.load_ramp_time = np.zeros(0)
    model.tracked_nodes, model.tracked_names = np.zeros(0, dtype=np.int32), []
    path = deck.write_deck(model, tmp_path / "deck.h5")
    with h5py.File(path, "a") as f:
        assert "/loads" not in f and "/output/tracked_nodes" not in f
        del f["/parts/integration_points"]
        del f["/nodes/initial_angular_velocity"]
    back = deck.read_deck(path)
    np.testing.assert_array_equal(back.integration_points, [5, 5])
    assert back.initial_angular_velocity.shape == (model.n_nodes, 3)
    assert back.n_loads == 0 and back.n_tracked == 0


def _broken(tmp_path: Path, edit: Callable[[h5py.File], None]) -> Path:
    path = deck.write_deck(_model(plastic=True), tmp_path / "deck.h5")
    with h5py.File(path, "a") as f:
        edit(f)
    return path


def _replace(name: str, value: np.ndarray) -> Callable[[h5py.File], None]:
    def edit(f: h5py.File) -> None:
        del f[name]
        f[name] = value
    return edit


def _set_entry(name: str, index: tuple[int, ...], value: float) -> Callable[[h5py.File], None]:
    def edit(f: h5py.File) -> None:
        data = f[name][()]
        data[index] = value
        f[name][...] = data
    return edit


@pytest.mark.parametrize(
    ("edit", "pattern"),
    [
        (lambda f: f.__delitem__("/parts/thickness"), r"/parts/thickness is missing"),
        (lambda f: f.__delitem__("/materials/yield_stress"), r"/materials/yield_stress is missing"),
        (_replace("/elements/part", np.zeros(5, dtype=np.int32)),
         r"/elements/part has 5 rows but /elements/connectivity, which sets the number of elements"),
        (_replace("/nodes/coordinates", np.zeros((15, 2))), r"/nodes/coordinates has shape"),
        (_replace("/elements/connectivity", np.zeros((8, 4))), r"/elements/connectivity has dtype float64"),
        (_set_entry("/parts/thickness", (1,), -0.003),
         r"/parts/thickness\[1\] = -0.003 must be > 0; set a positive shell thickness"),
        (_set_entry("/nodes/coordinates", (7, 1), np.nan), r"/nodes/coordinates\[7, 1\] = nan must be finite"),
        (_set_entry("/elements/connectivity", (2, 3), 15), r"/elements/connectivity\[2, 3\] = 15 is out of range"),
        (_set_entry("/elements/connectivity", (2, 3), -1), r"/elements/connectivity\[2, 3\] = -1 is out of range"),
        (_set_entry("/elements/connectivity", (0, 1), 0), r"/elements/connectivity\[0\] .* repeats a node"),
        (_set_entry("/elements/part", (0,), 2), r"/elements/part\[0\] = 2 is out of range"),
        (_set_entry("/parts/material", (1,), 5), r"/parts/material\[1\] = 5 is out of range"),
        (_set_entry("/parts/integration_points", (0,), 10), r"/parts/integration_points\[0\] = 10"),
        (_set_entry("/materials/poisson_ratio", (0,), 0.5), r"/materials/poisson_ratio\[0\] = 0.5"),
        (_set_entry("/materials/tangent_modulus", (1,), 80e9), r"/materials/tangent_modulus\[1\]"),
        (_set_entry("/materials/model", (0,), 9), r"/materials/model\[0\] = 9 must be 1 or 2"),
        (_set_entry("/loads/dof", (0,), 7), r"/loads/dof\[0\] = 7 must be between 1 and 6"),
        (_set_entry("/output/tracked_nodes", (1,), 99), r"/output/tracked_nodes\[1\] = 99 is out of range"),
        (lambda f: f["/control"].attrs.__delitem__("end_time"), r"/control attribute end_time is missing"),
        (lambda f: f["/control"].attrs.__setitem__("output_interval", 0.0), r"output_interval = 0 must be > 0"),
        (lambda f: f.attrs.__setitem__("paradyn_deck_version", 2), r"paradyn_deck_version = 2"),
        (lambda f: f.attrs.__delitem__("paradyn_deck_version"), r"paradyn_deck_version is missing"),
    ],
)
def test_validate_deck_rejects(tmp_path: Path, edit: Callable[[h5py.File], None], pattern: str) -> None:
    path = _broken(tmp_path, edit)
    with pytest.raises(deck.DeckError, match=pattern) as info:
        deck.validate_deck(path)
    assert str(info.value).startswith(str(path))


def test_write_deck_validates_and_leaves_nothing(tmp_path: Path) -> None:
    model = _model()
    model.thickness[1] = -0.003
    with pytest.raises(deck.DeckError, match=r"/parts/thickness\[1\] = -0.003 must be > 0"):
        deck.write_deck(model, tmp_path / "deck.h5")
    assert list(tmp_path.iterdir()) == []


def test_validate_model_requires_plasticity_data_for_model_2() -> None:
    model = _model()
    model.material_model = np.array([1, 2])
    with pytest.raises(deck.DeckError, match=r"/materials/yield_stress is missing"):
        deck.validate_model(model)


def test_validate_model_rejects_unused_nodes() -> None:
    model = _model()
    model.coordinates = np.vstack([model.coordinates, [[9.0, 9.0, 9.0]]])
    for spec in DATASETS:   # the per-node defaults follow the new row count
        if spec.shape[0] == "n_nodes" and not spec.required:
            setattr(model, spec.python, None)
    with pytest.raises(deck.DeckError, match=r"/nodes/coordinates\[15\] belongs to no element"):
        deck.validate_model(model)


@pytest.mark.parametrize("partition", [None, "blocks", "rcb"])
def test_partition_round_trip(tmp_path: Path, partition: str | None) -> None:
    """docs/formats.md /control partition: written as a string attribute when set, left out
    (engine default) when None, and read back as written."""
    model = _model()
    model.control.partition = partition
    path = deck.write_deck(model, tmp_path / "deck.h5")
    with h5py.File(path, "r") as f:
        assert f["/control"].attrs.get("partition") == partition
    assert deck.read_deck(path).control.partition == partition


def test_unknown_partition_is_rejected(tmp_path: Path) -> None:
    """docs/formats.md: partition is "blocks" or "rcb"; anything else is refused before writing,
    and on reading, with the allowed values in the message."""
    model = _model()
    model.control.partition = "metis"
    with pytest.raises(deck.DeckError, match=r"partition = 'metis' is unknown; use 'blocks' or 'rcb'"):
        deck.write_deck(model, tmp_path / "deck.h5")
    assert list(tmp_path.iterdir()) == []
    path = _broken(tmp_path, lambda f: f["/control"].attrs.__setitem__("partition", 3))
    with pytest.raises(deck.DeckError, match=r"/control attribute partition = 3 must be one string"):
        deck.read_deck(path)


def test_real_dataset_stored_as_integer_is_rejected(tmp_path: Path) -> None:
    path = _broken(tmp_path, _replace("/materials/density", np.array([7860, 2700], dtype=np.int64)))
    with pytest.raises(deck.DeckError, match=r"/materials/density has dtype int64, must be floating point"):
        deck.validate_deck(path)


def test_model_accepts_integer_lists_for_real_fields() -> None:
    model = _model()
    model.density = [7860, 2700]
    deck.validate_model(model)
    assert model.density.dtype == np.float64
