"""Post-processing of a finished run: the files ``paradyn-run`` writes beside ``results.h5``.

docs/outputs.md describes them: the VTK time series, ``history.csv``, ``summary.json`` and the
pictures. :func:`post_process` writes the ones asked for and says where they went.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .reading import Results
from .reports import write_history_csv, write_summary
from .vtkhdf_export import write_vtkhdf


def post_process(
    results: Results,
    out_dir: str | Path,
    extra: dict[str, Any] | None = None,
    *,
    vtk: bool = True,
    history: bool = True,
    summary: bool = True,
    plots: bool = False,
    vtk_series: bool = False,
) -> dict[str, Path]:
    """Write the outputs of a run into ``out_dir``; return them as label -> path.

    Parameters
    ----------
    results : Results
        The run, as :func:`paradyn.read` opened it.
    out_dir : str or Path
        Where the outputs go (usually the folder of ``results.h5``).
    extra : dict, optional
        Entries merged last into ``summary.json``.
    vtk, history, summary : bool
        Write every frame of every part in ``results.vtkhdf``, ``history.csv`` and
        ``summary.json`` (all three by default).
    plots : bool
        Also draw the pictures (``energies.png``, ``parts.png``, ``tracked.png`` when there are
        tracked points, ``deformed.png``); off by default: they cost about 2 s on the pipe whip,
        seven times its time loop (docs/outputs.md, "What a run writes by default").
    vtk_series : bool
        Also write a ``.pvd`` series per part (``vtk/<part>_NNNNN.vtu``), for ParaView before 5.12
        and other readers without VTKHDF; off by default (``vtk=False`` skips it too).

    Returns
    -------
    dict of str to Path
        ``"results"`` first, then every file written, in the order written.
    """
    out_dir = Path(out_dir)
    outputs: dict[str, Path] = {"results": results.path}
    if vtk and vtk_series:
        from .vtk_export import write_vtk_series

        for pvd in write_vtk_series(results, out_dir):
            outputs[f"vtk {pvd.stem}"] = pvd
    if vtk:
        outputs["vtkhdf"] = write_vtkhdf(results, out_dir / "results.vtkhdf")
    if history:
        outputs["history"] = write_history_csv(results, out_dir / "history.csv")
    if summary:
        summary_path = out_dir / "summary.json"
        write_summary(results, summary_path, extra=extra)
        outputs["summary"] = summary_path
    if plots:
        from . import plots as plotting  # matplotlib and pyvista load only when pictures are asked for

        outputs["energies plot"] = plotting.plot_energies(results, out_dir / "energies.png")
        outputs["parts plot"] = plotting.plot_parts(results, out_dir / "parts.png")
        if results.n_tracked:
            outputs["tracked plot"] = plotting.plot_tracked_histories(results, out_dir / "tracked.png")
        outputs["deformed picture"] = plotting.render_deformed(results, out_dir / "deformed.png")
    return outputs
