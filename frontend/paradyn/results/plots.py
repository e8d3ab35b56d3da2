"""Pictures of ParaDyn results as PNG files, without a display (docs/outputs.md, "Pictures").

The figures are made by :mod:`paradyn.results.figures` (what :meth:`paradyn.Results.plot` returns); this
module writes them, each through a temporary file renamed at the end (:mod:`paradyn.atomic_write`).
"""

from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

from paradyn.atomic_write import replacing

from . import rendering
from .figures import deformed_picture, energies_figure, parts_figure, tracked_figure
from .reading import Results


def _save(fig: Figure, path: str | Path) -> Path:
    path = Path(path)
    fig.tight_layout()
    with replacing(path) as temporary:
        fig.savefig(temporary, format="png")
    return path


def plot_tracked_histories(results: Results, path: str | Path, component: str = "dz") -> Path:
    """PNG of :func:`tracked_figure`."""
    return _save(tracked_figure(results, component), path)


def plot_energies(results: Results, path: str | Path) -> Path:
    """PNG of :func:`energies_figure`."""
    return _save(energies_figure(results), path)


def plot_parts(results: Results, path: str | Path) -> Path:
    """PNG of :func:`parts_figure`."""
    return _save(parts_figure(results), path)


def render_deformed(
    results: Results,
    path: str | Path,
    frame: int = -1,
    scalars: str = "plastic_strain",
    window_size: tuple[int, int] = (1200, 900),
    show_edges: bool | None = None,
    cmap: str = "viridis",
    scale: float | None = None,
) -> Path:
    """PNG of :func:`deformed_picture`, off screen (edges as :func:`paradyn.results.rendering.edges_shown`)."""
    picture = deformed_picture(results, frame, scalars, scale)
    return rendering.render(picture, path, window_size, show_edges, cmap)


def show_deformed(
    results: Results,
    frame: int = -1,
    scalars: str = "plastic_strain",
    window_size: tuple[int, int] = (1200, 900),
    show_edges: bool | None = None,
    cmap: str = "viridis",
    scale: float | None = None,
) -> None:
    """Interactive window of :func:`render_deformed`'s picture (needs a display)."""
    rendering.show(deformed_picture(results, frame, scalars, scale), window_size, show_edges, cmap)


__all__ = [
    "plot_energies",
    "plot_parts",
    "plot_tracked_histories",
    "render_deformed",
    "show_deformed",
]
