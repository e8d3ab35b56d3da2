"""What ``paradyn-run`` shows while it works: meshing, the engine's cycles, post-processing.

The engine prints machine-readable ``PARADYN-PROGRESS`` lines (docs/formats.md, "Engine progress
lines"); :mod:`paradyn.running.engine_process` turns them into :class:`~paradyn.running.engine_process.Progress`
records and this module draws them with tqdm (``tqdm.auto``: a text bar on a terminal, a widget in
Jupyter). The choices (docs/scene.md, "What paradyn-run shows"):

- the numbers first, the bar last: ``cycle 1234 t 1.000e-03 s dt 1.1e-07 s ETA 0:12 45%|###|``,
  cut to the terminal's width less one column, so it never wraps (80 columns keep the numbers);
- a stage without a measure of its own (meshing, each post-processing output) shows its name and
  the seconds it has taken, refreshed twice a second;
- where the stream is neither a terminal nor a notebook (a log file, a batch job), one plain line
  every tenth of the run instead of carriage returns, and a last ``100.0%`` line when the engine
  is done (its last progress line comes before the end);
- the ETA from the rate of this engine process: after a restart, the simulated time since the
  checkpoint over the wall time since the restart;
- engine warnings (initial penetrations) are printed above the bar as they come;
- quiet (``paradyn-run -q``): nothing but the check's ``warning:`` lines (a likely unit mistake
  is never silent).
"""

from __future__ import annotations

import math
import shutil
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, TextIO

from .engine_process import Progress

MAX_COLUMNS = 120   # wider terminals get a line this long; the bar takes what the numbers leave
REFRESH_S = 0.5     # a stage's clock is redrawn this often


def in_notebook() -> bool:
    """True inside a Jupyter kernel (where tqdm.auto draws a widget)."""
    shell = sys.modules.get("IPython")
    get = getattr(shell, "get_ipython", None)
    kernel = get() if callable(get) else None
    return kernel is not None and "IPKernelApp" in getattr(kernel, "config", {})


def clock(seconds: float | None) -> str:
    """``H:MM:SS`` or ``M:SS``; ``?`` when unknown."""
    if seconds is None or not math.isfinite(seconds) or seconds < 0:
        return "?"
    minutes, secs = divmod(round(seconds), 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"


def progress_text(p: Progress) -> str:
    """The numbers of one progress line, shortest first-read order: cycle, time, step, ETA."""
    return f"cycle {p.cycle} t {p.time:.3e} s dt {p.dt:.2e} s ETA {clock(p.eta_s)}"


class RunProgress:
    """The display of one ``paradyn-run``: call it with every :class:`Progress`; ``stage`` wraps
    meshing and post-processing; ``report`` prints the check's lines, ``warning`` a line above the
    bar; ``close`` ends it."""

    def __init__(self, stream: TextIO | None = None, live: bool | None = None, quiet: bool = False) -> None:
        self.stream = stream if stream is not None else sys.stderr
        self.quiet = quiet
        isatty = getattr(self.stream, "isatty", lambda: False)
        self.live = (isatty() or in_notebook()) if live is None else live
        self.bar: Any = None
        self.last_tenth = -1

    def _new_bar(self, total: float | None, description: str) -> Any:
        # the size from shutil, which falls back to 80 x 24 where the terminal reports 0 (a pty
        # without a size, where tqdm would draw nothing); one column less, so that it never wraps
        from tqdm.auto import tqdm  # 40 ms of imports a quiet or piped run never needs

        size = shutil.get_terminal_size((80, 24))
        notebook = in_notebook()
        columns = max(40, min(MAX_COLUMNS, size.columns - 1))
        return tqdm(total=total, file=self.stream, ncols=None if notebook else columns,
                    nrows=None if notebook else size.lines,
                    bar_format="{desc} {percentage:3.0f}%|{bar}|" if total else "{desc}",
                    desc=description, leave=True, mininterval=0.1)

    def __call__(self, p: Progress) -> None:
        if self.quiet:
            return
        text = progress_text(p)
        if not self.live:
            tenth = int(10 * p.fraction + 1e-9)   # 0.1 x 10 is 0.9999...: still a tenth
            if tenth > self.last_tenth:
                self.last_tenth = tenth
                self.stream.write(f"{100 * p.fraction:5.1f}% {text}\n")
                self.stream.flush()
            return
        if self.bar is None:
            self.bar = self._new_bar(p.end_time, text)
        self.bar.set_description_str(text, refresh=False)
        self.bar.n = min(p.time, p.end_time)
        self.bar.refresh()

    def finish_engine(self, done: dict[str, str] | None = None) -> None:
        """The engine is done: the bar (or, without a terminal, a last line) shows 100 % and the
        engine's last cycle and wall time (its last progress line came before the end), from the
        fields of its ``PARADYN-DONE`` line."""
        fields = done or {}
        text = (f"cycle {fields['cycles']} t {float(fields.get('time', 'nan')):.3e} s "
                f"done in {clock(float(fields.get('wall_s', 'nan')))}") if "cycles" in fields else "done"
        if not self.live:
            if not self.quiet and self.last_tenth < 10:   # the last tenth's line came before the end
                self.last_tenth = 10
                self.stream.write(f"100.0% {text}\n")
                self.stream.flush()
            return
        if self.bar is None and not self.quiet and "time" in fields:
            # no progress line came (a short run, or a restart close to its end): the bar at its end
            self.bar = self._new_bar(float(fields["time"]) or 1.0, text)
        if self.bar is not None:
            self.bar.set_description_str(text, refresh=False)
            self.bar.n = self.bar.total
            self.bar.refresh()
            self.bar.close()
            self.bar = None

    def report(self, lines: list[str]) -> None:
        """The check's lines (:meth:`paradyn.running.preflight.Preflight.lines`); only its warnings when quiet."""
        for line in lines:
            if not self.quiet or line.startswith("warning:"):
                self._print("  " + line)

    def warning(self, line: str) -> None:
        """A line above the bar (engine warnings as they come; not when quiet: paradyn-run repeats
        them at the end)."""
        if not self.quiet:
            self._print("  " + line.removeprefix("paradyn-engine: "))

    def _print(self, text: str) -> None:
        if self.bar is not None:
            self.bar.write(text, file=self.stream)
        else:
            self.stream.write(text + "\n")
            self.stream.flush()

    @contextmanager
    def stage(self, name: str) -> Iterator[None]:
        """Show ``name`` and its running seconds while the body runs (meshing, post-processing)."""
        started = time.monotonic()
        if self.quiet:
            yield
            return
        if not self.live:
            self.stream.write(f"{name} ...\n")
            self.stream.flush()
            yield
            return
        bar = self._new_bar(None, name)
        done = threading.Event()

        def tick() -> None:
            while not done.wait(REFRESH_S):
                bar.set_description_str(f"{name} {clock(time.monotonic() - started)}")

        ticker = threading.Thread(target=tick, daemon=True)
        ticker.start()
        try:
            yield
        finally:
            done.set()
            ticker.join()
            bar.set_description_str(f"{name} done in {time.monotonic() - started:.1f} s")
            bar.close()

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None
