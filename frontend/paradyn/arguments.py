"""Misspelt names, in scene files and in calls: "did you mean" and clear errors for bad arguments.

:func:`did_you_mean` names the closest allowed word (``difflib``, as Python's own messages do);
every message about an unknown key, value, table or name in the scene reader, the study reader and
the Python API uses it. :func:`checked_arguments` wraps a public function or method so that a call
with an unknown, misspelt or missing keyword argument raises :class:`ArgumentError` naming the
closest argument, instead of Python's bare ``TypeError`` about a missing argument (which never
says that ``densty=`` was given instead of ``density=``).
"""

from __future__ import annotations

import difflib
import functools
import inspect
from collections.abc import Callable, Iterable
from typing import Any, TypeVar

F = TypeVar("F", bound=Callable[..., Any])


class ArgumentError(TypeError):
    """A call of ParaDyn's Python API with an unknown, misspelt or missing argument; the message
    names the closest argument and lists them all."""


def closest(word: object, allowed: Iterable[str]) -> str | None:
    """The allowed word closest to ``word`` (``difflib``, cut-off 0.6; a difference of case
    alone always counts), or None."""
    allowed = list(allowed)
    text = str(word)
    same_case = [a for a in allowed if a.lower() == text.lower()]
    if same_case:
        return same_case[0]
    close = difflib.get_close_matches(text, allowed, n=1)
    return close[0] if close else None


def did_you_mean(word: object, allowed: Iterable[str]) -> str:
    """``"did you mean 'x'? "`` for the allowed word closest to ``word``, else ``""`` (to start the
    fix of a message)."""
    close = closest(word, allowed)
    return f"did you mean '{close}'? " if close is not None and close != str(word) else ""


def checked_arguments(name: str, error: type[Exception] = ArgumentError) -> Callable[[F], F]:
    """Wrap a function so that a call whose arguments do not bind raises ``error`` (``name`` is the
    function as the user writes it, e.g. ``paradyn.Scene.add_material``)."""

    def wrap(function: F) -> F:
        signature = inspect.signature(function)

        @functools.wraps(function)
        def call(*args: Any, **kwargs: Any) -> Any:
            try:
                signature.bind(*args, **kwargs)
            except TypeError as exc:
                raise error(argument_message(name, signature, args, kwargs, str(exc))) from None
            return function(*args, **kwargs)

        return call  # type: ignore[return-value]

    return wrap


def argument_message(name: str, signature: inspect.Signature, args: tuple[Any, ...], kwargs: dict[str, Any],
                     fallback: str) -> str:
    """What is wrong with a call of ``name`` whose arguments do not bind to ``signature``."""
    parameters = [p for p in signature.parameters.values() if p.name not in ("self", "cls")]
    named = [p.name for p in parameters if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    takes_any = any(p.kind is p.VAR_KEYWORD for p in parameters)
    unknown = [k for k in kwargs if k not in named]
    try:
        bound = signature.bind_partial(*args, **{k: v for k, v in kwargs.items() if k in named})
    except TypeError:   # too many positional arguments, or one given twice: Python's words say it
        return f"{name}(): {fallback.split('() ', 1)[-1]}; its arguments are: {', '.join(named)}"
    missing = [p.name for p in parameters if p.name in named and p.name not in bound.arguments
               and p.default is p.empty and p.name not in ("self", "cls")]
    problems = []
    for key in missing:
        typo = [k for k in unknown if closest(k, [key]) == key]
        hint = f" ('{typo[0]}' was given: a misspelling of '{key}'?)" if typo else ""
        problems.append(f"missing required argument '{key}'{hint}")
    if not takes_any:
        for key in unknown:
            if not any(closest(key, [m]) == m for m in missing):
                hint = did_you_mean(key, named).strip()
                problems.append(f"unknown argument '{key}'" + (f" ({hint})" if hint else ""))
    if not problems:
        return f"{name}(): {fallback.split('() ', 1)[-1]}"
    return f"{name}(): {'; '.join(problems)}; its arguments are: {', '.join(named)}"


__all__ = ["ArgumentError", "argument_message", "checked_arguments", "closest", "did_you_mean"]
