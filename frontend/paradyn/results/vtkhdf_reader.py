"""pyvista's reader of ``.vtkhdf`` files, with the time steps of a transient file.

pyvista's own ``HDFReader`` (0.49) reads the first step of a transient VTKHDF file only and has no
time API, though VTK's ``vtkHDFReader`` under it reads every step. :class:`VTKHDFReader` is that
reader with pyvista's :class:`~pyvista.TimeReader` interface: ``time_values``,
``set_active_time_value``, ``set_active_time_point``. ParaDyn declares it to pyvista as the reader
of ``.vtkhdf`` (the entry point ``pyvista.readers.override`` in ``pyproject.toml``), so wherever
ParaDyn is installed ``pyvista.get_reader("results.vtkhdf")`` returns it and ``pyvista.read`` reads
the first step, as for a ``.pvd`` series::

    reader = pyvista.get_reader("runs/pipe_whip/results.vtkhdf")
    reader.time_values                 # every frame's time (s)
    reader.set_active_time_point(10)   # or set_active_time_value(t)
    grid = reader.read()               # points at the deformed position, the frame's fields

A file that is not transient (one step, no ``Steps`` group) reads as before, with no time values.
"""

from __future__ import annotations

import math

import pyvista as pv
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline


class VTKHDFReader(pv.HDFReader, pv.TimeReader):   # type: ignore[misc]
    """VTK's ``vtkHDFReader`` with pyvista's time interface (see the module's description)."""

    def _set_defaults_post(self) -> None:
        self.reader.UpdateInformation()
        self._active_step = 0

    @property
    def time_values(self) -> list[float]:
        """The time of every step (s for ParaDyn's results); empty for a file without steps."""
        info = self.reader.GetOutputInformation(0)
        key = vtkStreamingDemandDrivenPipeline.TIME_STEPS()
        return [float(t) for t in info.Get(key)] if info.Has(key) else []

    @property
    def number_time_points(self) -> int:
        return len(self.time_values)

    def time_point_value(self, time_point: int) -> float:
        return self.time_values[self._step_index(time_point)]

    @property
    def active_time_value(self) -> float:
        values = self.time_values
        return values[self._active_step] if values else 0.0

    @property
    def active_time_point(self) -> int:
        """The index of the step :meth:`read` reads."""
        return self._active_step

    def set_active_time_point(self, time_point: int) -> None:
        self._active_step = self._step_index(time_point)
        self.reader.SetStep(self._active_step)

    def set_active_time_value(self, time_value: float) -> None:
        """The step at ``time_value``, one of :attr:`time_values` (to a relative 1e-12)."""
        values = self.time_values
        for k, t in enumerate(values):
            if math.isclose(t, time_value, rel_tol=1e-12, abs_tol=1e-300):
                self.set_active_time_point(k)
                return
        span = f"{len(values)} steps from {values[0]:g} to {values[-1]:g}" if values else "no time steps"
        raise ValueError(f"{self.path} has no step at time {time_value!r} ({span}); give one of time_values, "
                         f"or a step index to set_active_time_point")

    def _step_index(self, time_point: int) -> int:
        count = len(self.time_values)
        if not -count <= time_point < count:
            raise IndexError(f"step {time_point} does not exist: {self.path} holds {count} steps")
        return time_point % count


__all__ = ["VTKHDFReader"]
