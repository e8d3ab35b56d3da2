"""Pictures of a pyvista grid coloured by one of its fields: off screen to a PNG, or in a window.

This module knows grids, not results files: :meth:`paradyn.reading.Results.plot` and
:func:`paradyn.plots.render_deformed` hand it a frame's grid and a caption, so neither the reader
nor the plots need the other to draw.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from . import offscreen
from .atomic_write import replacing

SCALAR_TITLES = {
    "plastic_strain": "effective plastic strain",
    "von_mises": "von Mises stress (Pa)",
    "membrane_stress": "membrane stress magnitude (Pa)",
    "displacement": "displacement magnitude (m)",
    "velocity": "velocity magnitude (m/s)",
    "part": "part",
}


@dataclass
class Picture:
    """What to draw: a grid (``pyvista.UnstructuredGrid``), the field that colours it, a caption."""

    grid: Any
    scalars: str
    caption: str

    def check(self) -> None:
        """Raise ValueError naming the fields to choose from when ``scalars`` is not one."""
        grid = self.grid
        if self.scalars not in grid.cell_data and self.scalars not in grid.point_data:
            available = sorted({*grid.cell_data.keys(), *grid.point_data.keys()})
            raise ValueError(f"no field {self.scalars!r} to colour by; choose one of {available}")


def _plotter(
    picture: Picture, off_screen: bool, window_size: tuple[int, int], show_edges: bool, cmap: str
) -> Any:
    import pyvista as pv

    picture.check()
    plotter = pv.Plotter(off_screen=off_screen, window_size=list(window_size))
    plotter.add_mesh(
        picture.grid,
        scalars=picture.scalars,
        preference="cell",
        cmap=cmap,
        show_edges=show_edges,
        scalar_bar_args={"title": SCALAR_TITLES.get(picture.scalars, picture.scalars)},
    )
    plotter.add_text(picture.caption, font_size=10)
    plotter.view_isometric()
    plotter.reset_camera()
    return plotter


def render(
    picture: Picture,
    path: str | Path,
    window_size: tuple[int, int] = (1200, 900),
    show_edges: bool = True,
    cmap: str = "viridis",
) -> Path:
    """Write ``picture`` as a PNG at ``path`` (off screen, no display needed); return the path."""
    import pyvista as pv

    offscreen.prepare()   # no display: EGL directly, without VTK's "bad X server connection"

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    pv.OFF_SCREEN = True
    plotter = _plotter(picture, True, window_size, show_edges, cmap)
    try:
        with replacing(path) as temporary:
            plotter.screenshot(str(temporary))
    finally:
        plotter.close()
    return path


def show(
    picture: Picture,
    window_size: tuple[int, int] = (1200, 900),
    show_edges: bool = True,
    cmap: str = "viridis",
) -> None:
    """Open an interactive window with ``picture`` (needs a display)."""
    plotter = _plotter(picture, False, window_size, show_edges, cmap)
    plotter.show()
