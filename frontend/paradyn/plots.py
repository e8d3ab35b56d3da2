"""Pictures of ParaDyn results that work without a display.

matplotlib is used through its Agg canvas directly (no pyplot, so the caller's backend is left
alone); pyvista renders off screen (:mod:`paradyn.rendering`). This module reads results through
:mod:`paradyn.reading` only.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from . import rendering
from .atomic_write import replacing
from .reading import ENERGY_NAMES, TRACKED_COMPONENTS, Results

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


def _figure(title: str) -> tuple[Figure, Any]:
    fig = Figure(figsize=(8, 5), dpi=120)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    return fig, ax


def _save(fig: Figure, path: str | Path) -> Path:
    path = Path(path)
    fig.tight_layout()
    with replacing(path) as temporary:
        fig.savefig(temporary, format="png")
    return path


def plot_tracked_histories(results: Results, path: str | Path, component: str = "dz") -> Path:
    """PNG with one line per tracked point: ``component`` (dx..dz in mm, vx..vz in m/s) vs ms."""
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
    return _save(fig, path)


def plot_energies(results: Results, path: str | Path) -> Path:
    """PNG of kinetic, internal, hourglass, contact energy, external work and total (J) vs ms."""
    fig, ax = _figure(f"{results.title or results.path.stem}: energies")
    h = results.history
    t_ms = h["time"] * 1e3
    for name in ENERGY_NAMES:
        ax.plot(t_ms, h[name], label=_ENERGY_LABELS[name])
    ax.plot(t_ms, results.total_energy(), "k--", label="total (KE+IE+HG+contact-W)")
    ax.legend(loc="best", fontsize="small")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("energy (J)")
    return _save(fig, path)


def plot_parts(results: Results, path: str | Path) -> Path:
    """PNG of each part's kinetic and internal energy (J), and of each contact definition's force
    magnitude on its first part (N), vs ms (LS-DYNA's MATSUM and RCFORC)."""
    h = results.history
    t_ms = h["time"] * 1e3
    n_contacts = h["contact_force"].shape[1]
    fig = Figure(figsize=(8, 8 if n_contacts else 5), dpi=120)
    FigureCanvasAgg(fig)
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
    return _save(fig, path)


def render_deformed(
    results: Results,
    path: str | Path,
    frame: int = -1,
    scalars: str = "plastic_strain",
    window_size: tuple[int, int] = (1200, 900),
    show_edges: bool = True,
    cmap: str = "viridis",
) -> Path:
    """PNG of all parts at frame ``frame`` (deformed), coloured by ``scalars``, off screen."""
    picture = rendering.Picture(results.frame(frame), scalars, results.caption(frame))
    return rendering.render(picture, path, window_size, show_edges, cmap)


def show_deformed(
    results: Results,
    frame: int = -1,
    scalars: str = "plastic_strain",
    window_size: tuple[int, int] = (1200, 900),
    show_edges: bool = True,
    cmap: str = "viridis",
) -> None:
    """Interactive window of :func:`render_deformed`'s picture (needs a display)."""
    picture = rendering.Picture(results.frame(frame), scalars, results.caption(frame))
    rendering.show(picture, window_size, show_edges, cmap)


__all__ = [
    "plot_energies",
    "plot_parts",
    "plot_tracked_histories",
    "render_deformed",
    "show_deformed",
]
