"""Write files so that a reader never sees half of one: a temporary file beside the target, then a
rename over it (``os.replace`` is atomic on one file system).

Every writer of the frontend goes through here: the reports (``history.csv``, ``summary.json``),
the VTK series (``.vtu`` and ``.pvd``), the pictures and the Slurm job script.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

FILE_MODE = 0o644  # mkstemp creates 0600; outputs are meant to be read by others too


@contextmanager
def replacing(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; when the block ends without an error, rename it over
    ``path``, otherwise delete it.

    The temporary name keeps the suffix of ``path`` (libraries such as pyvista choose the file
    format from it) and starts with a dot, so ``*.vtu`` globs do not see it.

    Examples
    --------
    >>> with replacing(out_dir / "frame.vtu") as temporary:   # doctest: +SKIP
    ...     grid.save(temporary, binary=True)
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=f".tmp{path.suffix}", dir=path.parent)
    os.close(handle)
    temporary = Path(name)
    try:
        yield temporary
        os.chmod(temporary, FILE_MODE)
        os.replace(temporary, path)
    except OSError as error:   # a full disk, say: name the file the user asked for, not the temporary
        temporary.unlink(missing_ok=True)
        raise OSError(error.errno, f"cannot write {path} ({error.strerror or error})", str(path)) from error
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write ``text`` (UTF-8, ``\\n`` line ends) to ``path`` atomically; return the path.

    Not synced to disk, as no derived output is (the VTK files neither): they are made from
    ``results.h5``, which the engine syncs, and ``paradyn-post`` writes them again.
    """
    path = Path(path)
    with replacing(path) as temporary, open(temporary, "w", encoding="utf-8", newline="\n") as stream:
        stream.write(text)
    return path
