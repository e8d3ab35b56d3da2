"""Parts of a keyword deck (docs/keyword.md, "Parts, thicknesses and shell formulations").

``*ELEMENT_SHELL_THICKNESS`` gives each shell its own corner thicknesses; ParaDyn's engine has one
thickness per part, so :func:`split_by_thickness` makes a deck part whose shells have several
thicknesses into one engine part per distinct thickness (each element's thickness the mean of its
corners), keeping the deck's PID on every one of them (``/parts/id``, the outputs'
``file_part_id``) and naming them ``<part>_t<thickness>``. :func:`part_spec` builds a part's
:class:`PartSpec`: its thickness, ``*SECTION_SHELL``'s ELFORM and NIP, and the hourglass control.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from paradyn import _schema
from paradyn.scene.specs import PartSpec

from . import cards
from .cards import KeywordData, Record, _Reading
from .mesh import KeywordMesh
from .reader import Field, KeywordError
from .units import Units

MAX_INTEGRATION_POINTS = int(next(d.upper.value for d in _schema.DATASETS if d.python == "integration_points"))
THICKNESS_CARD = tuple(Field(name, "float", 0.0, 16) for name in ("THIC1", "THIC2", "THIC3", "THIC4", "BETA"))
CORNERS = ("THIC1", "THIC2", "THIC3", "THIC4")
# LS-DYNA's IHQ for shells -> ParaDyn's hourglass form
HOURGLASS_OF_IHQ = {0: "viscous", 1: "viscous", 2: "viscous", 3: "viscous", 4: "stiffness", 5: "stiffness"}
# ELFORM -> warping correction: Belytschko-Tsay without, Belytschko-Wong-Chiang with
WARPING_OF_ELFORM = {2: False, 10: True}
FULLY_INTEGRATED = (16, -16)
# formulations that are not 3-D shells: 2-D (plane stress, plane strain, axisymmetric), cohesive,
# Eulerian and mesh-free forms, user elements
REFUSED_ELFORMS = {12: "2-D plane stress", 13: "2-D plane strain", 14: "2-D axisymmetric (area weighted)",
                   15: "2-D axisymmetric (volume weighted)", 29: "cohesive shell", 31: "Eulerian", 32: "Eulerian",
                   41: "mesh-free", 42: "mesh-free", 43: "2-D mesh-free", 44: "2-D mesh-free", 46: "2-D cohesive",
                   47: "2-D cohesive", 51: "2-D", 52: "2-D", 55: "2-D"}


def _element_shell_thickness(r: _Reading) -> None:
    """*ELEMENT_SHELL_THICKNESS: each element's card, then THIC1..THIC4 and BETA (16 characters each)."""
    for element, thickness in r.groups(2):
        record = r.card(element, cards.ELEMENT_SHELL)
        if any(record[f"N{k}"] not in (0, None) for k in range(5, 9)):
            raise KeywordError(f"{element.where}: *ELEMENT_SHELL_THICKNESS {record['EID']} has nodes N5..N8; "
                               f"ParaDyn reads 4-node shells only")
        record.values.update(r.card(thickness, THICKNESS_CARD).values)
        r.data.elements.append(record)


def _section_corners(data: KeywordData, part: Record, warned: set[int]) -> list[float]:
    """T1..T4 of the part's section (T2..T4 blank or 0: T1, as in LS-DYNA)."""
    pid, secid = int(part["PID"]), int(part["SECID"] or 0)
    if secid not in data.sections:
        raise KeywordError(f"{part.where}: *PART {pid} names section {secid}, which no *SECTION_SHELL defines")
    second = data.sections[secid][1]
    t1 = float(second["T1"] or 0.0)
    corners = [float(second[f"T{k}"] or 0.0) or t1 for k in range(1, 5)]
    if len(set(corners)) > 1 and secid not in warned:
        warned.add(secid)
        data.warn(f"{second.where}: *SECTION_SHELL {secid} T1..T4 differ; ParaDyn's elements have one thickness, "
                  f"their mean {np.mean(corners):g} is used")
    return corners


def _thickness(corners: list[float]) -> float:
    return corners[0] if len(set(corners)) == 1 else float(np.mean(corners))


def split_by_thickness(data: KeywordData, mesh: KeywordMesh, given: dict[int, float] | None = None) -> None:
    """Give every engine part one thickness (deck units, ``mesh.part_thickness``): a deck part whose
    shells have several becomes one engine part per thickness, in the order of their first shell,
    each keeping the PID (``mesh.part_ids`` repeats it) with a name suffix (``mesh.part_suffix``).
    ``given``: PID -> the thickness of a part that has no shell section (a rigid solid's faces, a
    beam part's nominal diameter)."""
    by_pid = {int(p["PID"]): p for p in data.parts}
    section_of = {}
    warned: set[int] = set()
    n_shells = len(data.elements)   # the beams' rows follow (keyword/mesh.py), each of one thickness
    for pid in mesh.part_ids.tolist():
        if given and pid in given:
            section_of[pid] = [given[pid]] * 4
        else:
            section_of[pid] = _section_corners(data, by_pid[pid], warned)
    keys: dict[tuple[int, float], int] = {}
    element_part = np.empty_like(mesh.element_part)
    uneven: dict[int, Record] = {}
    for row in range(len(mesh.element_part)):
        pid = int(mesh.part_ids[mesh.element_part[row]])
        section = section_of[pid]
        if row >= n_shells:   # a beam: its part's one nominal thickness
            element_part[row] = keys.setdefault((pid, float(f"{_thickness(section):.12g}")), len(keys))
            continue
        record = data.elements[row]
        corners = [float(record.values.get(name) or 0.0) or section[k] for k, name in enumerate(CORNERS)]
        if len(set(corners)) > 1:
            uneven.setdefault(pid, record)
        thickness = float(f"{_thickness(corners):.12g}")
        if not thickness > 0.0:
            raise KeywordError(f"{record.where}: *ELEMENT_SHELL {record['EID']} of part {pid} has no thickness: its "
                               f"section's T1 is 0 and the element gives none; give T1 in *SECTION_SHELL or the "
                               f"corner thicknesses in *ELEMENT_SHELL_THICKNESS")
        element_part[row] = keys.setdefault((pid, thickness), len(keys))
    for pid, record in uneven.items():
        data.warn(f"{record.where}: *PART {pid}: shells with different corner thicknesses (the first: *ELEMENT_SHELL"
                  f"_THICKNESS {record['EID']}); ParaDyn's elements have one thickness, each takes the mean of its "
                  f"four corners")
    _renumber(data, mesh, keys, element_part, by_pid)


def _renumber(data: KeywordData, mesh: KeywordMesh, keys: dict[tuple[int, float], int], element_part: np.ndarray,
              by_pid: dict[int, Record]) -> None:
    count = {pid: sum(1 for p, _ in keys if p == pid) for pid, _ in keys}
    mesh.element_part = element_part.astype(np.int32)
    mesh.part_ids = np.array([pid for pid, _ in keys], dtype=np.int64)
    mesh.part_thickness = [t for _, t in keys]
    mesh.part_suffix = [f"_t{t:g}" if count[pid] > 1 else "" for pid, t in keys]
    for pid, n in count.items():
        if n > 1:
            listed = ", ".join(f"{t:g}" for p, t in keys if p == pid)
            data.warn(f"{by_pid[pid].where}: *PART {pid} has shells of {n} thicknesses ({listed}); ParaDyn has one "
                      f"thickness per part, so it runs as {n} parts named <part>_t<thickness>, each with PID {pid} "
                      f"(/parts/id, file_part_id); contacts and sets that name the PID take all of them")


def part_spec(data: KeywordData, record: Record, name: str, material: str, unit: Units, mesh: KeywordMesh,
              index: int) -> PartSpec:
    """The engine part ``index`` of the mesh, of the deck's *PART ``record``."""
    pid, secid = int(record["PID"]), int(record["SECID"] or 0)
    first = data.sections[secid][0]
    nip = int(first["NIP"]) or 2
    if not 1 <= nip <= MAX_INTEGRATION_POINTS:
        raise KeywordError(f"{first.where}: *SECTION_SHELL {secid} NIP = {nip}; ParaDyn takes 1 to "
                           f"{MAX_INTEGRATION_POINTS} points through the thickness")
    form, coefficient = _hourglass(data, record)
    element = "full" if int(first["ELFORM"]) in FULLY_INTEGRATED else "blt"
    geometry = mesh.part_geometry(index)
    return PartSpec(name=name, material=material, thickness=mesh.part_thickness[index] * unit.length,
                    geometry=geometry, integration_points=nip,
                    hourglass_coefficient=coefficient, hourglass_form=form,
                    warping_correction=_warping(data, first, pid, name), element=element,
                    thickness_update=_thickness_update(data, pid, name, element, geometry.mesh_data.quads))


def _thickness_update(data: KeywordData, pid: int, name: str, element: str, quads: np.ndarray) -> bool:
    """*CONTROL_SHELL ISTUPD = 1 (the element's forces use its current thickness) as the part's
    ``thickness_update``, for a part of one-point quadrilaterals; a part with triangles or the fully
    integrated element keeps t0, with a warning. Other ISTUPD values are warned and read as 0."""
    control = data.control.get("CONTROL_SHELL")
    istupd = int(control["ISTUPD"] or 0) if control is not None else 0
    if istupd == 0:
        return False
    if istupd != 1:
        data.warn(f"{control.where}: *CONTROL_SHELL ISTUPD = {istupd} is not read (ParaDyn reads 1, the thickness "
                  f"update of every part, or 0); part {pid} '{name}' keeps its thickness")
        return False
    triangles = int(np.count_nonzero(quads[:, 2] == quads[:, 3]))
    if element != "blt" or triangles:
        why = "is fully integrated" if element != "blt" else f"has {triangles} triangles"
        data.warn(f"{control.where}: *CONTROL_SHELL ISTUPD = 1: part {pid} '{name}' {why}, and ParaDyn's thickness "
                  f"update is the one-point quadrilateral's; the part keeps its thickness t0")
        return False
    return True


def _warping(data: KeywordData, section: Record, pid: int, name: str) -> bool:
    """ELFORM 2 and 10 as they are; 16 and -16 are the fully integrated element with the warping
    correction (its flat projection needs the rigid links on a warped element, as LS-DYNA's
    formulation 16 handles warping in its own way); a form that is not a 3-D shell is refused;
    any other shell form is warned and runs as ELFORM 2."""
    elform, secid = int(section["ELFORM"]), int(section["SECID"])
    if elform in WARPING_OF_ELFORM:
        return WARPING_OF_ELFORM[elform]
    if elform in REFUSED_ELFORMS or elform >= 98:
        what = REFUSED_ELFORMS.get(elform, "a user-defined element")
        raise KeywordError(f"{section.where}: *PART {pid} '{name}' uses *SECTION_SHELL {secid} ELFORM = {elform} "
                           f"({what}), which is not a 3-D thin shell; ParaDyn runs 3-D shells only: give the section "
                           f"ELFORM 2 (Belytschko-Tsay) or 16 (fully integrated), or leave the part out of the deck")
    if elform in FULLY_INTEGRATED:
        return True
    data.warn(f"{section.where}: *SECTION_SHELL {secid} ELFORM = {elform} is not available; ParaDyn's "
              f"Belytschko-Lin-Tsay shell (ELFORM 2) is used for part {pid} '{name}'")
    return False


def _hourglass(data: KeywordData, part: Record) -> tuple[str, float]:
    """The part's hourglass form and coefficient: its *HOURGLASS, else *CONTROL_HOURGLASS, else IHQ 1, 0.1."""
    hgid = int(part["HGID"] or 0)
    if hgid:
        if hgid not in data.hourglasses:
            raise KeywordError(f"{part.where}: *PART {part['PID']} names hourglass {hgid}, which no "
                               f"*HOURGLASS defines")
        record = data.hourglasses[hgid]
        ihq, coefficient = int(record["IHQ"]), float(record["QM"])
    elif "CONTROL_HOURGLASS" in data.control:
        record = data.control["CONTROL_HOURGLASS"]
        ihq, coefficient = int(record["IHQ"]), float(record["QH"])
    else:
        return "viscous", 0.1
    if ihq not in HOURGLASS_OF_IHQ:
        data.warn(f"{record.where}: IHQ = {ihq} has no ParaDyn counterpart for shells; the physical form is used")
        return "physical", coefficient
    return HOURGLASS_OF_IHQ[ihq], coefficient


READERS: dict[str, Callable[[_Reading], None]] = {"ELEMENT_SHELL_THICKNESS": _element_shell_thickness}
