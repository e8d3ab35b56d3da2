"""Scenes built in Python: :class:`Scene`, the tables of a scene file (docs/scene.md) made by calls.

Every ``add_*`` call checks its entry at once with the reader of :func:`paradyn.scene.load_scene`
(the same keys, types, ranges and messages, which name the table and the key); :meth:`Scene.validate`
checks the whole scene (unique names, defined parts, materials and curves) and returns the
:class:`paradyn.scene.Scene` that :func:`paradyn.scene.build_model` meshes. :meth:`Scene.to_toml`
writes the scene file that ``load_scene`` reads back to the same scene, and :func:`paradyn.run`
runs a Scene as it runs a file. The TOML text is written by :mod:`paradyn.scene.toml_writing`.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from paradyn.arguments import ArgumentError, checked_arguments, did_you_mean

from . import contact_reading, reading, specs
from .building import build_model
from .reading import _parse_toml, scene_from_tables
from .row_tables import ROW_TABLES, parse_row
from .tables import _Reader
from .toml_writing import scene_toml
from .welds import parse_weld

if TYPE_CHECKING:
    from paradyn import deck


class SceneArgumentError(specs.SceneError, ArgumentError):
    """A call of :class:`Scene` or a geometry with an unknown, misspelt or missing argument (both a
    :class:`~paradyn.scene.SceneError` and a ``TypeError``); the message names the closest argument."""


def _checked(name: str) -> Any:
    return checked_arguments(name, SceneArgumentError)


class Geometry:
    """A part's geometry, the table ``[part.geometry]`` of docs/scene.md; use a subclass."""

    kind = ""

    def __init__(self, **keys: Any) -> None:
        self.table: dict[str, Any] = {"kind": self.kind, **{k: _plain(v) for k, v in keys.items()}}

    def __repr__(self) -> str:
        keys = ", ".join(f"{k}={v!r}" for k, v in self.table.items() if k != "kind")
        return f"{type(self).__name__}({keys})"


class Cylinder(Geometry):
    """The open lateral surface of a circular cylinder, ``radius`` and ``length`` in m.

    ``options``: ``axis``, ``center``, ``elements_around`` (a multiple of 4), ``elements_along``
    (docs/scene.md, ``kind = "cylinder"``).
    """

    kind = "cylinder"

    @_checked("paradyn.Cylinder")
    def __init__(self, radius: float, length: float, **options: Any) -> None:
        super().__init__(radius=radius, length=length, **options)


class Plate(Geometry):
    """A flat rectangle of ``size`` = (lx, ly) m with ``elements`` = (nx, ny) quadrilaterals.

    ``options``: ``origin``, ``u_axis``, ``v_axis`` (docs/scene.md, ``kind = "plate"``).
    """

    kind = "plate"

    @_checked("paradyn.Plate")
    def __init__(self, size: tuple[float, float], elements: tuple[int, int], **options: Any) -> None:
        super().__init__(size=size, elements=elements, **options)


class MeshFile(Geometry):
    """A quadrilateral mesh file that meshio reads (``.msh``, ``.vtu``, ``.inp``, ...), coordinates in m;
    ``group`` takes one physical group or cell set of it (docs/scene.md, ``kind = "file"``)."""

    kind = "file"

    @_checked("paradyn.MeshFile")
    def __init__(self, path: str | Path, group: str | None = None) -> None:
        super().__init__(path=str(Path(path).resolve()), **({} if group is None else {"group": group}))


class Scene:
    """A scene built in Python; the same scene a TOML file describes (docs/scene.md).

    Parameters
    ----------
    title : str
        The run's title (pictures, ``summary.json``).
    end_time, output_interval : float
        Simulated time (s) and the interval between field frames (s), the required keys of ``[run]``.
    effects : mapping of str to bool, optional
        The ``[effects]`` switches, e.g. ``{"friction": False}``.
    **run : Any
        The other keys of ``[run]`` (``history_interval``, ``gravity``, ``mass_damping``, ...).

    Raises
    ------
    paradyn.scene.SceneError
        A key that ``[run]`` does not have, a wrong type or a value out of range; the message
        names the key. Every ``add_*`` raises it the same way for its own entry.

    Examples
    --------
    >>> import paradyn
    >>> scene = paradyn.Scene("plate", end_time=2e-4, output_interval=5e-5)
    >>> scene.add_material("steel", model="elastic", density=7800.0, youngs_modulus=2.0e11,
    ...                    poisson_ratio=0.3)
    >>> scene.add_part("plate", material="steel", thickness=0.002,
    ...                geometry=paradyn.Plate(size=(0.1, 0.1), elements=(4, 4)))
    >>> scene.add_fix("plate", box=[[0.0, 0.0, 0.0], [0.0, 0.1, 0.0]])
    >>> scene.add_load("plate", point=[0.1, 0.1, 0.0], dof="uz", value=-50.0, ramp_time=5e-5)
    >>> scene.add_track("corner", part="plate", point=[0.1, 0.1, 0.0])
    >>> scene
    Scene('plate', materials=['steel'], parts=['plate'], fix=1, load=1, track=1)
    >>> scene.add_part("bad", material="steel", thickness=-1.0, geometry=paradyn.Plate((1, 1), (2, 2)))
    Traceback (most recent call last):
    ...
    paradyn.scene.specs.SceneError: paradyn.Scene 'plate': 'thickness' in [[part]] #2 'bad' must be > 0, got -1.0
    """

    @_checked("paradyn.Scene")
    def __init__(self, title: str = "scene", *, end_time: float, output_interval: float,
                 effects: Mapping[str, bool] | None = None, **run: Any) -> None:
        self._tables: dict[str, Any] = {"title": title}
        self._set("run", {"end_time": end_time, "output_interval": output_interval, **run})
        if effects:
            self._set("effects", dict(effects))

    @property
    def title(self) -> str:
        return str(self._tables["title"])

    @property
    def origin(self) -> Path:
        """What messages name: ``paradyn.Scene '<title>'`` (a relative mesh path is relative to the
        working folder; :class:`MeshFile` makes it absolute)."""
        return Path(f"paradyn.Scene '{self.title}'")

    def __repr__(self) -> str:
        names = {k: [e["name"] for e in self._tables.get(k, [])] for k in ("material", "part")}
        counts = [f"{k}={len(v)}" for k, v in self._tables.items() if isinstance(v, list) and k not in names]
        return ", ".join([f"Scene({self.title!r}", f"materials={names['material']}", f"parts={names['part']}",
                          *counts]) + ")"

    # ---- entries ------------------------------------------------------------------------------
    @_checked("paradyn.Scene.add_material")
    def add_material(self, name: str, *, model: str, density: float, youngs_modulus: float,
                     poisson_ratio: float, **options: Any) -> None:
        """A ``[[material]]``: ``model`` ``"elastic"`` or ``"j2_plasticity"`` (then ``yield_stress``,
        and optionally ``tangent_modulus``, ``hardening_mixing``); SI units."""
        self._add("material", name=name, model=model, density=density, youngs_modulus=youngs_modulus,
                  poisson_ratio=poisson_ratio, **options)

    @_checked("paradyn.Scene.add_part")
    def add_part(self, name: str, *, material: str, thickness: float, geometry: Geometry | Mapping[str, Any],
                 **options: Any) -> None:
        """A ``[[part]]`` of shells on ``geometry`` (:class:`Cylinder`, :class:`Plate`, :class:`MeshFile`).

        ``options``: ``integration_points``, ``hourglass_form``, ``hourglass_coefficient``,
        ``warping_correction``, ``element``, ``rotary_inertia``, ``initial_velocity`` (docs/scene.md,
        ``[[part]]``).
        """
        table = geometry.table if isinstance(geometry, Geometry) else dict(geometry)
        self._add("part", name=name, material=material, thickness=thickness, **options, geometry=table)

    @_checked("paradyn.Scene.add_fix")
    def add_fix(self, part: str, box: Any, **options: Any) -> None:
        """A ``[[fix]]``: the ``dofs`` (default all six) of ``part``'s nodes inside ``box`` =
        [[xmin, ymin, zmin], [xmax, ymax, zmax]] (m) are held."""
        self._add("fix", part=part, box=box, **options)

    @_checked("paradyn.Scene.add_load")
    def add_load(self, part: str, *, point: Any, dof: str, value: float, **options: Any) -> None:
        """A ``[[load]]``: a force (N) or moment (N m) on ``dof`` of the node nearest ``point``;
        ``ramp_time`` (s) ramps it up from 0."""
        self._add("load", part=part, point=point, dof=dof, value=value, **options)

    @_checked("paradyn.Scene.add_track")
    def add_track(self, name: str, *, part: str, point: Any) -> None:
        """A ``[[track]]``: the node of ``part`` nearest ``point`` goes into the history as ``name``."""
        self._add("track", name=name, part=part, point=point)

    @_checked("paradyn.Scene.add_contact")
    def add_contact(self, *parts: str, **options: Any) -> None:
        """A ``[[contact]]``: two parts (``kind="node_to_segment"``, the default), or with
        ``kind="single_surface"`` the parts that form one surface (none: every part). ``options``:
        ``kind``, ``penalty_scale``, ``thickness_scale``, ``static_friction``, ``dynamic_friction``,
        ``friction_decay``, ``symmetric``, ``initial_penetration``, ``birth_time``, ``death_time``, and for
        ``kind="tiebreak"`` ``normal_failure_stress``, ``shear_failure_stress`` (docs/scene.md, ``[[contact]]``)."""
        self._add("contact", **({"parts": list(parts)} if parts else {}), **options)

    @_checked("paradyn.Scene.add_weld")
    def add_weld(self, *parts: str, point: Any, **options: Any) -> None:
        """A ``[[weld]]``: the nodes of the two ``parts`` nearest ``point`` move as one small rigid
        body (a spot weld); ``options``: ``strength`` (SN, SS in N: it lets go when
        (max(fn, 0)/SN)^N + (|fs|/SS)^M >= 1, fn along the first part's node to the second's),
        ``exponent`` (N, M), ``failure_time`` (docs/scene.md, ``[[weld]]``)."""
        self._add("weld", parts=list(parts), point=point, **options)

    @_checked("paradyn.Scene.add_rigid_wall")
    def add_rigid_wall(self, *, point: Any, normal: Any, **options: Any) -> None:
        """A ``[[rigid_wall]]``: by default the plane through ``point`` facing ``normal`` (a cylinder's
        axis; any direction for a sphere); ``shape``
        (``"plane"``, ``"finite_plane"``, ``"cylinder"``, ``"sphere"``, ``"box"``) with its ``edge``,
        ``size``, ``radius``, ``length``; ``velocity``, ``penalty_scale``, ``friction`` (docs/scene.md)."""
        self.add("rigid_wall", point=point, normal=normal, **options)

    @_checked("paradyn.Scene.add")
    def add(self, table: str, /, **keys: Any) -> None:
        """An entry of the scene's row table ``[[table]]`` (one deck row per entry; its keys are
        the datasets of schema/deck.toml whose ``scene`` names the table), checked at once."""
        if table not in ROW_TABLES:
            raise specs.SceneError(f"{self.origin}: no row table [[{table}]]; {did_you_mean(table, ROW_TABLES)}the "
                                   f"row tables are: {', '.join(ROW_TABLES) or 'none'} (the other tables have "
                                   f"their own add_* method)")
        self._add(table, **keys)

    @_checked("paradyn.Scene.add_curve")
    def add_curve(self, name: str, *, time: Any, value: Any) -> None:
        """A ``[[curve]]``: a factor, linear between the points (``time`` in s, increasing)."""
        self._add("curve", name=name, time=time, value=value)

    @_checked("paradyn.Scene.add_pressure")
    def add_pressure(self, part: str, *, value: float, **options: Any) -> None:
        """A ``[[pressure]]`` of ``value`` (Pa) on every element of ``part``, times ``curve`` if named."""
        self._add("pressure", part=part, value=value, **options)

    @_checked("paradyn.Scene.add_prescribe")
    def add_prescribe(self, part: str, *, box: Any, dof: str, value: float, **options: Any) -> None:
        """A ``[[prescribe]]``d velocity (m/s, rad/s) of ``dof`` of ``part``'s nodes in ``box``,
        times ``curve`` if named; ``birth_time`` and ``death_time`` (s): the dof is free before and
        after them (LS-DYNA BIRTH, DEATH)."""
        self._add("prescribe", part=part, box=box, dof=dof, value=value, **options)

    # ---- the whole scene ----------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The scene's tables, as ``tomllib`` reads them from the file :meth:`to_toml` writes."""
        return copy.deepcopy(self._tables)

    def validate(self) -> specs.Scene:
        """Check the whole scene as :func:`paradyn.scene.load_scene` checks a file; return its specs."""
        return scene_from_tables(self._tables, self.origin)

    def build(self) -> deck.Model:
        """Mesh the parts and assemble the deck model (:func:`paradyn.scene.build_model`)."""
        return build_model(self.validate())

    def to_toml(self, path: str | Path) -> Path:
        """Check the scene, then write it as a scene file (docs/scene.md) at ``path``; return the path."""
        from paradyn.atomic_write import write_text_atomic

        self.validate()
        return write_text_atomic(Path(path), scene_toml(self._tables))

    @classmethod
    def from_toml(cls, path: str | Path) -> Scene:
        """A Scene with the tables of a scene file, checked (mesh file paths made absolute)."""
        path = Path(path)
        tables = _parse_toml(path)
        scene_from_tables(tables, path)
        scene = cls.__new__(cls)
        scene._tables = tables
        for part in tables.get("part", []):
            if part["geometry"]["kind"] == "file":
                part["geometry"]["path"] = str((path.parent / part["geometry"]["path"]).resolve())
        return scene

    # ---- checking one entry -------------------------------------------------------------------
    def _set(self, kind: str, table: dict[str, Any]) -> None:
        table = {k: _plain(v) for k, v in table.items()}
        check_entry(kind, table, 0, self.origin)
        self._tables[kind] = table

    def _add(self, array: str, /, **keys: Any) -> None:
        """Check the next ``[[array]]`` entry alone, then keep it (a refused entry is not kept)."""
        entries = self._tables.get(array, [])
        table = {k: _plain(v) for k, v in keys.items()}
        check_entry(array, table, len(entries), self.origin)
        self._tables[array] = [*entries, table]


# the scene file reader's parser of each table: one entry is checked as load_scene checks it
_PARSERS = {"run": reading._parse_run, "effects": reading._parse_effects, "material": reading._parse_material,
            "part": reading._parse_part, "fix": reading._parse_fix, "load": reading._parse_load,
            "track": reading._parse_track, "contact": contact_reading.parse_contact, "curve": reading._parse_curve,
            "pressure": reading._parse_pressure, "prescribe": reading._parse_prescribe, "weld": parse_weld}


def check_entry(kind: str, table: Mapping[str, Any], index: int, path: Path) -> None:
    """Check one entry alone (keys, types, ranges), as :func:`paradyn.scene.load_scene` does: ``kind``
    is ``"run"``, ``"effects"`` or an array of tables (``"part"``, ...) with the entry's 0-based ``index``;
    messages start with ``path``. References to other entries are checked by :meth:`Scene.validate`."""
    reader = _Reader(path)
    if kind in ROW_TABLES:
        parse_row(reader, dict(table), kind, index)
        return
    parser = _PARSERS[kind]
    if kind in ("run", "effects"):
        parser(reader, dict(table))
    else:
        parser(reader, dict(table), index)


def _plain(value: Any) -> Any:
    """A value as TOML holds it: numpy scalars and arrays, tuples and paths become int, float,
    str and lists (so that the reader's checks and the TOML text see what a file would hold)."""
    if isinstance(value, np.ndarray | tuple | list):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, Mapping):
        return {k: _plain(v) for k, v in value.items()}
    return value
