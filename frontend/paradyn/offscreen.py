"""Off-screen rendering without a display, and without VTK's warning about it.

VTK 9 opens an X window first and falls back to EGL or OSMesa when that fails, printing
``vtkXOpenGLRenderWindow ... WARN| bad X server connection`` on every run without a display. When
there is no display (no ``DISPLAY`` or ``WAYLAND_DISPLAY``) and the user has not chosen a window
class, :func:`prepare` asks VTK for the EGL window directly (libEGL is found), else lowers VTK's
log to errors: the picture is the same, the warning is not printed. docs/outputs.md, "Pictures".
"""

from __future__ import annotations

import ctypes.util
import os
import sys

WINDOW_ENV = "VTK_DEFAULT_OPENGL_WINDOW"   # VTK 9.4 and later: the render window class to create


def has_display() -> bool:
    """True where an X or Wayland display is set (or on macOS and Windows, where VTK needs none)."""
    if not sys.platform.startswith("linux"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


def prepare() -> None:
    """Before a render window is made: EGL where there is no display, and no X warning."""
    if has_display() or os.environ.get(WINDOW_ENV):
        return
    if ctypes.util.find_library("EGL"):
        os.environ[WINDOW_ENV] = "vtkEGLRenderWindow"
        return
    from vtkmodules.vtkCommonCore import vtkLogger

    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)
