"""Pictures of ParaDyn results that work without a display.

matplotlib is used through its Agg canvas directly (no pyplot, so the caller's backend is left
alone); pyvista renders off screen.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from .results import ENERGY_NAMES, TRACKED_COMPONENTS, Results

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
_SCALAR_TITLES = {
    "plastic_strain": "effective plastic strain",
    "von_mises": "von Mises stress (Pa)",
    "membrane_stress": "membrane stress magnitude (Pa)",
    "displacement": "displacement magnitude (m)",
    "velocity": "velocity magnitude (m/s)",
    "part": "part",
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
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, format="png")
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


def _plotter_with_frame(
    results: Results,
    frame: int,
    scalars: str,
    off_screen: bool,
    window_size: tuple[int, int],
    show_edges: bool,
    cmap: str,
) -> Any:
    import pyvista as pv

    grid = results.frame(frame)
    if scalars not in grid.cell_data and scalars not in grid.point_data:
        available = sorted({*grid.cell_data.keys(), *grid.point_data.keys()})
        raise ValueError(f"no field {scalars!r} to colour by; choose one of {available}")
    t = results.frame_times[results.frame_index(frame)]
    plotter = pv.Plotter(off_screen=off_screen, window_size=list(window_size))
    plotter.add_mesh(
        grid,
        scalars=scalars,
        preference="cell",
        cmap=cmap,
        show_edges=show_edges,
        scalar_bar_args={"title": _SCALAR_TITLES.get(scalars, scalars)},
    )
    plotter.add_text(
        f"{results.title or results.path.stem}   t = {t * 1e3:.3f} ms", font_size=10
    )
    plotter.view_isometric()
    plotter.reset_camera()
    return plotter


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
    import pyvista as pv

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    pv.OFF_SCREEN = True
    plotter = _plotter_with_frame(results, frame, scalars, True, window_size, show_edges, cmap)
    try:
        plotter.screenshot(str(path))
    finally:
        plotter.close()
    return path


def show_deformed(
    results: Results,
    frame: int = -1,
    scalars: str = "plastic_strain",
    window_size: tuple[int, int] = (1200, 900),
    show_edges: bool = True,
    cmap: str = "viridis",
) -> None:
    """Interactive window of :func:`render_deformed`'s picture (needs a display)."""
    plotter = _plotter_with_frame(results, frame, scalars, False, window_size, show_edges, cmap)
    plotter.show()


__all__ = [
    "plot_tracked_histories",
    "plot_energies",
    "render_deformed",
    "show_deformed",
]
