"""Figures of ParaDyn results that work without a display: what :meth:`paradyn.Results.plot` returns.

Every ``*_figure`` function returns a :class:`NotebookFigure` (a matplotlib ``Figure`` that Jupyter
shows as the value of a cell); :mod:`paradyn.results.plots` writes them as the PNG files of docs/outputs.md.
matplotlib is used through its Agg canvas directly (no pyplot, so the caller's backend is left
alone); the deformed shape is drawn off screen by pyvista (:mod:`paradyn.results.rendering`), with the
displacements magnified by the factor :func:`displacement_scale` chooses, which the caption states.

The ``results`` argument is a :class:`paradyn.Results`; this module does not import
:mod:`paradyn.results.reading` (typed ``Any``), so that ``Results.plot`` can draw through it without an
import circle (tests/test_reading.py).
"""

from __future__ import annotations

import io
import math
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from . import rendering
from .layout import ENERGY_NAMES, TRACKED_COMPONENTS

_COMPONENT_LABELS = {
    "dx": ("displacement x", "mm", 1e3),
    "dy": ("displacement y", "mm", 1e3),
    "dz": ("displacement z", "mm", 1e3),
    "vx": ("velocity x", "m/s", 1.0),
    "vy": ("velocity y", "m/s", 1.0),
    "vz": ("velocity z", "m/s", 1.0),
}
_ENERGY_LABELS = {
    "kinetic_energy": "kinetic",
    "internal_energy": "internal",
    "hourglass_energy": "hourglass",
    "contact_energy": "contact",
    "external_work": "external work",
}
# the largest displacement is drawn at least this fraction of the model's bounding box diagonal
VISIBLE_FRACTION = 0.05


class NotebookFigure(Figure):
    """A matplotlib Figure on an Agg canvas that Jupyter shows as a PNG (``_repr_png_``) whatever
    the notebook's matplotlib backend; ``savefig`` and every other Figure method work as usual."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        FigureCanvasAgg(self)

    def _repr_png_(self) -> bytes:
        buffer = io.BytesIO()
        self.savefig(buffer, format="png")
        return buffer.getvalue()


def _figure(title: str) -> tuple[NotebookFigure, Any]:
    fig = NotebookFigure(figsize=(8, 5), dpi=120)
    ax = fig.add_subplot(1, 1, 1)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    return fig, ax


def parts_figure(results: Any) -> NotebookFigure:
    """Each part's internal (solid) and kinetic (dashed) energy in J, and each contact definition's
    force magnitude on its first part in N, against time in ms (LS-DYNA's MATSUM and RCFORC)."""
    h = results.history
    t_ms = h["time"] * 1e3
    n_contacts = h["contact_force"].shape[1]
    fig = NotebookFigure(figsize=(8, 8 if n_contacts else 5), dpi=120)
    energy = fig.add_subplot(2 if n_contacts else 1, 1, 1)
    energy.set_title(f"{results.title or results.path.stem}: energies per part")
    for i, name in enumerate(results.part_names[:h["part_kinetic_energy"].shape[1]]):
        line = energy.plot(t_ms, h["part_internal_energy"][:, i], label=f"{name} internal")[0]
        energy.plot(t_ms, h["part_kinetic_energy"][:, i], "--", color=line.get_color(), label=f"{name} kinetic")
    energy.set_ylabel("energy (J)")
    energy.legend(loc="best", fontsize="small")
    energy.grid(True, alpha=0.3)
    if n_contacts:
        force = fig.add_subplot(2, 1, 2, sharex=energy)
        for k in range(n_contacts):
            force.plot(t_ms, np.linalg.norm(h["contact_force"][:, k], axis=1), label=f"contact {k}")
        force.set_ylabel("contact force on the first part (N)")
        force.legend(loc="best", fontsize="small")
        force.grid(True, alpha=0.3)
    fig.axes[-1].set_xlabel("time (ms)")
    return fig


def tracked_figure(results: Any, component: str = "dz") -> NotebookFigure:
    """One line per tracked point: ``component`` (dx..dz in mm, vx..vz in m/s) against time in ms."""
    if component not in _COMPONENT_LABELS:
        raise ValueError(
            f"component {component!r} is not one of {', '.join(TRACKED_COMPONENTS)}"
        )
    label, unit, scale = _COMPONENT_LABELS[component]
    data = results.history[
        "tracked_displacement" if component.startswith("d") else "tracked_velocity"
    ]
    axis = "xyz".index(component[1])
    fig, ax = _figure(f"{results.title or results.path.stem}: tracked points, {label}")
    t_ms = results.history["time"] * 1e3
    for i, name in enumerate(results.tracked_names):
        ax.plot(t_ms, data[:, i, axis] * scale, label=name)
    if results.n_tracked:
        ax.legend(loc="best", fontsize="small")
    else:
        ax.text(0.5, 0.5, "no tracked points in this run", transform=ax.transAxes, ha="center")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel(f"{label} ({unit})")
    return fig


def energies_figure(results: Any) -> NotebookFigure:
    """Kinetic, internal, hourglass, contact energy, external work and total (J) against time (ms)."""
    fig, ax = _figure(f"{results.title or results.path.stem}: energies")
    h = results.history
    t_ms = h["time"] * 1e3
    for name in ENERGY_NAMES:
        ax.plot(t_ms, h[name], label=_ENERGY_LABELS[name])
    ax.plot(t_ms, results.total_energy(), "k--", label="total (KE+IE+HG+contact-W)")
    ax.legend(loc="best", fontsize="small")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("energy (J)")
    return fig


def displacement_scale(coordinates: np.ndarray, displacement: np.ndarray,
                       fraction: float = VISIBLE_FRACTION) -> float:
    """The factor that magnifies ``displacement`` until its largest one is at least ``fraction`` of
    the bounding box diagonal of ``coordinates``: 1 when it already is (or nothing moved), else
    the smallest of 1, 2, 5 x 10^k that does it, so the caption states a round number.

    Examples
    --------
    A 2 m pipe with a 3 mm dent: the dent is drawn 50 times larger, 0.15 m, 7.5 % of the 2 m.

    >>> import numpy as np
    >>> nodes = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    >>> displacement_scale(nodes, np.array([[0.0, 0.0, 0.0], [0.0, -0.003, 0.0]]))
    50.0
    >>> displacement_scale(nodes, np.array([[0.0, 0.0, 0.0], [0.0, -0.3, 0.0]]))   # visible as it is
    1.0
    """
    size = float(np.linalg.norm(np.ptp(coordinates, axis=0))) if len(coordinates) else 0.0
    peak = float(np.max(np.linalg.norm(displacement, axis=1))) if len(displacement) else 0.0
    if peak == 0.0 or peak >= fraction * size:
        return 1.0
    needed = fraction * size / peak
    decade = 10.0 ** math.floor(math.log10(needed))
    return next(m * decade for m in (1.0, 2.0, 5.0, 10.0) if m * decade >= needed)


def deformed_picture(results: Any, frame: int = -1, scalars: str = "plastic_strain",
                     scale: float | None = None) -> rendering.Picture:
    """All parts at frame ``frame``, displacements times ``scale`` (None: :func:`displacement_scale`),
    coloured by ``scalars``; the caption gives the title, the time and the factor."""
    grid = results.frame(frame, deformed=False)
    displacement = np.asarray(grid.point_data["displacement"])
    if scale is None:
        scale = displacement_scale(np.asarray(grid.points), displacement)
    grid.points = np.asarray(grid.points) + scale * displacement
    shown = "true scale" if scale == 1.0 else f"displacements x {scale:g}"
    return rendering.Picture(grid, scalars, f"{results.caption(frame)}   {shown}")


def deformed_figure(results: Any, frame: int = -1, scalars: str = "plastic_strain",
                    scale: float | None = None, show_edges: bool | None = None) -> NotebookFigure:
    """:func:`deformed_picture` drawn off screen, in a matplotlib figure."""
    picture = deformed_picture(results, frame, scalars, scale)
    fig = NotebookFigure(figsize=(8, 6), dpi=150)
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    ax.imshow(rendering.image(picture, show_edges=show_edges))
    ax.set_axis_off()
    return fig


