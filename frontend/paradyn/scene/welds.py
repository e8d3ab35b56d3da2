"""Spot welds of a scene (docs/scene.md, ``[[weld]]``): the nodes of two parts nearest a point
joined as a small rigid body, with the weld's failure (docs/theory.md, "Weld failure").
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from paradyn.deck.rigid_bodies import Weld

from .specs import WeldSpec
from .tables import _Reader

_WELD_KEYS = ("parts", "point", "strength", "exponent", "failure_time")


def parse_weld(r: _Reader, t: dict[str, Any], index: int) -> WeldSpec:
    """Entry ``index`` of ``[[weld]]``, checked key by key."""
    label = f"[[weld]] #{index + 1}"
    r.keys(t, label, _WELD_KEYS)
    parts = r.raw(t, "parts", label, None)
    if not (isinstance(parts, list) and len(parts) == 2 and all(isinstance(p, str) for p in parts)
            and parts[0] != parts[1]):
        raise r.error(f"'parts' in {label} must name the two different parts the weld joins, e.g. "
                      f"[\"upper\", \"lower\"]; got {parts!r}")
    strength = tuple(float(v) for v in r.vector(t, "strength", label, default=(0.0, 0.0), length=2))
    exponent = tuple(float(v) for v in r.vector(t, "exponent", label, default=(2.0, 2.0), length=2))
    if min(strength) < 0.0 or min(exponent) <= 0.0:
        raise r.error(f"{label}: 'strength' (SN, SS in N) must be >= 0 and 'exponent' (N, M) > 0; got "
                      f"{list(strength)}, {list(exponent)}")
    return WeldSpec(parts=(parts[0], parts[1]), point=r.vector(t, "point", label),
                    strength=(strength[0], strength[1]), exponent=(exponent[0], exponent[1]),
                    failure_time=r.number(t, "failure_time", label, default=1e20))


def scene_welds(scene_welds: list[WeldSpec], node_of: Callable[[str, tuple[float, float, float], str], int]
                ) -> list[Weld]:
    """The welds of the deck model: ``node_of(part, point, label)`` the node of the part nearest
    the point (the first part's node is N1, the weld's normal N1 -> N2)."""
    return [Weld([node_of(spec.parts[0], spec.point, f"[[weld]] #{k + 1}"),
                  node_of(spec.parts[1], spec.point, f"[[weld]] #{k + 1}")],
                 strength=spec.strength, exponent=spec.exponent, failure_time=spec.failure_time)
            for k, spec in enumerate(scene_welds)]



