"""Read a ParaDyn results file into a :class:`Results` object.

Opening reads what is small: the mesh, the frame times, the history and the run's figures and
names. The frame fields (displacement, velocity, stresses, plastic strain: n_frames x n_nodes or
n_elements each) stay in the file and are read when asked for, one frame at a time:
``res.to_pyvista(k)`` (a pyvista grid, or one per part), ``res.frame_arrays(k)`` (numpy arrays) or
``res.displacement[k]``; ``res.to_dataframe()`` and ``res.plot()`` give the history as a pandas
table and matplotlib figures (docs/python.md). The file format is docs/formats.md, version 1; what each output means is
docs/outputs.md.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.lib.mixins import NDArrayOperatorsMixin

from paradyn._schema import HISTORY_UNITS

from . import grids, history_columns
from . import names as run_names
from .layout import (
    ENERGY_NAMES,
    FRAME_DATASETS,
    TRACKED_COMPONENTS,
    FrameArrays,
    IncompleteResultsError,
    ResultsError,
    check_header,
    frame_tails,
    open_results,
    read_frame_layout,
    read_frame_row,
    read_frame_rows,
    read_history,
    read_mesh,
    read_rows,
    read_run,
)

if TYPE_CHECKING:  # pyvista is imported lazily: it is slow to import and only needed for meshes
    import pyvista

    from paradyn.running.engine_process import EngineRun  # an annotation: the results do not import the runs

__all__ = [
    "ENERGY_NAMES", "TRACKED_COMPONENTS", "FrameArrays", "FrameField", "IncompleteResultsError",
    "Results", "ResultsError", "read",
]


class FrameField(NDArrayOperatorsMixin):
    """One frame field of a results file, shape (n_frames, ...), read from the file when used.

    ``field[k]`` (or ``field[k, nodes, 2]``) reads frame ``k`` only; any other index, numpy
    functions and arithmetic read every frame (``np.asarray(field)``). Nothing is kept in memory
    between two uses.
    """

    def __init__(self, path: Path, name: str, n_frames: int, tail: tuple[int, ...]) -> None:
        self.path = path
        self.name = name
        self.shape = (n_frames, *tail)
        self.dtype = np.dtype(np.float64)

    @property
    def ndim(self) -> int:
        return len(self.shape)

    def __len__(self) -> int:
        return self.shape[0]

    def __repr__(self) -> str:
        return f"FrameField({str(self.path)!r}, {FRAME_DATASETS[self.name]!r}, shape={self.shape})"

    def __iter__(self) -> Iterator[np.ndarray]:
        for k in range(len(self)):
            yield self.read(k)

    def __getitem__(self, key: Any) -> np.ndarray:
        first, rest = (key[0], key[1:]) if isinstance(key, tuple) and key else (key, ())
        if isinstance(first, (int, np.integer)):
            row = self.read(int(first))
            return row[rest] if rest else row
        return self.read_all()[key]

    def read(self, k: int) -> np.ndarray:
        """Frame ``k`` (negative counts from the end) as a float64 array."""
        n = len(self)
        if not -n <= k < n:
            raise IndexError(f"frame {k} does not exist: {self.path} holds {n} frames")
        with open_results(self.path) as h5:
            return read_frame_row(h5, self.name, k % n, self.shape[1:])

    def read_all(self) -> np.ndarray:
        """Every frame, as one float64 array of ``shape``."""
        with open_results(self.path) as h5:
            if FRAME_DATASETS[self.name] not in h5:   # a file written before the field
                return read_frame_rows(h5, self.name, 0, len(self), self.shape[1:])
            return read_rows(h5, FRAME_DATASETS[self.name], len(self), self.shape[1:], self.path)

    def __array__(self, dtype: Any = None, copy: bool | None = None) -> np.ndarray:
        data = self.read_all()
        return data if dtype is None else data.astype(dtype)

    def __array_ufunc__(self, ufunc: np.ufunc, method: str, *inputs: Any, **kwargs: Any) -> Any:
        arrays = tuple(x.read_all() if isinstance(x, FrameField) else x for x in inputs)
        return getattr(ufunc, method)(*arrays, **kwargs)


@dataclass(repr=False)
class Results:
    """A ParaDyn results file: SI units, indices 0-based.

    Read at open: ``coordinates`` (n_nodes, 3) m, ``connectivity`` (n_elements, 4),
    ``element_part`` (n_elements,), ``time_values`` (n_frames,) s (also ``frame_times``),
    ``history`` (``time`` (n_records,) s, the five energies (J), ``contact_penetration`` m,
    ``dt`` s (the step from each record on), ``dt_stable`` s (the mesh's stable step then) and
    ``dt_element`` (the 0-based id of the element with the smallest step, as float64),
    ``tracked_displacement`` and ``tracked_velocity`` (n_records, n_tracked, 3)) and ``run`` (the
    ``/run`` attributes, empty if the run stopped before writing them).

    Read on demand from the file at ``path``: ``displacement`` and ``velocity``
    (n_frames, n_nodes, 3) m, m/s, ``membrane_stress`` (n_frames, n_elements, 3) Pa (sxx, syy,
    sxy), ``von_mises`` (n_frames, n_elements) Pa, ``plastic_strain`` (n_frames, n_elements),
    ``thickness`` (n_frames, n_elements) m (the current shell thickness) and the other fields of
    docs/outputs.md, each a :class:`FrameField`; :meth:`frame_arrays` reads all of one frame at once.

    Names come from the results file, else from the deck (docs/outputs.md, "Names").
    ``engine_run`` and ``outputs`` are filled by :func:`paradyn.run`: how the engine ran and the
    files post-processing wrote (label -> path).

    Examples
    --------
    A free strip moving up at 1 m/s for 0.1 ms, run on one rank:

    >>> import paradyn
    >>> scene = paradyn.Scene("strip", end_time=1e-4, output_interval=2.5e-5)
    >>> scene.add_material("steel", model="elastic", density=7800.0, youngs_modulus=2e11, poisson_ratio=0.3)
    >>> scene.add_part("strip", material="steel", thickness=0.002, initial_velocity=[0.0, 0.0, 1.0],
    ...                geometry=paradyn.Plate(size=(0.1, 0.02), elements=(5, 1)))
    >>> scene.add_track("tip", part="strip", point=[0.1, 0.02, 0.0])
    >>> res = paradyn.run(scene, "runs/strip", ranks=1, threads=1, plots=False)
    >>> len(res.time_values), round(float(res.time_values[-1]) * 1e6)   # frames; the last one's time in µs
    (5, 100)
    >>> res.displacement[-1].shape                          # the last frame, read from results.h5 now
    (12, 3)
    >>> grid = res.to_pyvista(-1)                           # a pyvista.UnstructuredGrid, deformed
    >>> grid.n_cells, sorted(grid.cell_data.keys())[:6]
    (5, ['element_id', 'file_element_id', 'file_part_id', 'internal_energy_density', 'layer_stress', 'membrane_strain'])
    >>> history = res.to_dataframe()                        # a pandas.DataFrame when pandas is installed
    >>> round(float(history["tip_dz"].to_numpy()[-1]) * 1e3, 3)   # mm
    0.1
    >>> fig = res.plot("energies")                          # a matplotlib Figure; Jupyter shows it
    >>> res.outputs["vtkhdf"].name                          # every frame in one file, for ParaView
    'results.vtkhdf'
    """

    path: Path
    version: int
    complete: bool
    coordinates: np.ndarray
    connectivity: np.ndarray
    element_part: np.ndarray
    time_values: np.ndarray
    history: dict[str, np.ndarray]
    run: dict[str, Any]
    part_names: list[str]
    tracked_names: list[str]
    title: str = ""
    tracked_nodes: np.ndarray | None = None
    end_time: float | None = None
    deck_path: Path | None = None
    effects_written: list[str] | None = None
    effect_table: list[run_names.EffectRow] = field(default_factory=list)
    file_ids: dict[str, np.ndarray] = field(default_factory=dict)   # the mesh file's ids (deck /nodes/id, ...)
    engine_run: EngineRun | None = None
    outputs: dict[str, Path] = field(default_factory=dict)
    displacement: FrameField = field(init=False, compare=False)
    velocity: FrameField = field(init=False, compare=False)
    membrane_stress: FrameField = field(init=False, compare=False)
    von_mises: FrameField = field(init=False, compare=False)
    plastic_strain: FrameField = field(init=False, compare=False)
    acceleration: FrameField = field(init=False, compare=False)
    nodal_contact_force: FrameField = field(init=False, compare=False)
    layer_stress: FrameField = field(init=False, compare=False)
    membrane_strain: FrameField = field(init=False, compare=False)
    internal_energy_density: FrameField = field(init=False, compare=False)
    surface_strain: FrameField = field(init=False, compare=False)
    thickness: FrameField = field(init=False, compare=False)
    _grid_cache: dict[Any, grids.Topology] = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        tails = frame_tails(self.n_nodes, self.n_elements)
        for name in FRAME_DATASETS:
            setattr(self, name, FrameField(self.path, name, self.n_frames, tails[name]))

    def __repr__(self) -> str:
        state = "complete" if self.complete else "INCOMPLETE"
        return (
            f"Results({str(self.path)!r}, {state}, title={self.title!r}, "
            f"nodes={self.n_nodes}, elements={self.n_elements}, parts={self.part_names}, "
            f"frames={self.n_frames}, history_records={self.n_records}, "
            f"tracked={self.tracked_names})"
        )

    # ---- sizes -------------------------------------------------------------------------------
    @property
    def n_nodes(self) -> int:
        return int(self.coordinates.shape[0])

    @property
    def n_elements(self) -> int:
        return int(self.connectivity.shape[0])

    @property
    def n_parts(self) -> int:
        return len(self.part_names)

    @property
    def n_frames(self) -> int:
        return int(self.time_values.shape[0])

    @property
    def n_records(self) -> int:
        return int(self.history["time"].shape[0])

    @property
    def n_tracked(self) -> int:
        return int(self.history["tracked_displacement"].shape[1])

    @property
    def frame_times(self) -> np.ndarray:
        """The frame times (s); the same array as ``time_values``."""
        return self.time_values

    @property
    def effects(self) -> list[str]:
        """The effects that ran, in the order of the step, as the engine wrote them (the engine
        alone decides what a deck declares; empty for a run that did not finish writing them).
        :attr:`effect_table` has their counters and the effects the scene switched off."""
        return list(self.effects_written or [])

    # ---- frames ------------------------------------------------------------------------------
    def frame_index(self, k: int) -> int:
        """Normalise a frame index (negative counts from the end); raise if out of range."""
        if self.n_frames == 0:
            raise IndexError(f"{self.path} holds no field frames (the run wrote none)")
        if not -self.n_frames <= k < self.n_frames:
            raise IndexError(
                f"frame {k} does not exist: {self.path} holds {self.n_frames} frames "
                f"(indices 0..{self.n_frames - 1}, or negative from the end)"
            )
        return k % self.n_frames

    def frame_arrays(self, k: int = -1) -> FrameArrays:
        """Every field of frame ``k`` (negative counts from the end), read from the file now."""
        k = self.frame_index(k)
        tails = frame_tails(self.n_nodes, self.n_elements)
        with open_results(self.path) as h5:
            rows = {name: read_frame_row(h5, name, k, tails[name]) for name in FRAME_DATASETS}
        return FrameArrays(index=k, time=float(self.time_values[k]), **rows)

    def part_index(self, part: int | str) -> int:
        """Part index from an index or a part name."""
        if isinstance(part, str):
            if part not in self.part_names:
                raise KeyError(f"no part named {part!r}; the parts are {self.part_names}")
            return self.part_names.index(part)
        if not 0 <= part < self.n_parts:
            raise IndexError(f"part {part} does not exist; parts are 0..{self.n_parts - 1}")
        return int(part)

    def part_elements(self, part: int | str) -> np.ndarray:
        """Global indices of the elements of a part (index or name)."""
        return np.flatnonzero(self.element_part == self.part_index(part))

    def ids(self) -> grids.FileIds:
        """The ids of the nodes, elements and parts in the mesh file the model came from (a
        keyword deck's NID, EID, PID, a gmsh file's tags; 0 for parts that came from no file);
        the 1-based row numbers where the deck holds none."""
        rows = {"node": self.n_nodes, "element": self.n_elements, "part": self.n_parts}
        ids = {}
        for kind, n in rows.items():
            stored = self.file_ids.get(kind)
            ids[kind] = stored if stored is not None and stored.shape == (n,) else np.arange(1, n + 1)
        return grids.FileIds(**ids)

    def frame(
        self, k: int = -1, part: int | str | None = None, deformed: bool = True
    ) -> pyvista.UnstructuredGrid:
        """Field frame ``k`` as a pyvista grid of VTK_QUAD cells, read from the file now.

        Points are at the deformed position (``deformed=False``: the initial one); point data
        ``displacement``, ``velocity``, ``node_id``, ``file_node_id``; cell data ``membrane_stress``,
        ``von_mises``, ``plastic_strain``, ``part``, ``element_id``, ``file_element_id``,
        ``file_part_id`` (docs/outputs.md).  The field data
        ``TimeValue`` holds the frame time.  ``part`` restricts the grid to one part.
        """
        arrays = self.frame_arrays(k)
        key = ("all",) if part is None else ("part", self.part_index(part))
        if key not in self._grid_cache:
            elements = np.arange(self.n_elements) if part is None else self.part_elements(part)
            self._grid_cache[key] = grids.topology(
                self.coordinates, self.connectivity, self.element_part, elements, self.ids())
        topo = self._grid_cache[key]
        grid = topo.grid.copy(deep=True)
        grids.fill_frame(grid, topo, self.coordinates, arrays, deformed)
        return grid

    def iter_frames(self) -> Iterator[FrameArrays]:
        """Every frame's arrays in turn, each read from the file when reached."""
        for k in range(self.n_frames):
            yield self.frame_arrays(k)

    def to_pyvista(
        self, frame: int = -1, *, by_part: bool = False, deformed: bool = True
    ) -> pyvista.UnstructuredGrid | pyvista.MultiBlock:
        """Frame ``frame`` as :meth:`frame`'s grid of all parts, or with ``by_part`` a
        ``pyvista.MultiBlock`` of one grid per part, named by the part names (parts without
        elements left out). ``.plot()`` on either opens pyvista's interactive window."""
        if not by_part:
            return self.frame(frame, deformed=deformed)
        import pyvista as pv

        blocks = pv.MultiBlock()
        for index, name in enumerate(self.part_names):
            if np.any(self.element_part == index):
                blocks[name] = self.frame(frame, part=index, deformed=deformed)
        return blocks

    def plot(self, kind: str = "energies", **options: Any) -> Any:
        """A matplotlib figure (Jupyter shows it; ``.savefig(path)`` writes it).

        ``kind``: ``"energies"`` (against time), ``"tracked"`` (``component="dz"``: dx..vz of every
        tracked point) or ``"deformed"`` (``frame=-1``, ``scalars="plastic_strain"``, ``scale=None``:
        a displacement factor chosen so the largest displacement is visible, named in the caption).
        See :mod:`paradyn.results.figures`.
        """
        from . import figures as made

        figures = {"energies": made.energies_figure, "tracked": made.tracked_figure,
                   "deformed": made.deformed_figure}
        if kind not in figures:
            raise ValueError(f"no plot kind {kind!r}; choose one of {', '.join(figures)}")
        return figures[kind](self, **options)

    def caption(self, frame: int = -1) -> str:
        """The title and time of a frame, as the pictures print it."""
        t = self.time_values[self.frame_index(frame)]
        return f"{self.title or self.path.stem}   t = {t * 1e3:.3f} ms"

    # ---- history -----------------------------------------------------------------------------
    def total_energy(self) -> np.ndarray:
        """kinetic + internal + hourglass + contact - external_work, per history record (J)."""
        h = self.history
        return (
            h["kinetic_energy"]
            + h["internal_energy"]
            + h["hourglass_energy"]
            + h["contact_energy"]
            - h["external_work"]
        )

    def tracked_columns(self) -> list[str]:
        """Column-safe tracked point names (unique, no commas or blanks)."""
        return run_names.unique_safe_names(self.tracked_names, "tracked")

    def history_units(self) -> dict[str, str]:
        """The unit of every column of :meth:`history_table` (schema/results.toml; ``-``: none)."""
        units = {name: HISTORY_UNITS[name] for name in ("time", *ENERGY_NAMES)}
        units["total_energy"] = HISTORY_UNITS["kinetic_energy"]
        units |= {name: HISTORY_UNITS[name] for name in ("contact_penetration", "dt", "dt_stable", "dt_element")}
        units |= {column: HISTORY_UNITS[name] for column, (name, _) in self._part_columns().items()}
        for name in self.tracked_columns():
            units |= {f"{name}_d{axis}": HISTORY_UNITS["tracked_displacement"] for axis in "xyz"}
            units |= {f"{name}_v{axis}": HISTORY_UNITS["tracked_velocity"] for axis in "xyz"}
        return units

    def to_dataframe(self) -> Any:
        """The history as a ``pandas.DataFrame`` (the columns of :meth:`history_table`, units in
        ``.attrs["units"]``); without pandas installed, the ``dict`` of :meth:`history_table`."""
        try:
            import pandas
        except ImportError:
            return self.history_table()
        frame = pandas.DataFrame(self.history_table())
        frame.attrs["units"] = self.history_units()
        return frame

    def _part_columns(self) -> dict[str, tuple[str, np.ndarray]]:
        """The per-part, per-contact, per-wall and reaction columns: column -> (its /history dataset, values)."""
        return history_columns.part_columns(self)

    def contact_sides(self) -> list[tuple[str, ...]]:
        """Each contact definition's parts by column-safe name (history_columns.contact_sides)."""
        return history_columns.contact_sides(self)

    def history_table(self) -> dict[str, np.ndarray]:
        """The history as columns, in the order of the CSV file (see docs/outputs.md)."""
        h = self.history
        table: dict[str, np.ndarray] = {"time": h["time"]}
        for name in ENERGY_NAMES:
            table[name] = h[name]
        table["total_energy"] = self.total_energy()
        table["contact_penetration"] = h["contact_penetration"]
        table["dt"] = h["dt"]
        table["dt_stable"] = h["dt_stable"]
        table["dt_element"] = h["dt_element"].astype(np.int64)
        for column, (_, values) in self._part_columns().items():
            table[column] = values
        disp, vel = h["tracked_displacement"], h["tracked_velocity"]
        for i, name in enumerate(self.tracked_columns()):
            for c, axis in enumerate("xyz"):
                table[f"{name}_d{axis}"] = disp[:, i, c]
            for c, axis in enumerate("xyz"):
                table[f"{name}_v{axis}"] = vel[:, i, c]
        return table


def read(
    path: str | Path,
    deck: str | Path | None = None,
    allow_incomplete: bool = False,
) -> Results:
    """Open a ParaDyn results file.

    Parameters
    ----------
    path : str or Path
        The ``results.h5`` the engine wrote.
    deck : str or Path, optional
        The deck the run used, for the names the results file does not hold; by default
        ``deck.h5`` beside the results file, when it exists and matches the mesh.
    allow_incomplete : bool
        Read a file whose run did not finish, keeping only the frames and history records that
        were written completely.

    Returns
    -------
    Results
        The mesh, frame times, history and names; frame fields are read when used.

    Raises
    ------
    FileNotFoundError
        No file at ``path`` (or at an explicit ``deck``).
    ResultsError
        Not a ParaDyn results file, an unsupported version or a damaged file;
        :class:`IncompleteResultsError` when the run did not finish and ``allow_incomplete`` is
        False.

    Examples
    --------
    >>> import paradyn
    >>> res = paradyn.read("runs/pipe_whip/results.h5")      # doctest: +SKIP
    >>> res.time_values[-1], res.displacement[-1].shape       # doctest: +SKIP
    (0.0025, (544, 3))
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no results file at {path}; check the path or run the deck first")
    with open_results(path) as h5:
        version, complete = check_header(h5, path, allow_incomplete)
        mesh = read_mesh(h5, path)
        n_nodes, n_elements = mesh["coordinates"].shape[0], mesh["connectivity"].shape[0]
        times = read_frame_layout(h5, path, complete, n_nodes, n_elements)
        history = read_history(h5, path, complete)
        run = read_run(h5)
        written = run_names.names_in_results(h5)
    names = run_names.merged(written, run_names.names_in_deck(path, deck, n_nodes))
    n_parts = max(
        len(names.part_names),
        names.n_parts,
        int(mesh["part"].max()) + 1 if mesh["part"].size else 0,
    )
    return Results(
        path=path,
        version=version,
        complete=complete,
        coordinates=mesh["coordinates"],
        connectivity=mesh["connectivity"],
        element_part=mesh["part"],
        time_values=times,
        history=history,
        run=run,
        part_names=run_names.part_names(names.part_names, n_parts),
        tracked_names=run_names.tracked_names(names, history["tracked_displacement"].shape[1]),
        title=names.title or "",
        tracked_nodes=names.tracked_nodes,
        end_time=names.end_time,
        deck_path=names.deck_path,
        effects_written=names.effects,
        effect_table=written.effect_table,
        file_ids=names.file_ids,
    )
