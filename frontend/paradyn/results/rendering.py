"""Pictures of a pyvista grid coloured by one of its fields: off screen to a PNG, or in a window.

This module knows grids, not results files: :mod:`paradyn.results.plots` hands it a frame's grid and a
caption, so neither the reader nor the plots need the other to draw. Off-screen rendering runs with
VTK's logging off (:func:`quiet`): without an X server VTK would print a "bad X server connection"
warning and then render off screen anyway.

Edges: drawn (thin, dark grey) on a grid of at most :data:`EDGE_LIMIT` cells, left out above it,
where on a 1200 x 900 picture they would cover the colours (``show_edges`` True or False forces it).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from paradyn.atomic_write import replacing

EDGE_LIMIT = 5000  # cells; about 15 x 15 pixels per element when a square mesh fills 1200 x 900

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


@contextlib.contextmanager
def quiet() -> Iterator[None]:
    """VTK's log off while drawing off screen (no "bad X server connection" warning)."""
    import pyvista as pv

    with pv.vtk_verbosity("off"):
        yield


def edges_shown(grid: Any, show_edges: bool | None) -> bool:
    """``show_edges``, or when None: edges on a grid of at most :data:`EDGE_LIMIT` cells."""
    return grid.n_cells <= EDGE_LIMIT if show_edges is None else show_edges


def _plotter(
    picture: Picture, off_screen: bool, window_size: tuple[int, int], show_edges: bool | None, cmap: str
) -> Any:
    import pyvista as pv

    picture.check()
    plotter = pv.Plotter(off_screen=off_screen, window_size=list(window_size))
    plotter.add_mesh(
        picture.grid,
        scalars=picture.scalars,
        preference="cell",
        cmap=cmap,
        show_edges=edges_shown(picture.grid, show_edges),
        edge_color="#404040",
        line_width=0.5,
        scalar_bar_args={"title": SCALAR_TITLES.get(picture.scalars, picture.scalars)},
    )
    plotter.add_text(picture.caption, font_size=10)
    plotter.view_isometric()
    plotter.reset_camera()
    plotter.camera.zoom(1.3)  # reset_camera leaves room for a sphere around the model; use more of the picture
    return plotter


def image(
    picture: Picture,
    window_size: tuple[int, int] = (1200, 900),
    show_edges: bool | None = None,
    cmap: str = "viridis",
) -> np.ndarray:
    """``picture`` drawn off screen (no display needed), as an RGB array (height, width, 3)."""
    with quiet():
        plotter = _plotter(picture, True, window_size, show_edges, cmap)
        try:
            return np.asarray(plotter.screenshot(return_img=True))
        finally:
            plotter.close()


def render(
    picture: Picture,
    path: str | Path,
    window_size: tuple[int, int] = (1200, 900),
    show_edges: bool | None = None,
    cmap: str = "viridis",
) -> Path:
    """Write ``picture`` as a PNG at ``path`` (off screen, no display needed); return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with quiet():
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
    show_edges: bool | None = None,
    cmap: str = "viridis",
) -> None:
    """Open an interactive window with ``picture`` (needs a display)."""
    plotter = _plotter(picture, False, window_size, show_edges, cmap)
    plotter.show()
