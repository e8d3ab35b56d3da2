"""Quantities of interest and their errors (issue 16, docs/accuracy-cost.md).

A quantity is written as text and read from a run's history table:

- ``upper_top.dz@1e-3``: a component (dx dy dz vx vy vz) of a tracked point at a time (s),
  interpolated linearly between history records; ``@1e-3,2.5e-3`` gives one quantity per time;
- ``mean(lower_contact,upper_contact).dz@1e-3``: the mean of several tracked points;
- ``diff(upper_contact,upper_top).dz@1e-3``: the first point's component less the second's (the
  change of a distance, free of the rigid motion both points share);
- ``upper_top.dz:peak`` (the value of largest magnitude), ``:max``, ``:min``, ``:final``;
- an energy (``internal_energy``, ``kinetic_energy``, ``hourglass_energy``, ``contact_energy``,
  ``external_work``, ``total_energy``) with ``@TIME`` or a statistic, e.g. ``internal_energy:peak``.

The reference of a quantity is a value the user gives, the Richardson extrapolation over the mesh
ladder (:func:`richardson`), or the finest run's value; the error of a run is its relative
difference from the reference.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from paradyn._schema import ENERGY_NAMES

from .design import StudyError

COMPONENTS = ("dx", "dy", "dz", "vx", "vy", "vz")
STATISTICS = ("peak", "max", "min", "final")
ENERGIES = (*ENERGY_NAMES, "total_energy")
# Observed orders outside this range: the ladder is not in the asymptotic range. Below 1 (with a
# ratio of 2) the correction beyond the finest mesh, (q3 - q2) / (r^p - 1), would be larger than the
# last change it rests on; above 6 the changes shrink faster than any of the element's error terms.
ORDER_RANGE = (1.0, 6.0)
_SOURCE = re.compile(r"^(?:(?P<how>mean|diff)\((?P<points>[\w,\s]+)\)|(?P<point>\w+))(?:\.(?P<component>\w+))?$")


@dataclass(frozen=True)
class Quantity:
    """One quantity of interest: a weighted sum of history columns, then a time or a statistic."""

    name: str
    columns: tuple[str, ...]
    weights: tuple[float, ...]
    time: float | None = None        # the value at this time, s
    statistic: str | None = None     # or one of STATISTICS

    def value(self, history: Mapping[str, np.ndarray]) -> float:
        """The quantity in a run's history table; a StudyError when the run has not the column or time."""
        missing = [c for c in self.columns if c not in history]
        if missing:
            raise StudyError(f"quantity '{self.name}': the run has no history column {missing[0]}; tracked "
                             "points are the scene's [[track]] names, components are " + " ".join(COMPONENTS))
        series = sum(w * np.asarray(history[c], dtype=np.float64) for c, w in zip(self.columns, self.weights,
                                                                                   strict=True))
        times = np.asarray(history["time"], dtype=np.float64)
        if self.time is not None:
            if not times.size or self.time > times[-1] * (1 + 1e-9) or self.time < 0:
                reached = times[-1] if times.size else 0.0
                raise StudyError(f"quantity '{self.name}' asks for t = {self.time:g} s but the run ends at "
                                 f"{reached:g} s; ask for an earlier time or a longer run (end_time)")
            return float(np.interp(self.time, times, series))
        if self.statistic == "final":
            return float(series[-1])
        if self.statistic == "max":
            return float(np.max(series))
        if self.statistic == "min":
            return float(np.min(series))
        return float(series[np.argmax(np.abs(series))])


def check_quantities(quantities: list[Quantity], tracks: list[str], end_time: float) -> None:
    """A StudyError for a quantity that names a point the scene does not track or a time after the
    runs' end, before anything runs."""
    for q in quantities:
        for column in q.columns:
            point = column.rsplit("_", 1)[0]
            if column not in ENERGIES and point not in tracks:
                raise StudyError(f"quantity '{q.name}': the scene tracks no point '{point}'; its [[track]] names "
                                 f"are: {', '.join(tracks) or 'none'}")
        if q.time is not None and q.time > end_time * (1 + 1e-9):
            raise StudyError(f"quantity '{q.name}' asks for t = {q.time:g} s but the runs end at {end_time:g} s; "
                             "ask for an earlier time or a longer run (end_time)")


def parse_quantities(name: str, text: str) -> list[Quantity]:
    """The quantities written ``text`` (see the module doc), named ``name`` (``name@t`` for several times)."""
    source, at, times = text.strip().partition("@")
    statistic = None
    if not at:
        source, colon, statistic = source.partition(":")
        if not colon or statistic not in STATISTICS:
            raise StudyError(f"quantity '{name}' = '{text}': end it with @TIME (s) or :STATISTIC "
                             f"({', '.join(STATISTICS)}), e.g. 'upper_top.dz@1e-3' or 'internal_energy:peak'")
    columns, weights = _columns(name, text, source.strip())
    if statistic is not None:
        return [Quantity(name, columns, weights, statistic=statistic)]
    try:
        values = [float(t) for t in times.split(",")]
    except ValueError:
        raise StudyError(f"quantity '{name}' = '{text}': the times after @ must be numbers in s, "
                         "separated by commas") from None
    if len(values) == 1:
        return [Quantity(name, columns, weights, time=values[0])]
    return [Quantity(f"{name}@{t:g}", columns, weights, time=t) for t in values]


def _columns(name: str, text: str, source: str) -> tuple[tuple[str, ...], tuple[float, ...]]:
    if source in ENERGIES:
        return (source,), (1.0,)
    match = _SOURCE.match(source)
    if not match or match["component"] not in COMPONENTS:
        raise StudyError(f"quantity '{name}' = '{text}': write POINT.COMPONENT, mean(P1,P2).COMPONENT, "
                         f"diff(P1,P2).COMPONENT or an energy ({', '.join(ENERGIES)}); components are "
                         f"{' '.join(COMPONENTS)}")
    points = [p.strip() for p in (match["points"] or match["point"]).split(",") if p.strip()]
    if match["how"] == "diff" and len(points) != 2:
        raise StudyError(f"quantity '{name}' = '{text}': diff takes two points, diff(P1,P2), P1 less P2")
    weights = (1.0, -1.0) if match["how"] == "diff" else (1.0 / len(points),) * len(points)
    return tuple(f"{p}_{match['component']}" for p in points), weights


@dataclass(frozen=True)
class Extrapolation:
    """Richardson extrapolation over a mesh ladder: the value and the observed order, or why not."""

    value: float | None
    order: float | None
    message: str                     # empty when the ladder is in the asymptotic range


def richardson(factors: Sequence[float], values: Sequence[float]) -> Extrapolation:
    """Extrapolate ``values`` on meshes refined by ``factors`` (element size 1/factor) to size 0.

    The three finest meshes, refined by a constant ratio r, give the observed order
    p = ln((q1 - q2) / (q2 - q3)) / ln r and the value q3 + (q3 - q2) / (r^p - 1). A ladder whose
    changes alternate in sign, grow, or give p outside :data:`ORDER_RANGE` is not in the asymptotic
    range: then ``value`` and ``order`` are None and ``message`` says what was seen.
    """
    pairs = sorted(zip(factors, values, strict=True))
    if len(pairs) < 3:
        return Extrapolation(None, None, f"needs 3 meshes, the study has {len(pairs)}: give mesh = [1, 2, 4]")
    (f1, q1), (f2, q2), (f3, q3) = pairs[-3:]
    r = f2 / f1
    if f1 <= 0 or abs(f3 / f2 - r) > 1e-9 * r or r <= 1:
        return Extrapolation(None, None, f"the three finest meshes ({f1:g}, {f2:g}, {f3:g}) are not refined by a "
                                         "constant ratio above 1: give mesh factors like 1, 2, 4")
    e21, e32 = q2 - q1, q3 - q2
    scale = max(abs(q1), abs(q2), abs(q3), np.finfo(np.float64).tiny)
    if abs(e32) <= 1e-12 * scale and abs(e21) <= 1e-12 * scale:
        return Extrapolation(q3, None, "")   # converged to round-off: no order to observe
    ladder = f"changes {e21:+.3g} then {e32:+.3g} from mesh {f1:g} to {f2:g} to {f3:g}"
    if e21 == 0 or e32 / e21 <= 0:
        return Extrapolation(None, None, f"not in the asymptotic range: the {ladder} alternate in sign "
                                         "(refine further, or use the finest run as the reference)")
    ratio = e21 / e32
    if ratio <= 1:
        return Extrapolation(None, None, f"not in the asymptotic range: the {ladder} do not shrink "
                                         "(refine further, or use the finest run as the reference)")
    order = math.log(ratio) / math.log(r)
    if not ORDER_RANGE[0] <= order <= ORDER_RANGE[1]:
        return Extrapolation(None, order, f"not in the asymptotic range: the {ladder} give an observed order "
                                          f"{order:.2f}, outside {ORDER_RANGE[0]:g} to {ORDER_RANGE[1]:g} "
                                          "(refine further, or use the finest run as the reference)")
    return Extrapolation(q3 + e32 / (r**order - 1.0), order, "")


@dataclass(frozen=True)
class Reference:
    """The reference of one quantity: its value, where it came from, and a note."""

    value: float | None
    source: str                      # "given", "richardson", "finest run" or "none"
    order: float | None = None
    note: str = ""


def reference(given: float | None, mode: str, ladder: Sequence[tuple[float, float]],
              finest: float | None) -> Reference:
    """A quantity's reference: ``given`` if any; else Richardson over ``ladder`` (mesh factor, value)
    when ``mode`` is "richardson" and the ladder is asymptotic; else the finest run's value."""
    if given is not None:
        return Reference(given, "given")
    if finest is None:
        return Reference(None, "none", note="no finished run on the mesh ladder (the base and its mesh "
                                            "steps) to compare with; give a reference value")
    note = ""
    if mode == "richardson":
        ex = richardson([f for f, _ in ladder], [q for _, q in ladder])
        if ex.value is not None:
            return Reference(ex.value, "richardson", ex.order)
        note = f"Richardson: {ex.message}; errors are against the finest run"
    return Reference(finest, "finest run", note=note)


def relative_error(value: float, ref: float) -> float:
    """|value - ref| / |ref| (the absolute difference when ref is 0)."""
    return abs(value - ref) / abs(ref) if ref != 0 else abs(value - ref)


def pareto_front(costs: Sequence[float], errors: Sequence[float]) -> list[int]:
    """Indices of the runs no other run beats on both cost and error, cheapest first."""
    order = sorted(range(len(costs)), key=lambda i: (costs[i], errors[i]))
    front, best = [], math.inf
    for i in order:
        if errors[i] < best:
            front.append(i)
            best = errors[i]
    return front


def parse_target(text: str | float) -> float:
    """``"1%"`` or ``0.01`` as a fraction; a StudyError for anything else."""
    try:
        value = float(text[:-1]) / 100 if isinstance(text, str) and text.endswith("%") else float(text)
    except ValueError:
        raise StudyError(f"target '{text}' is not a number; write it as 1% or 0.01") from None
    if not 0 < value < 10:
        raise StudyError(f"target {text} must be a relative error above 0, such as 1% or 0.01")
    return value
