"""The knobs a study turns and the designs that combine them (issue 16, docs/accuracy-cost.md).

A *knob* is one setting of a scene that trades accuracy against time: :data:`KNOBS` names each,
with how to read the scene's own value (the base) and how to set another. A *configuration* is a
set of knob values away from the base; the base run is the empty configuration. A *design* turns
knob values into configurations: ``one_at_a_time`` (each value of each knob around the base),
``grid`` (every combination) or ``list`` (configurations given one by one).
"""

from __future__ import annotations

import copy
import itertools
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from paradyn import _schema
from paradyn.arguments import did_you_mean
from paradyn.scene.specs import (
    HOURGLASS_FORMS,
    ROTARY_INERTIAS,
    SHELL_ELEMENTS,
    CylinderGeometry,
    FileGeometry,
    PlateGeometry,
    Scene,
)

DESIGNS = ("one_at_a_time", "grid", "list")
PRECISIONS = tuple(_schema.ENUMS["precision"])   # [run] precision: the engines there are
Value = int | float | bool | str
Config = tuple[tuple[str, Value], ...]   # (knob, value) pairs in the order of KNOBS; () is the base


class StudyError(ValueError):
    """A study that cannot be made: a bad knob, value, quantity or option; the message says the fix."""


@dataclass(frozen=True)
class Knob:
    """One setting a study can turn: its value type, what it means, the scene's value and a setter."""

    name: str
    kind: type
    meaning: str
    base: Callable[[Scene], Value | None]        # the scene's value; None when its parts differ
    apply: Callable[[Scene, Any], None]           # sets the value on a copy of the scene
    check: Callable[[Any], str | None] = lambda v: None   # a problem with the value, or None
    needs: str = ""                               # what the scene must have ("contact"), or ""


def _same(values: Sequence[Value]) -> Value | None:
    return values[0] if values and all(v == values[0] for v in values) else None


def _refine(scene: Scene, factor: float) -> None:
    for part in scene.parts:
        g = part.geometry
        if isinstance(g, FileGeometry):
            raise StudyError(f"part '{part.name}' is meshed from a file ({g.path}); the mesh knob refines "
                             "generated parts (cylinder, plate) only: leave 'mesh' out of the study")
        if isinstance(g, CylinderGeometry):
            g.elements_around = _scaled(part.name, "elements_around", g.elements_around, factor, multiple=4)
            g.elements_along = _scaled(part.name, "elements_along", g.elements_along, factor)
        elif isinstance(g, PlateGeometry):
            g.elements = (_scaled(part.name, "elements[0]", g.elements[0], factor),
                          _scaled(part.name, "elements[1]", g.elements[1], factor))


def _scaled(part: str, key: str, count: int, factor: float, multiple: int = 1) -> int:
    value = count * factor
    if abs(value - round(value)) > 1e-9 or round(value) < 1 or round(value) % multiple:
        need = f"a whole number{f' and a multiple of {multiple}' if multiple > 1 else ''}"
        raise StudyError(f"mesh factor {factor:g} gives part '{part}' {key} = {value:g}, which must be {need}; "
                         "choose factors that keep every element count whole (1, 2, 4 ...)")
    return round(value)


def _positive(v: Any) -> str | None:
    return None if v > 0 else "must be above 0"


def _non_negative(v: Any) -> str | None:
    return None if v >= 0 else "must be 0 or more"


def _set_parts(key: str) -> Callable[[Scene, Any], None]:
    def apply(scene: Scene, value: Any) -> None:
        for part in scene.parts:
            setattr(part, key, value)
    return apply


def _set_contacts(key: str) -> Callable[[Scene, Any], None]:
    def apply(scene: Scene, value: Any) -> None:
        for contact in scene.contacts:
            setattr(contact, key, value)
    return apply


def _thickness_scale(scene: Scene) -> float | None:
    """The one thickness scale of every contact's two parts; None when they differ."""
    return _same([scale for c in scene.contacts for scale in c.thickness_scale])


def _set_thickness_scale(scene: Scene, value: float) -> None:
    for contact in scene.contacts:
        contact.thickness_scale = (value, value)


def _set_run(key: str) -> Callable[[Scene, Any], None]:
    return lambda scene, value: setattr(scene.run, key, value)


def _set_effect(switch: str) -> Callable[[Scene, Any], None]:
    def apply(scene: Scene, value: bool) -> None:
        if value:
            scene.run.effect_switches.pop(switch, None)   # on is the deck's default: the base deck, bitwise
        else:
            scene.run.effect_switches[switch] = "off"
    return apply


def _set_precision(scene: Scene, value: str) -> None:
    # double is the deck's default: the attribute left out, the base deck bitwise
    scene.run.precision = None if value == "double" else value


# the plane-stress return of J2 plasticity: exact (j2_plasticity) or radial (j2_radial, docs/theory.md)
PLASTIC_RETURNS = {"exact": "j2_plasticity", "radial": "j2_radial"}


def _plastic_return(scene: Scene) -> str | None:
    returns = {name for name, model in PLASTIC_RETURNS.items() for m in scene.materials if m.model == model}
    return returns.pop() if len(returns) == 1 else None


def _set_plastic_return(scene: Scene, value: str) -> None:
    for material in scene.materials:
        if material.model in PLASTIC_RETURNS.values():
            material.model = PLASTIC_RETURNS[value]


def _effect_knob(switch: str) -> Knob:
    return Knob(switch, bool, f"[effects] {switch}: false switches the effect off",
                lambda s: s.run.effect_switches.get(switch, "on") == "on", _set_effect(switch))


KNOBS: dict[str, Knob] = {k.name: k for k in [
    Knob("mesh", float, "factor on every generated part's element counts (1, 2, 4 ...)",
         lambda s: 1, _refine, _positive),
    Knob("time_step", float, "[run] time_step: a fixed step in s, 0 = automatic",
         lambda s: s.run.time_step, _set_run("time_step"), _non_negative),
    Knob("time_step_safety", float, "[run] time_step_safety: factor on the stable step, in (0, 1]",
         lambda s: s.run.time_step_safety, _set_run("time_step_safety"),
         lambda v: None if 0 < v <= 1 else "must lie in (0, 1]"),
    Knob("integration_points", int, "integration_points of every part, 1 to 9",
         lambda s: _same([p.integration_points for p in s.parts]), _set_parts("integration_points"),
         lambda v: None if 1 <= v <= 9 else "must be 1 to 9"),
    Knob("hourglass_form", str, f"hourglass_form of every part: {', '.join(HOURGLASS_FORMS)}",
         lambda s: _same([p.hourglass_form for p in s.parts]), _set_parts("hourglass_form"),
         lambda v: None if v in HOURGLASS_FORMS else f"must be one of {', '.join(HOURGLASS_FORMS)}"),
    Knob("hourglass_coefficient", float, "hourglass_coefficient of every part, >= 0",
         lambda s: _same([p.hourglass_coefficient for p in s.parts]), _set_parts("hourglass_coefficient"),
         _non_negative),
    Knob("element", str, f"element of every part (its quadrilaterals): {', '.join(SHELL_ELEMENTS)}",
         lambda s: _same([p.element for p in s.parts]), _set_parts("element"),
         lambda v: None if v in SHELL_ELEMENTS else f"must be one of {', '.join(SHELL_ELEMENTS)}"),
    Knob("plastic_return", str, "the plane-stress return of every J2 material: exact (j2_plasticity) or radial "
         "(j2_radial)", _plastic_return, _set_plastic_return,
         lambda v: None if v in PLASTIC_RETURNS else f"must be one of {', '.join(PLASTIC_RETURNS)}"),
    Knob("rotary_inertia", str, f"rotary_inertia of every part (its shells' nodal rotary inertia): "
         f"{', '.join(ROTARY_INERTIAS)}", lambda s: _same([p.rotary_inertia for p in s.parts]),
         _set_parts("rotary_inertia"),
         lambda v: None if v in ROTARY_INERTIAS else f"must be one of {', '.join(ROTARY_INERTIAS)}"),
    Knob("thickness_update", bool, "thickness_update of every part: the element's forces use its current thickness "
         "(LS-DYNA ISTUPD = 1; one-point quadrilaterals)", lambda s: _same([p.thickness_update for p in s.parts]),
         _set_parts("thickness_update")),
    Knob("warping_correction", bool, "warping_correction of every part",
         lambda s: _same([p.warping_correction for p in s.parts]), _set_parts("warping_correction")),
    Knob("penalty_scale", float, "penalty_scale of every [[contact]], > 0",
         lambda s: _same([c.penalty_scale for c in s.contacts]), _set_contacts("penalty_scale"), _positive,
         needs="contact"),
    Knob("contact_thickness_scale", float, "thickness_scale of every [[contact]] (both parts), in (0, 10]: the "
         "contact surfaces sit scale t / 2 off each mid-surface", _thickness_scale, _set_thickness_scale,
         lambda v: None if 0 < v <= 10 else "must lie in (0, 10]", needs="contact"),
    Knob("symmetric", bool, "symmetric of every [[contact]]: true both passes, false swapped passes",
         lambda s: _same([c.symmetric for c in s.contacts]), _set_contacts("symmetric"), needs="contact"),
    Knob("contact_sort_interval", int, "[run] contact_sort_interval: cycles between bucket sorts, 0 = automatic",
         lambda s: int(s.run.contact_sort_interval), _set_run("contact_sort_interval"), _non_negative,
         needs="contact"),
    Knob("contact_closing_limit", float, "[run] contact_closing_limit: the most a pair of contact surfaces near "
         "each other may close in a step, as a fraction of the thinner wall (automatic; 0 = off)",
         lambda s: s.run.contact_closing_limit, _set_run("contact_closing_limit"),
         lambda v: None if 0 <= v < 1 else "must lie in [0, 1)", needs="contact"),
    Knob("contact_travel_limit", float, "[run] contact_travel_limit: the most a contact may close in a step, "
         "as a fraction of the thinner wall; 0 = off", lambda s: s.run.contact_travel_limit,
         _set_run("contact_travel_limit"), lambda v: None if 0 <= v < 1 else "must lie in [0, 1)", needs="contact"),
    Knob("precision", str, f"[run] precision: {', '.join(PRECISIONS)} (the element kernel in single, "
         "a second engine)", lambda s: s.run.precision or "double", _set_precision,
         lambda v: None if v in PRECISIONS else f"must be one of {', '.join(PRECISIONS)}"),
    *[_effect_knob(switch) for switch in _schema.EFFECT_SWITCHES],
]}
# Knobs the issue asks for that the engine does not offer today (none now): asking for one is an
# error that says why
UNAVAILABLE: dict[str, str] = {}


def knob(name: str) -> Knob:
    """The knob called ``name``; a StudyError naming the knobs there are otherwise."""
    if name in UNAVAILABLE:
        raise StudyError(f"knob '{name}' is not available: {UNAVAILABLE[name]}")
    if name not in KNOBS:
        raise StudyError(f"unknown knob '{name}'; {did_you_mean(name, KNOBS)}the knobs are: {', '.join(KNOBS)}")
    return KNOBS[name]


def check_value(name: str, value: Any, scene: Scene) -> Value:
    """``value`` as knob ``name`` takes it (an int for an int knob ...); a StudyError if it cannot be."""
    k = knob(name)
    if k.needs == "contact" and not scene.contacts:
        raise StudyError(f"knob '{name}' needs a [[contact]] in the scene, and {scene.path} has none")
    if k.kind is float and isinstance(value, int) and not isinstance(value, bool):
        value = float(value)
    if not isinstance(value, k.kind) or (k.kind is int and isinstance(value, bool)):
        raise StudyError(f"knob '{name}' takes {k.kind.__name__} values ({k.meaning}), got {value!r}")
    problem = k.check(value)
    if problem:
        raise StudyError(f"knob '{name}' = {value!r} {problem} ({k.meaning})")
    return value


def base_values(scene: Scene) -> dict[str, Value | None]:
    """The scene's own value of every knob (None where its parts or contacts differ)."""
    return {name: k.base(scene) for name, k in KNOBS.items()}


def normalise(values: Mapping[str, Value], base: Mapping[str, Value | None]) -> Config:
    """A configuration: the values that differ from the base, in the order of :data:`KNOBS`."""
    return tuple((name, values[name]) for name in KNOBS if name in values and values[name] != base[name])


def label(config: Config) -> str:
    """``base`` or ``mesh=2, integration_points=3``."""
    return ", ".join(f"{name}={value:g}" if isinstance(value, float) else f"{name}={value}"
                     for name, value in config) or "base"


def apply(scene: Scene, config: Config) -> Scene:
    """A copy of ``scene`` with the configuration's knob values set."""
    variant = copy.deepcopy(scene)
    for name, value in config:
        KNOBS[name].apply(variant, value)
    return variant


@dataclass
class Design:
    """How the knob values combine: ``kind`` one of :data:`DESIGNS`; ``knobs`` knob -> values for
    ``one_at_a_time`` and ``grid``; ``runs`` the configurations of ``list``."""

    kind: str = "one_at_a_time"
    knobs: dict[str, list[Value]] = field(default_factory=dict)
    runs: list[dict[str, Value]] = field(default_factory=list)

    def configurations(self, scene: Scene) -> list[Config]:
        """The configurations, base first, each once; checks every knob and value against the scene."""
        if self.kind not in DESIGNS:
            raise StudyError(f"unknown design '{self.kind}'; {did_you_mean(self.kind, DESIGNS)}choose one of "
                             f"{', '.join(DESIGNS)}")
        knobs = {name: [check_value(name, v, scene) for v in values] for name, values in self.knobs.items()}
        runs = [{n: check_value(n, v, scene) for n, v in run.items()} for run in self.runs]
        if self.kind == "list":
            if knobs:
                raise StudyError("a 'list' design takes its configurations from runs, not knobs; "
                                 "give runs, or use design one_at_a_time or grid")
            wanted = runs
        else:
            if runs:
                raise StudyError(f"a '{self.kind}' design takes knobs, not runs; use design 'list' for runs")
            if not knobs:
                raise StudyError("the study turns no knob; give knobs (--knob mesh=1,2,4, or [study.knobs])")
            if self.kind == "grid":
                wanted = [dict(zip(knobs, combo, strict=True)) for combo in itertools.product(*knobs.values())]
            else:
                wanted = [{name: v} for name, values in knobs.items() for v in values]
        base = base_values(scene)
        configs: list[Config] = [()]
        for values in wanted:
            config = normalise(values, base)
            if config not in configs:
                configs.append(config)
        return configs
