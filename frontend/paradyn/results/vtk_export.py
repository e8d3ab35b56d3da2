"""ParaView and pyvista time series of a results file: one ``<part>.pvd`` per part, one
``vtk/<part>_<k:05d>.vtu`` per frame (docs/outputs.md, "VTK time series")."""

from __future__ import annotations

import re
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from paradyn.atomic_write import replacing, write_text_atomic

from . import grids
from .names import unique_safe_names
from .reading import Results, ResultsError


def write_vtk_series(results: Results, out_dir: str | Path) -> list[Path]:
    """Write one ParaView time series per part; return the ``.pvd`` paths.

    Layout: ``out_dir/<part>.pvd`` referencing ``out_dir/vtk/<part>_<k:05d>.vtu`` (binary,
    VTK_QUAD cells at the deformed position).  Old ``vtk/<part>_#####.vtu`` files of the same
    parts are removed first, so a shorter re-run leaves no stale frames.  Parts without
    elements get no series.  Frames are read from the results file one at a time.

    Examples
    --------
    >>> import paradyn
    >>> from paradyn.results.vtk_export import write_vtk_series
    >>> write_vtk_series(paradyn.read("runs/pipe_whip/results.h5"), "runs/pipe_whip")  # doctest: +SKIP
    [PosixPath('runs/pipe_whip/lower_pipe.pvd'), PosixPath('runs/pipe_whip/upper_pipe.pvd')]
    """
    out_dir = Path(out_dir)
    vtk_dir = out_dir / "vtk"
    vtk_dir.mkdir(parents=True, exist_ok=True)
    if results.n_frames == 0:
        raise ResultsError(f"{results.path} holds no field frames; there is nothing to write")
    series: dict[str, grids.Topology] = {}
    for part, stem in enumerate(unique_safe_names(results.part_names, "part")):
        elements = np.flatnonzero(results.element_part == part)
        if elements.size == 0:
            continue
        _remove_stale_frames(vtk_dir, stem)
        series[stem] = grids.topology(
            results.coordinates, results.connectivity, results.element_part, elements, results.ids())
    files: dict[str, list[str]] = {stem: [] for stem in series}
    for k in range(results.n_frames):
        frame = results.frame_arrays(k)  # one read of the frame serves every part
        for stem, topo in series.items():
            grids.fill_frame(topo.grid, topo, results.coordinates, frame, deformed=True)
            vtu = vtk_dir / f"{stem}_{k:05d}.vtu"
            with replacing(vtu) as temporary:
                topo.grid.save(temporary, binary=True)
            files[stem].append(vtu.relative_to(out_dir).as_posix())
    pvds = []
    for stem in series:
        pvds.append(write_text_atomic(out_dir / f"{stem}.pvd", _pvd_xml(results.time_values, files[stem])))
    return pvds


def _remove_stale_frames(vtk_dir: Path, stem: str) -> None:
    pattern = re.compile(re.escape(stem) + r"_\d{5}\.vtu")
    for old in vtk_dir.glob(f"{stem}_*.vtu"):
        if pattern.fullmatch(old.name):
            old.unlink()


def _pvd_xml(times: np.ndarray, files: list[str]) -> str:
    """PVD collection: one DataSet per frame; one part per file, so part is always 0."""
    lines = [
        '<?xml version="1.0"?>',
        '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
        "  <Collection>",
    ]
    for t, f in zip(times.tolist(), files, strict=True):
        lines.append(
            f'    <DataSet timestep="{float(t)!r}" group="" part="0" file={quoteattr(f)}/>'
        )
    lines += ["  </Collection>", "</VTKFile>", ""]
    return "\n".join(lines)
