"""Beams of a keyword deck as trusses (docs/keyword.md, "Beams as trusses").

``*ELEMENT_BEAM`` (EID PID N1 N2 N3 ...; N3, the orientation node, is not needed by a truss and
ignored) on a part whose ``*SECTION_BEAM`` has ELFORM 3 (truss: axial force only, cross-section
A) becomes an element N1 N2 N2 N2 of a truss part (``/parts/element_kind`` truss,
``/parts/cross_section_area`` A); its material is any the reader takes (``*MAT_ELASTIC``,
``*MAT_PLASTIC_KINEMATIC``, ``*MAT_PIECEWISE_LINEAR_PLASTICITY``, in their uniaxial form). Other
beam formulations (bending beams, cables, discrete beams) are refused, naming the ELFORM.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from paradyn.scene.specs import PartSpec

from .cards import KeywordData, Record, _options, _Reading
from .mesh import PartMeshGeometry
from .reader import Field, KeywordError, layout

ELEMENT_BEAM = tuple(Field(n, "int", None if n in ("EID", "PID", "N1", "N2") else 0, 8)
                     for n in ("EID", "PID", "N1", "N2", "N3", "RT1", "RR1", "RT2", "RR2", "LOCAL"))
SECTION_BEAM = (layout("int:SECID int:ELFORM SHRF int:QR/IRID int:CST SCOOR NSM int:NAUPD", elform=1, shrf=1.0,
                       **{"qr/irid": 2}, cst=0, scoor=0.0, nsm=0.0, naupd=0),
                layout("A RAMPT STRESS", a=0.0, rampt=0.0, stress=0.0))
TRUSS_ELFORM = 3
# LS-DYNA's beam formulations (*SECTION_BEAM ELFORM), named in the refusal of those not read
BEAM_FORMS = {1: "Hughes-Liu beam", 2: "Belytschko-Schwer resultant beam", 4: "Belytschko-Schwer full cross-"
              "section integration", 5: "Belytschko-Schwer tubular beam", 6: "discrete beam/cable",
              7: "2-D plane strain shell", 8: "2-D axisymmetric shell", 9: "spotweld beam",
              11: "integrated warped beam", 12: "resultant warped beam", 13: "small displacement linear beam",
              14: "elastic beam with warping"}


def _element_beam(r: _Reading) -> None:
    """*ELEMENT_BEAM cards (the plain keyword; its options _THICKNESS, _OFFSET, ... are not read)."""
    for line in r.lines():
        record = r.card(line, ELEMENT_BEAM, {"RT1": 0, "RR1": 0, "RT2": 0, "RR2": 0, "LOCAL": 0})
        if int(record["N1"]) == int(record["N2"]):
            raise KeywordError(f"{line.where}: *ELEMENT_BEAM {record['EID']} has N1 = N2 = {record['N1']}; a beam "
                               f"joins two different nodes")
        r.data.beams.append(record)


def _section_beam(r: _Reading) -> None:
    """*SECTION_BEAM: card 1, then card 2 (for ELFORM 3: A, RAMPT, STRESS); the title card with _TITLE."""
    titled = "TITLE" in _options(r.keyword, "SECTION_BEAM")
    for group in r.groups(3 if titled else 2):
        first = r.card(group[-2], SECTION_BEAM[0])
        second = r.card(group[-1], SECTION_BEAM[1]) if int(first["ELFORM"]) == TRUSS_ELFORM else \
            Record({}, group[-1].where)
        r.data.beam_sections[int(first["SECID"])] = [first, second]


def beam_area(data: KeywordData, part: Record) -> float:
    """The cross-section area A (deck units) of a beam part's *SECTION_BEAM; ELFORM other than 3 refused."""
    pid, secid = int(part["PID"]), int(part["SECID"] or 0)
    if secid not in data.beam_sections:
        raise KeywordError(f"{part.where}: *PART {pid} has *ELEMENT_BEAM elements but names section {secid}, which "
                           f"no *SECTION_BEAM defines; give the part a *SECTION_BEAM with ELFORM 3 (truss)")
    first, second = data.beam_sections[secid]
    elform = int(first["ELFORM"])
    if elform != TRUSS_ELFORM:
        what = BEAM_FORMS.get(elform, "a beam formulation")
        raise KeywordError(f"{first.where}: *PART {pid} uses *SECTION_BEAM {secid} ELFORM = {elform} ({what}), which "
                           f"ParaDyn does not have; ParaDyn's beams are trusses, ELFORM 3 (axial force only, "
                           f"cross-section A): give the section ELFORM 3 with its area A for wires and cables, or "
                           f"leave the part out of the deck")
    area = float(second["A"] or 0.0)
    if not area > 0.0:
        raise KeywordError(f"{second.where}: *SECTION_BEAM {secid} ELFORM 3 has A = {second['A']}; give the truss's "
                           f"cross-section area A > 0")
    if float(first["NSM"] or 0.0) != 0.0:
        data.warn(f"{first.where}: *SECTION_BEAM {secid} NSM = {first['NSM']} (non-structural mass) is not "
                  f"supported and ignored")
    return area


def beam_pids(data: KeywordData) -> set[int]:
    """The PIDs of the deck's *ELEMENT_BEAM elements (truss parts)."""
    return {int(record["PID"]) for record in data.beams}


def beam_thickness(data: KeywordData) -> dict[int, float]:
    """PID -> the nominal diameter sqrt(4 A / pi) (deck units) of each beam part that has elements."""
    by_pid = {int(p["PID"]): p for p in data.parts}
    return {pid: math.sqrt(4.0 * beam_area(data, by_pid[pid]) / math.pi) for pid in beam_pids(data) if pid in by_pid}


def truss_part_spec(data: KeywordData, record: Record, name: str, material: str, length: float,
                    geometry: PartMeshGeometry) -> PartSpec:
    """The truss part of the deck's beam *PART ``record`` (``length``: the deck's length unit in m).
    Its thickness is the nominal diameter of a round wire of area A (for the outputs; a truss has
    no contact surface)."""
    area = beam_area(data, record) * length**2
    return PartSpec(name=name, material=material, thickness=math.sqrt(4.0 * area / math.pi), geometry=geometry,
                    integration_points=1, element_kind="truss", cross_section_area=area)


READERS: dict[str, Callable[[_Reading], None]] = {
    "ELEMENT_BEAM": _element_beam,
    "SECTION_BEAM": _section_beam, "SECTION_BEAM_TITLE": _section_beam,
}
