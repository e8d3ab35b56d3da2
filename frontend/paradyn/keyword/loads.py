"""Loads and motions of a keyword deck on ParaDyn's effects (docs/keyword.md, "Loads and motions").

``*LOAD_NODE_POINT`` / ``_SET`` become point loads (a curve written exactly as a sum of ramps,
keyword/curves.py), ``*BOUNDARY_PRESCRIBED_MOTION_NODE`` / ``_SET`` prescribed velocities (a
displacement or acceleration turned into a velocity curve), ``*LOAD_BODY_X/Y/Z`` base
accelerations, and ``*INITIAL_VELOCITY`` (node set, exempted set, ``*DEFINE_BOX``) the nodes'
initial velocities. :func:`apply_loads` writes them into the model, with every curve they use.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from paradyn import deck
from paradyn.scene.building import set_curves

from .cards import KeywordData, Record, _Reading
from .curves import curve_points, cut_at, ramps_of, velocity_of_acceleration, velocity_of_displacement
from .mesh import KeywordMesh
from .reader import Field, KeywordError, layout
from .units import Units

LOAD_NODE = layout("int:ID int:DOF int:LCID SF int:CID int:M1 int:M2 int:M3", dof=0, lcid=0, sf=1.0, cid=0, m1=0,
                   m2=0, m3=0)
MOTION = layout("int:ID int:DOF int:VAD int:LCID SF int:VID DEATH BIRTH", dof=0, vad=0, lcid=0, sf=1.0, vid=0,
                death=1e28, birth=0.0)
MOTION_ID = (Field("MID", "int", 0), Field("HEADING", "text", "", 70))
VELOCITY = (layout("int:NSID int:NSIDEX int:BOXID int:IRIGID int:ICID", nsid=0, nsidex=0, boxid=0, irigid=0, icid=0),
            layout("VX VY VZ VXR VYR VZR", vx=0.0, vy=0.0, vz=0.0, vxr=0.0, vyr=0.0, vzr=0.0),
            layout("VXE VYE VZE VXRE VYRE VZRE", vxe=0.0, vye=0.0, vze=0.0, vxre=0.0, vyre=0.0, vzre=0.0))
BOX = layout("int:BOXID XMN XMX YMN YMX ZMN ZMX", xmn=0.0, xmx=0.0, ymn=0.0, ymx=0.0, zmn=0.0, zmx=0.0)
# LS-DYNA's DOF of a nodal load or motion -> ParaDyn's dof (1..3 translations, 4..6 rotations)
ENGINE_DOF = {1: 1, 2: 2, 3: 3, 5: 4, 6: 5, 7: 6}


def _load_node(target: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        for line in r.lines():
            r.data.point_loads.append((target, r.card(line, LOAD_NODE)))
    return read


def _motion(target: str) -> Callable[[_Reading], None]:
    def read(r: _Reading) -> None:
        if not r.keyword.endswith("_ID"):
            for line in r.lines():
                r.data.motions.append((target, r.card(line, MOTION)))
            return
        for head, line in r.groups(2):
            record = r.card(line, MOTION)
            record.values.update(r.card(head, MOTION_ID).values)
            r.data.motions.append((target, record))
    return read


def _initial_velocity(r: _Reading) -> None:
    lines = r.lines(skip_blank=False)
    while lines:
        first = r.card(lines[0], VELOCITY[0])
        size = 3 if int(first["NSIDEX"]) else 2
        group = lines[:size] + [lines[-1]] * max(0, size - len(lines))
        records = [first] + [r.card(line, card) for line, card in zip(group[1:], VELOCITY[1:size], strict=True)]
        if int(first["IRIGID"]):
            r.data.warn(f"{first.where}: *INITIAL_VELOCITY IRIGID = {first['IRIGID']} is ignored: ParaDyn has no "
                        f"rigid bodies, the velocities go to the nodes as given")
        r.data.set_velocities.append(records)
        lines = lines[size:]


def _define_box(r: _Reading) -> None:
    for line in r.head_and_rest("TITLE" in r.keyword.split("_")):
        if line.text.strip():
            record = r.card(line, BOX)
            r.data.boxes[int(record["BOXID"])] = record


READERS: dict[str, Callable[[_Reading], None]] = {
    "LOAD_NODE_POINT": _load_node("NODE"), "LOAD_NODE_SET": _load_node("SET"),
    "BOUNDARY_PRESCRIBED_MOTION_NODE": _motion("NODE"), "BOUNDARY_PRESCRIBED_MOTION_SET": _motion("SET"),
    "BOUNDARY_PRESCRIBED_MOTION_NODE_ID": _motion("NODE"), "BOUNDARY_PRESCRIBED_MOTION_SET_ID": _motion("SET"),
    "BOUNDARY_PRESCRIBED_MOTION_RIGID": _motion("RIGID"), "BOUNDARY_PRESCRIBED_MOTION_RIGID_ID": _motion("RIGID"),
    "INITIAL_VELOCITY": _initial_velocity,
    "DEFINE_BOX": _define_box, "DEFINE_BOX_TITLE": _define_box,
}


# ----------------------------------------------------------------------------------------------
# the mapping


class CurveTable:
    """The model's curves, added in order; :meth:`write` sets /curves."""

    def __init__(self) -> None:
        self.times: list[list[float]] = []
        self.values: list[list[float]] = []

    def add(self, times: np.ndarray, values: np.ndarray) -> int:
        self.times.append([float(t) for t in times])
        self.values.append([float(v) for v in values])
        return len(self.times) - 1

    def write(self, model: deck.Model) -> None:
        if self.times:
            set_curves(model, self.times, self.values)


def apply_loads(data: KeywordData, mesh: KeywordMesh, unit: Units, model: deck.Model, end_time: float) -> None:
    """Point loads, prescribed velocities and base accelerations, with their curves (``end_time`` in s)."""
    table = CurveTable()
    _point_loads(data, mesh, unit, model, end_time)
    _motions(data, mesh, unit, model, end_time, table)
    _body_loads(data, unit, model, end_time, table)
    table.write(model)


def node_rows(data: KeywordData, mesh: KeywordMesh, target: str, ident: int, where: str, what: str) -> list[int]:
    """Rows of a node (``target`` NODE) or of a node set's nodes (SET); a node no shell uses is an error."""
    if target == "SET" and ident not in data.node_sets:
        raise KeywordError(f"{where}: {what} names node set {ident}, which no *SET_NODE defines")
    nids = [ident] if target == "NODE" else data.node_sets[ident]
    missing = [n for n in nids if n not in mesh.node_index]
    if missing:
        raise KeywordError(f"{where}: {what} names node {missing[0]}, which no shell element uses (or no *NODE "
                           f"defines); ParaDyn's nodes belong to shells")
    return [mesh.node_index[n] for n in nids]


def _dof(record: Record, what: str, refused: dict[int, str]) -> int:
    dof = int(record["DOF"])
    if dof in refused:
        raise KeywordError(f"{record.where}: {what} DOF = {dof} ({refused[dof]}) is not read; {_DOF_FIX}")
    if dof not in ENGINE_DOF:
        raise KeywordError(f"{record.where}: {what} DOF = {dof} is not read; {_DOF_FIX}")
    return ENGINE_DOF[dof]


_DOF_FIX = "give DOF 1, 2, 3 (x, y, z) or 5, 6, 7 (about x, y, z) in global axes"


def _point_loads(data: KeywordData, mesh: KeywordMesh, unit: Units, model: deck.Model, end_time: float) -> None:
    """*LOAD_NODE_POINT / _SET: SF x the curve LCID on DOF 1-3 (force) or 5-7 (moment), as ramps."""
    force = unit.mass * unit.length / unit.time**2
    nodes, dofs, values, ramps = [], [], [], []
    for target, record in data.point_loads:
        what = f"*LOAD_NODE_{'POINT' if target == 'NODE' else 'SET'}"
        dof = _dof(record, what, {4: "a follower force", 8: "a follower moment"})
        if int(record["CID"]):
            raise KeywordError(f"{record.where}: {what} CID = {record['CID']}: local coordinate systems are not "
                               f"read; give the load in global axes (CID 0)")
        scale = float(record["SF"]) * force * (unit.length if dof > 3 else 1.0)
        times, curve = curve_points(data, int(record["LCID"]), unit, end_time, f"{record.where}: {what}")
        for row in node_rows(data, mesh, target, int(record["ID"]), record.where, what):
            for ramp, value in ramps_of(times, curve):
                nodes.append(row)
                dofs.append(dof)
                values.append(scale * value)
                ramps.append(ramp)
    if nodes:
        model.load_node = np.array(nodes, dtype=np.int32)
        model.load_dof = np.array(dofs, dtype=np.int32)
        model.load_value = np.array(values, dtype=np.float64)
        model.load_ramp_time = np.array(ramps, dtype=np.float64)


def _motions(data: KeywordData, mesh: KeywordMesh, unit: Units, model: deck.Model, end_time: float,
             table: CurveTable) -> None:
    """*BOUNDARY_PRESCRIBED_MOTION_NODE / _SET as prescribed velocities: SF x a velocity curve."""
    seen: dict[tuple[int, int], str] = {}
    nodes, dofs, values, curves, births, deaths = [], [], [], [], [], []
    rigid_curves: dict[tuple[int, int, float], int] = {}
    for target, record in data.motions:
        what = f"*BOUNDARY_PRESCRIBED_MOTION_{target}"
        if target == "RIGID":   # a body's motion: its rows once the bodies are known (keyword/rigid.py)
            dof = _dof(record, what, {4: "along the vector VID", 8: "about the vector VID"})
            key = (int(record["LCID"]), int(record["VAD"]), float(record["DEATH"]))   # one curve per such key
            if key not in rigid_curves:
                rigid_curves[key] = table.add(*_motion_curve(data, record, unit, end_time, what))
            scale = float(record["SF"]) * (unit.velocity if dof <= 3 else 1.0 / unit.time)
            data.rigid_motions.append((int(record["ID"]), dof, scale, rigid_curves[key], record.where))
            continue
        dof = _dof(record, what, {4: "along the vector VID", -4: "along the vector VID", 8: "about the vector VID",
                                  -8: "about the vector VID"})
        times, velocity = _motion_curve(data, record, unit, end_time, what, release=True)
        curve = table.add(times, velocity)
        birth, death = _life(record, unit)
        scale = float(record["SF"]) * (unit.velocity if dof <= 3 else 1.0 / unit.time)
        for row in node_rows(data, mesh, target, int(record["ID"]), record.where, what):
            if (row, dof) in seen:
                raise KeywordError(f"{record.where}: {what} prescribes node {int(mesh.node_ids[row])} DOF "
                                   f"{record['DOF']} again (first at {seen[(row, dof)]}); prescribe each dof once")
            seen[(row, dof)] = record.where
            nodes.append(row)
            dofs.append(dof)
            values.append(scale)
            curves.append(curve)
            births.append(birth)
            deaths.append(death)
    if nodes:
        model.prescribed_node = np.array(nodes, dtype=np.int32)
        model.prescribed_dof = np.array(dofs, dtype=np.int32)
        model.prescribed_value = np.array(values, dtype=np.float64)
        model.prescribed_curve = np.array(curves, dtype=np.int32)
        model.prescribed_birth_time = np.array(births, dtype=np.float64)
        model.prescribed_death_time = np.array(deaths, dtype=np.float64)


def _life(record: Record, unit: Units) -> tuple[float, float]:
    """A node motion's BIRTH and DEATH in s (DEATH at or past LS-DYNA's 1e28: never, 1e20)."""
    birth, death = float(record["BIRTH"]), float(record["DEATH"])
    return birth * unit.time, death * unit.time if death < 1e20 else 1e20


def _motion_curve(data: KeywordData, record: Record, unit: Units, end_time: float,
                  what: str, release: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The velocity curve of a motion (s, deck velocity units per SF): VAD 0 the curve, VAD 2 its
    slope (a displacement), VAD 1 its integral from 0 (an acceleration); a rigid body's (release
    False) cut at DEATH and held, a node's (release: the engine frees the dof between BIRTH and
    DEATH) whole."""
    vad, lcid = int(record["VAD"]), int(record["LCID"])
    times, values = curve_points(data, lcid, unit, end_time, f"{record.where}: {what}")
    if vad == 2:
        times, values = velocity_of_displacement(times, values)
        values = values * unit.time        # deck length per second -> per deck time (SF x unit.velocity: SI)
    elif vad == 1:
        times, values = velocity_of_acceleration(times, values)
        values = values / unit.time        # deck acceleration x seconds -> deck velocity
    elif vad != 0:
        raise KeywordError(f"{record.where}: {what} VAD = {vad} is not read; use 0 (velocity), 1 (acceleration) "
                           f"or 2 (displacement)")
    _warn_times(data, record, what, unit, end_time, release)
    death = float(record["DEATH"]) * unit.time
    return cut_at(times, values, death) if death < end_time and not release else (times, values)


def _warn_times(data: KeywordData, record: Record, what: str, unit: Units, end_time: float, release: bool) -> None:
    """A node's BIRTH and DEATH are the engine's (prescribed birth_time, death_time); a rigid body's
    motion has none: it is prescribed from 0, and held at its DEATH value after DEATH."""
    birth, death = float(record["BIRTH"]) * unit.time, float(record["DEATH"]) * unit.time
    if birth > 0.0 and not release:
        data.warn(f"{record.where}: {what} BIRTH = {record['BIRTH']:g} is not supported for a rigid body: ParaDyn "
                  f"prescribes its motion from time 0 (the curve's values before BIRTH apply)")
    if death < end_time and not release:
        data.warn(f"{record.where}: {what} DEATH = {record['DEATH']:g}: ParaDyn cannot release a rigid body's "
                  f"prescribed dof; the velocity curve ends at DEATH and its value there is held to the end of the run")
    if int(record["VID"]):
        data.warn(f"{record.where}: {what} VID = {record['VID']} is ignored (DOF {record['DOF']} is along an axis)")


def _body_loads(data: KeywordData, unit: Units, model: deck.Model, end_time: float, table: CurveTable) -> None:
    """*LOAD_BODY_X/Y/Z as base accelerations: SF times the curve LCID, an acceleration of the base,
    so the model is pushed the other way (a curve of 9.81 in *LOAD_BODY_Z is gravity along -z)."""
    if not data.body_loads:
        return
    curve_of: dict[int, int] = {}
    for axis, record in data.body_loads:
        lcid = int(record["LCID"] or 0)
        if lcid not in curve_of:
            times, values = curve_points(data, lcid, unit, end_time, f"{record.where}: *LOAD_BODY_{axis}")
            curve_of[lcid] = table.add(times, values)
    acceleration = unit.length / unit.time**2
    model.base_acceleration_direction = np.array([-np.eye(3)["XYZ".index(axis)] for axis, _ in data.body_loads])
    model.base_acceleration_value = np.array([float(r["SF"]) * acceleration for _, r in data.body_loads])
    model.base_acceleration_curve = np.array([curve_of[int(r["LCID"] or 0)] for _, r in data.body_loads],
                                             dtype=np.int32)


def set_velocities(data: KeywordData, mesh: KeywordMesh, unit: Units) -> tuple[np.ndarray, np.ndarray]:
    """Velocities and angular velocities (SI) of *INITIAL_VELOCITY: the nodes of NSID (0: every
    node), within the box BOXID if given, take VX..VZR; the nodes of NSIDEX take VXE..VZRE instead."""
    n = len(mesh.coordinates)
    velocity, angular = np.zeros((n, 3)), np.zeros((n, 3))
    for records in data.set_velocities:
        first = records[0]
        if int(first["ICID"]):
            raise KeywordError(f"{first.where}: *INITIAL_VELOCITY ICID = {first['ICID']}: local coordinate systems "
                               f"are not read; give the velocities in global axes (ICID 0)")
        rows = _set_rows(data, mesh, int(first["NSID"]), first.where)
        if int(first["BOXID"]):
            rows = rows[_in_box(data, mesh, unit, int(first["BOXID"]), first.where, rows)]
        exempt = _set_rows(data, mesh, int(first["NSIDEX"]), first.where) if int(first["NSIDEX"]) else rows[:0]
        taken = np.setdiff1d(rows, exempt)
        velocity[taken] = [float(records[1][k]) * unit.velocity for k in ("VX", "VY", "VZ")]
        angular[taken] = [float(records[1][k]) / unit.time for k in ("VXR", "VYR", "VZR")]
        if exempt.size:
            velocity[exempt] = [float(records[2][k]) * unit.velocity for k in ("VXE", "VYE", "VZE")]
            angular[exempt] = [float(records[2][k]) / unit.time for k in ("VXRE", "VYRE", "VZRE")]
    return velocity, angular


def _set_rows(data: KeywordData, mesh: KeywordMesh, nsid: int, where: str) -> np.ndarray:
    """Rows of the node set's nodes that shells use (every node for 0)."""
    if nsid == 0:
        return np.arange(len(mesh.coordinates))
    if nsid not in data.node_sets:
        raise KeywordError(f"{where}: *INITIAL_VELOCITY names node set {nsid}, which no *SET_NODE defines")
    return np.array(sorted({mesh.node_index[n] for n in data.node_sets[nsid] if n in mesh.node_index}), dtype=np.int64)


def _in_box(data: KeywordData, mesh: KeywordMesh, unit: Units, boxid: int, where: str, rows: np.ndarray) -> np.ndarray:
    """Which of ``rows`` lie in the *DEFINE_BOX (bounds included)."""
    if boxid not in data.boxes:
        raise KeywordError(f"{where}: BOXID = {boxid} names no *DEFINE_BOX; define the box")
    box = data.boxes[boxid]
    low = np.array([float(box[k]) for k in ("XMN", "YMN", "ZMN")]) * unit.length
    high = np.array([float(box[k]) for k in ("XMX", "YMX", "ZMX")]) * unit.length
    x = mesh.coordinates[rows]
    return np.all((x >= low) & (x <= high), axis=1)
