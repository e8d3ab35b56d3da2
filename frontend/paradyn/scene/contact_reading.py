"""Reading a scene's ``[[contact]]`` tables (docs/scene.md): kind, parts, penalty and friction, life,
edges and a tiebreak's failure stresses, each problem a SceneError naming the table and key."""

from __future__ import annotations

from typing import Any

from paradyn import _schema
from paradyn.scene.specs import EDGE_KINDS, ContactSpec
from paradyn.scene.tables import _REQUIRED, _Reader, read_life

_CONTACT_KEYS = ("parts", "kind", "initial_penetration", "penalty_scale", "soft_constraint", "thickness_scale",
                 "static_friction", "dynamic_friction", "friction_decay", "symmetric", "birth_time", "death_time",
                 "edges", *ContactSpec.FAILURE_KEYS)


def parse_contact(r: _Reader, t: dict[str, Any], index: int) -> ContactSpec:
    label = f"[[contact]] #{index + 1}"
    r.keys(t, label, _CONTACT_KEYS)
    kind = (r.string(t, "kind", label, choices=tuple(_schema.ENUMS["contact_kind"])) if "kind" in t
            else ContactSpec.kind)
    edges = r.raw(t, "edges", label, kind in EDGE_KINDS)
    if not isinstance(edges, bool) or (edges and kind in ("tied", "tiebreak")):
        raise r.error(f"'edges' in {label} must be true (edges against edges; not tied) or false; got {edges!r}")
    strengths = {k: r.number(t, k, label, default=0.0, minimum=0.0) for k in ContactSpec.FAILURE_KEYS}
    if (kind == "tiebreak") != any(strengths.values()):   # a tiebreak needs one, and only a tiebreak takes them
        raise r.error(f"{label} is kind = \"{kind}\": kind = \"tiebreak\" needs 'normal_failure_stress' and/or "
                      f"'shear_failure_stress' (Pa), and no other kind takes them (\"tied\": a tie that never fails)")
    parts = _contact_parts(r, t, label, kind := EDGE_KINDS.get(kind, kind))
    symmetric = r.raw(t, "symmetric", label, ContactSpec.symmetric)
    if not isinstance(symmetric, bool):
        raise r.error(f"'symmetric' in {label} must be true (both passes every step) or false "
                      f"(slave and master swap every step, as in the paper); got {symmetric!r}")
    static = r.number(t, "static_friction", label, default=ContactSpec.static_friction, minimum=0.0)
    birth, death = read_life(r, t, label, "contact", ContactSpec)
    return ContactSpec(
        parts=parts,
        penalty_scale=r.number(t, "penalty_scale", label, default=ContactSpec.penalty_scale, positive=True),
        soft_constraint=r.number(t, "soft_constraint", label, default=ContactSpec.soft_constraint, minimum=0.0),
        thickness_scale=_thickness_scale(r, t, label, kind),
        static_friction=static,
        dynamic_friction=r.number(t, "dynamic_friction", label, default=static, minimum=0.0),
        friction_decay=r.number(t, "friction_decay", label, default=ContactSpec.friction_decay, minimum=0.0),
        symmetric=symmetric,
        kind=kind,
        initial_penetration=r.string(t, "initial_penetration", label, default=ContactSpec.initial_penetration,
                                     choices=tuple(_schema.ENUMS["initial_penetration"])),
        birth_time=birth,
        death_time=death, edges=edges, **strengths,
    )



def _thickness_scale(r: _Reader, t: dict[str, Any], label: str, kind: str) -> tuple[float, float]:
    """``thickness_scale``: one number for both parts, or [first, second] for a pair (LS-DYNA SFST,
    SFMT); a single_surface contact takes one number. Each in (0, 10]."""
    value = r.raw(t, "thickness_scale", label, ContactSpec.thickness_scale[0])
    pair = isinstance(value, list) and len(value) == 2 and kind != "single_surface"
    scales = value if pair else [value]
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and 0.0 < v <= 10.0 for v in scales):
        form = "one number" if kind == "single_surface" else "one number, or [first part, second part]"
        raise r.error(f"'thickness_scale' in {label} must be {form}, each above 0 and at most 10 (1: the shell's "
                      f"thickness, LS-DYNA's SFST/SFMT default); got {value!r}")
    return (float(scales[0]), float(scales[-1]))


def _contact_parts(r: _Reader, t: dict[str, Any], label: str, kind: str) -> tuple[str, ...]:
    """Two different parts for a node_to_segment pair; one or more different parts for a
    single_surface contact, or none (every part of the scene)."""
    if kind == "single_surface":
        parts = r.raw(t, "parts", label, [])
        if (not isinstance(parts, list) or not all(isinstance(p, str) for p in parts)
                or len(set(parts)) != len(parts)):
            raise r.error(f"'parts' in {label} must list different parts that form the single surface, e.g. "
                          f"parts = [\"pipe\"] (leave it out for every part of the scene); got {parts!r}")
        return tuple(parts)
    parts = r.raw(t, "parts", label, _REQUIRED)
    if (not isinstance(parts, list) or len(parts) != 2 or not all(isinstance(p, str) for p in parts)
            or parts[0] == parts[1]):
        raise r.error(f"'parts' in {label} must name two different parts, e.g. parts = [\"a\", \"b\"] "
                      f"(for a part against itself use kind = \"single_surface\"); got {parts!r}")
    return (parts[0], parts[1])
