"""The materials of a keyword deck (docs/keyword.md): *MAT cards as scene materials, in SI.

MAT 1 is elastic; MAT 3 is j2_plasticity, or j2_rate with SRC and SRP; MAT 24 (and MAT 81, read
as MAT 24 without its damage) is piecewise_linear, or piecewise_linear_rate with C and P, its
curves (LCSS or the EPS/ES pairs, LCSR) becoming scene curves that the material names. MAT 3's FS
and MAT 24's FAIL are the failure strain (element erosion, docs/theory.md); *MAT_ADD_EROSION's
EFFEPS and NUMFIP add to them (keyword/erosion.py).
"""

from __future__ import annotations

import itertools

import numpy as np

from paradyn import deck
from paradyn.scene.building import set_curves
from paradyn.scene.specs import CurveSpec, MaterialSpec, Scene

from .cards import KeywordData, Record
from .erosion import apply_erosion
from .reader import KeywordError
from .units import Units


def material_of(mid: int, data: KeywordData, unit: Units, curves: list[CurveSpec], rigid: bool = False) -> MaterialSpec:
    """Material ``mid`` of the deck; a MAT 24's curves are appended to ``curves``. ``rigid``: its
    rigid copy (density and elastic constants) for a part *DEFORMABLE_TO_RIGID switches."""
    model, cards = data.materials[mid]
    spec = _material(mid, "rigid" if rigid else model, cards, unit)
    if spec.model == "piecewise_linear":
        _piecewise(mid, data, unit, spec, curves)
    if not rigid:
        apply_erosion(mid, data, spec)   # *MAT_ADD_EROSION: EFFEPS and NUMFIP
    return spec


def _material(mid: int, model: str, cards: list[Record], unit: Units) -> MaterialSpec:
    first = cards[0]
    for name in ("RO", "E", "PR"):
        if first[name] is None:
            raise KeywordError(f"{first.where}: *MAT {mid} field {name} is blank; give its value")
    spec = MaterialSpec(name=f"mat_{mid}", model=model, density=float(first["RO"]) * unit.density,
                        youngs_modulus=float(first["E"]) * unit.stress, poisson_ratio=float(first["PR"]))
    if model == "j2_plasticity":
        if first["SIGY"] is None:
            raise KeywordError(f"{first.where}: *MAT_PLASTIC_KINEMATIC {mid} field SIGY is blank; give the "
                               f"yield stress")
        spec.yield_stress = float(first["SIGY"]) * unit.stress
        spec.tangent_modulus = float(first["ETAN"]) * unit.stress
        spec.hardening_mixing = float(first["BETA"])
        _rates(mid, cards[1], unit, spec)
        _failure(mid, cards[1], "FS", "*MAT_PLASTIC_KINEMATIC", spec)
    return spec


def _failure(mid: int, card: Record, name: str, keyword: str, spec: MaterialSpec) -> None:
    """The failure strain (MAT 3 FS, MAT 24 FAIL): an effective plastic strain > 0 becomes the
    material's failure_strain (an element is eroded when a point reaches it); 0, blank or a huge
    value (MAT 24's default 1e21) means no failure. A negative value (LS-DYNA: a user failure
    subroutine) is refused."""
    value = float(card.values.get(name) or 0.0)
    if value < 0.0:
        raise KeywordError(f"{card.where}: {keyword} {mid} {name} = {value:g} asks for a user failure subroutine, "
                           f"which ParaDyn does not have; give the failure plastic strain (> 0) or 0 for none")
    if 0.0 < value < 1e20:
        spec.extra["failure_strain"] = value


def _rates(mid: int, card: Record, unit: Units, spec: MaterialSpec) -> None:
    """MAT 3's Cowper-Symonds rate scaling: SRC = C (1 / the deck's time) and SRP = P make the
    material j2_rate; SRC = 0 means no rate effect, as in LS-DYNA."""
    c, p = float(card["SRC"] or 0.0), float(card["SRP"] or 0.0)
    if c == 0.0:
        return
    if c < 0.0 or p <= 0.0:
        raise KeywordError(f"{card.where}: *MAT_PLASTIC_KINEMATIC {mid} SRC = {c:g}, SRP = {p:g}: the Cowper-Symonds "
                           f"constants must both be > 0 (or SRC = 0 for no rate effect)")
    spec.model = "j2_rate"
    spec.extra = {"rate_c": c / unit.time, "rate_p": p}


def _piecewise(mid: int, data: KeywordData, unit: Units, spec: MaterialSpec, curves: list[CurveSpec]) -> None:
    """MAT 24 (MAT 81 read as it) as piecewise_linear(_rate): the hardening curve from LCSS (a
    *DEFINE_CURVE, SFA and SFO 0 meaning 1, OFFA and OFFO added), else from the EPS/ES pairs (the
    points up to the last nonzero ES), else the bilinear law of SIGY and ETAN; the rate factor
    from LCSR (a curve of the factor against the strain rate), else Cowper-Symonds C, P (C = 0:
    none). A curve that starts past zero plastic strain is extrapolated back to it, as LS-DYNA does."""
    first, second, eps, es = data.materials[mid][1]
    spec.extra.update({"hardening_curve": None, "rate_curve": None})   # none unless given below
    keyword = "*MAT_PIECEWISE_LINEAR_PLASTICITY"
    if "FAIL" in first.values:   # MAT 81's EPPF is its damage's, not a failure strain
        _failure(mid, first, "FAIL", keyword, spec)
    lcss, lcsr = int(second["LCSS"] or 0), int(second["LCSR"] or 0)
    ordinates = [float(es[f"ES{k}"] or 0.0) for k in range(1, 9)]
    if lcss:
        strain, stress = _keyword_curve(data, lcss, second.where, f"{keyword} {mid} LCSS")
        stress = [v * unit.stress for v in stress]
    elif any(ordinates):
        count = max(k for k, v in enumerate(ordinates, start=1) if v)
        strain = [float(eps[f"EPS{k}"] or 0.0) for k in range(1, count + 1)]
        stress = [v * unit.stress for v in ordinates[:count]]
    else:
        if first["SIGY"] is None or not float(first["SIGY"]) > 0.0:
            raise KeywordError(f"{first.where}: {keyword} {mid} has no LCSS, no ES1..ES8 and SIGY = {first['SIGY']}; "
                               f"give the yield stress SIGY (with ETAN) or a stress-strain curve")
        spec.yield_stress = float(first["SIGY"]) * unit.stress
        spec.tangent_modulus = float(first["ETAN"] or 0.0) * unit.stress
        strain = []
    if strain:
        strain, stress = _from_zero(strain, stress, data, f"{first.where}: {keyword} {mid}")
        fault = deck.material_curve_fault("hardening", np.asarray(strain), np.asarray(stress), stress[0])
        if fault or any(b <= a for a, b in itertools.pairwise(strain)):
            raise KeywordError(f"{second.where}: {keyword} {mid}: the stress-strain curve (plastic strain, stress) "
                               f"{list(zip(strain, stress, strict=True))} "
                               f"{fault or 'has plastic strains that do not increase strictly; order them'}")
        spec.yield_stress, spec.tangent_modulus = stress[0], 0.0
        spec.extra["hardening_curve"] = _add_curve(curves, f"mat_{mid}_hardening", strain, stress)
    c, p = float(second["C"] or 0.0), float(second["P"] or 0.0)
    if lcsr:
        rates, factors = _keyword_curve(data, lcsr, second.where, f"{keyword} {mid} LCSR")
        rates = [r / unit.time for r in rates]
        fault = deck.material_curve_fault("rate", np.asarray(rates), np.asarray(factors), 0.0)
        if fault:
            raise KeywordError(f"{second.where}: {keyword} {mid} LCSR = {lcsr}: {fault}")
        if c:
            data.warn(f"{second.where}: {keyword} {mid} has LCSR = {lcsr} and C = {c:g}; the rate curve is used, "
                      f"C and P are ignored")
        spec.extra["rate_curve"] = _add_curve(curves, f"mat_{mid}_rates", rates, factors)
    elif c:
        if c < 0.0 or p <= 0.0:
            raise KeywordError(f"{second.where}: {keyword} {mid} C = {c:g}, P = {p:g}: the Cowper-Symonds constants "
                               f"must both be > 0 (or C = 0 for no rate effect)")
        spec.model = "piecewise_linear_rate"
        del spec.extra["rate_curve"]   # a key of piecewise_linear alone
        spec.extra.update({"rate_c": c / unit.time, "rate_p": p})


def _keyword_curve(data: KeywordData, lcid: int, where: str, what: str) -> tuple[list[float], list[float]]:
    """The points of *DEFINE_CURVE lcid, scaled and offset (SFA, SFO of 0 meaning 1), in its units."""
    if lcid not in data.curves:
        raise KeywordError(f"{where}: {what} = {lcid} names no *DEFINE_CURVE (a *DEFINE_TABLE of curves by strain "
                           f"rate is not read); define the curve")
    head, points = data.curves[lcid]
    sfa, sfo = float(head["SFA"]) or 1.0, float(head["SFO"]) or 1.0
    return ([a * sfa + float(head["OFFA"]) for a, _ in points], [o * sfo + float(head["OFFO"]) for _, o in points])


def _from_zero(strain: list[float], stress: list[float], data: KeywordData,
               where: str) -> tuple[list[float], list[float]]:
    """The curve from zero plastic strain: a first point past zero is extrapolated back along the
    first segment (LS-DYNA's reading), points before zero are cut at it; with a warning."""
    if strain[0] == 0.0:
        return strain, stress
    if len(strain) == 1:
        return [0.0], stress
    if strain[0] > 0.0:
        slope = (stress[1] - stress[0]) / (strain[1] - strain[0])
        start = stress[0] - slope * strain[0]
    else:
        start = float(np.interp(0.0, strain, stress))
    data.warn(f"{where}: the stress-strain curve starts at plastic strain {strain[0]:g}, not 0; it is taken from "
              f"(0, {start:g} Pa) (LS-DYNA extrapolates the first segment)")
    kept = [k for k, e in enumerate(strain) if e > 0.0]
    return [0.0] + [strain[k] for k in kept], [start] + [stress[k] for k in kept]


def _add_curve(curves: list[CurveSpec], name: str, x: list[float], y: list[float]) -> str:
    curves.append(CurveSpec(name=name, time=tuple(x), value=tuple(y)))
    return name


def apply_material_curves(scene: Scene, model: deck.Model) -> None:
    """The materials' curves after the deck's other curves (the body loads'): appended to /curves,
    and the materials' curve indices (into the scene's curves) moved past those."""
    if not scene.curves:
        return
    before = 0 if model.curve_first_point is None else len(model.curve_first_point)
    times = [] if before == 0 else np.split(np.asarray(model.curve_time), np.asarray(model.curve_first_point)[1:])
    values = [] if before == 0 else np.split(np.asarray(model.curve_value), np.asarray(model.curve_first_point)[1:])
    set_curves(model, [list(t) for t in times] + [list(c.time) for c in scene.curves],
               [list(v) for v in values] + [list(c.value) for c in scene.curves])
    for name in ("hardening_curve", "rate_curve"):
        indices = getattr(model, name)
        if indices is not None:
            setattr(model, name, np.where(np.asarray(indices) >= 0, np.asarray(indices) + before, indices))


__all__ = ["apply_material_curves", "material_of"]
