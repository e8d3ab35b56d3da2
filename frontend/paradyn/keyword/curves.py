"""Load curves of a keyword deck as ParaDyn's effects take them (docs/keyword.md, "Curves").

:func:`curve_points` turns a ``*DEFINE_CURVE`` into times (s) and values: time ``A SFA + OFFA``,
value ``O SFO + OFFO`` (SFA, SFO 0 mean 1); a positive OFFA holds the value 0 until just before the
shift (0.999 OFFA), as LS-DYNA does for a time curve; a curve that starts after time 0 holds its
first value before it, and one that ends before the end time runs on to it by its last slope (as
LS-DYNA extrapolates a curve). :func:`ramps_of` writes a piecewise-linear curve as a sum
of ParaDyn point-load ramps, exactly; :func:`velocity_of_displacement` and
:func:`velocity_of_acceleration` make a prescribed displacement or acceleration a velocity curve.
"""

from __future__ import annotations

import numpy as np

from .cards import KeywordData
from .reader import KeywordError
from .units import Units

ACCELERATION_SUBDIVISIONS = 8    # points per segment of an integrated acceleration (v is quadratic there)
JUMP_WIDTH = 1e-4                # a velocity jump's transition, as a fraction of the shortest segment


def curve_points(data: KeywordData, lcid: int, unit: Units, end_time: float,
                 what: str) -> tuple[np.ndarray, np.ndarray]:
    """The curve LCID from time 0 to at least ``end_time`` (s): times in s, values as written (scaled)."""
    if lcid not in data.curves:
        raise KeywordError(f"{what} LCID = {lcid} names no *DEFINE_CURVE; define the curve")
    head, points = data.curves[lcid]
    if not points:
        raise KeywordError(f"{head.where}: *DEFINE_CURVE {lcid} has no points; give at least one (time, value) pair")
    sfa, sfo = float(head["SFA"]) or 1.0, float(head["SFO"]) or 1.0
    offa, offo = float(head["OFFA"]), float(head["OFFO"])
    times = np.array([(a * sfa + offa) * unit.time for a, _ in points])
    values = np.array([o * sfo + offo for _, o in points])
    if np.any(np.diff(times) <= 0.0):
        raise KeywordError(f"{head.where}: *DEFINE_CURVE {lcid}: the abscissas must increase strictly")
    if offa > 0.0 and 0.999 * offa * unit.time < times[0]:
        times = np.concatenate([[0.0, 0.999 * offa * unit.time], times])
        values = np.concatenate([[0.0, 0.0], values])
    return _over(times, values, end_time)


def _slope(times: np.ndarray, values: np.ndarray, at: int) -> float:
    """The first (``at`` 0) or last (-1) segment's slope; 0 for a one-point curve."""
    if times.size < 2:
        return 0.0
    pair = slice(0, 2) if at == 0 else slice(-2, None)
    return float(np.diff(values[pair])[0] / np.diff(times[pair])[0])


def _over(times: np.ndarray, values: np.ndarray, end_time: float) -> tuple[np.ndarray, np.ndarray]:
    """The curve from time 0 (its first value held before its first point) to ``end_time``
    (extrapolated by its last slope)."""
    if times[0] > 0.0:
        times = np.concatenate([[0.0], times])
        values = np.concatenate([[values[0]], values])
    elif times[0] < 0.0:
        keep = times > 0.0
        start = float(np.interp(0.0, times, values)) if keep.any() else float(
            values[-1] - _slope(times, values, -1) * times[-1])
        times, values = np.concatenate([[0.0], times[keep]]), np.concatenate([[start], values[keep]])
    if times[-1] < end_time:
        last = values[-1] + _slope(times, values, -1) * (end_time - times[-1])
        times, values = np.append(times, end_time), np.append(values, last)
    return times, values


def cut_at(times: np.ndarray, values: np.ndarray, stop: float) -> tuple[np.ndarray, np.ndarray]:
    """The curve up to time ``stop`` (its value there the last), held after it."""
    if stop >= times[-1]:
        return times, values
    keep = times < stop
    return np.append(times[keep], stop), np.append(values[keep], np.interp(stop, times, values))


def ramps_of(times: np.ndarray, values: np.ndarray) -> list[tuple[float, float]]:
    """A piecewise-linear curve from time 0, held after its last point, as a sum of ParaDyn ramps
    ``value min(t / ramp_time, 1)`` (ramp time 0: at once): ``(ramp_time, value)`` pairs, exact.

    With slopes ``s_k`` on the segments ending at ``t_k`` (and 0 after the last), the ramp ending
    at ``t_k`` carries ``(s_k - s_{k+1}) t_k``, plus ``f(0)`` at once."""
    rows = [(0.0, float(values[0]))] if values[0] != 0.0 else []
    slopes = np.append(np.diff(values) / np.diff(times), 0.0)
    for k in range(1, times.size):
        coefficient = float((slopes[k - 1] - slopes[k]) * times[k])
        if coefficient != 0.0:
            rows.append((float(times[k]), coefficient))
    return rows


def velocity_of_displacement(times: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The velocity of a piecewise-linear displacement: its slope on each segment, each jump a
    linear transition centred on the point (JUMP_WIDTH of the shortest segment each side), which
    keeps the integral, so the displacement is exact at the curve's points and outside the jumps."""
    slopes = np.diff(values) / np.diff(times)
    if slopes.size == 0:
        return np.array([0.0]), np.array([0.0])
    half = JUMP_WIDTH * float(np.min(np.diff(times)))
    t, v = [0.0], [float(slopes[0])]
    for k in range(1, slopes.size):
        if slopes[k] != slopes[k - 1]:
            t += [float(times[k]) - half, float(times[k]) + half]
            v += [float(slopes[k - 1]), float(slopes[k])]
    t.append(float(times[-1]))
    v.append(float(slopes[-1]))
    return np.array(t), np.array(v)


def velocity_of_acceleration(times: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The velocity from 0 of a piecewise-linear acceleration: exact at the curve's points and at
    ACCELERATION_SUBDIVISIONS points of each segment whose acceleration varies (the velocity is
    quadratic there, linear between those points)."""
    t, v = [float(times[0])], [0.0]
    for k in range(times.size - 1):
        t0, t1, a0, a1 = (float(x) for x in (times[k], times[k + 1], values[k], values[k + 1]))
        base, parts = v[-1], 1 if a0 == a1 else ACCELERATION_SUBDIVISIONS
        for j in range(1, parts + 1):
            tau = (t1 - t0) * j / parts
            t.append(t0 + tau)
            v.append(base + a0 * tau + 0.5 * (a1 - a0) / (t1 - t0) * tau**2)
    return np.array(t), np.array(v)
