"""CF global attributes of every dataset: ``Conventions``, ``history`` and ``source``.

``history`` names what made the data: the command line when the ``bifurc`` command runs
(:func:`command` sets it), else the API call (:func:`recorded` wraps a public function),
with the UTC time, the package version and the git commit when the code is a checkout.
"""
from __future__ import annotations

import contextlib
import contextvars
import datetime
import functools
import inspect
import subprocess
from pathlib import Path

from ._version import __version__

CONVENTIONS = "CF-1.10"
_CALL: contextvars.ContextVar = contextvars.ContextVar("bifurc_call", default=None)


def _git(*args) -> str | None:
    try:
        out = subprocess.run(["git", *args], cwd=Path(__file__).resolve().parent, capture_output=True, text=True,
                             timeout=5)
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() or None if out.returncode == 0 else None


@functools.lru_cache(maxsize=1)
def git_commit() -> str | None:
    """Commit of the checkout this package runs from, ``-dirty`` if it has local changes (None: an
    installed copy, not tracked by git; a package installed inside another repository is not tracked)."""
    if _git("ls-files", "--error-unmatch", Path(__file__).name) is None:
        return None
    return _git("describe", "--always", "--dirty", "--abbrev=7")


def _short(value) -> str:
    """A compact repr for history: arrays and long sequences summarised."""
    import numpy as np
    if isinstance(value, (list, tuple)) and any(not isinstance(v, (int, float, str, np.number)) for v in value):
        return f"<{len(value)} {'/'.join(sorted({type(v).__name__ for v in value}))}>"     # e.g. datasets
    if isinstance(value, (np.ndarray, list, tuple)) and np.size(value) > 4:
        a = np.asarray(value)
        if a.dtype.kind in "fiu":
            return f"<{a.size} values {a.min():g}..{a.max():g}>"
        return f"<{a.size} items>"
    if isinstance(value, np.ndarray):
        return repr(value.tolist())
    text = repr(value)
    return text if len(text) <= 60 else f"<{type(value).__name__}>"


def current_call() -> str | None:
    """The command line or API call being recorded (None: outside both)."""
    return _CALL.get()


@contextlib.contextmanager
def command(text: str):
    """Record ``text`` (e.g. the command line) as the origin of every dataset made inside."""
    token = _CALL.set(text)
    try:
        yield
    finally:
        _CALL.reset(token)


def recorded(name: str):
    """Decorator: inside the call, datasets record ``name(arguments)`` unless a command is recorded."""
    def wrap(func):
        sig = inspect.signature(func)

        @functools.wraps(func)
        def inner(*args, **kwargs):
            if _CALL.get() is not None:
                return func(*args, **kwargs)
            bound = sig.bind_partial(*args, **kwargs)
            items = []
            for i, (k, v) in enumerate(bound.arguments.items()):
                kind = sig.parameters[k].kind
                if kind == inspect.Parameter.VAR_KEYWORD:      # **options: each by its name
                    items += [f"{kk}={_short(vv)}" for kk, vv in v.items()]
                elif kind == inspect.Parameter.POSITIONAL_OR_KEYWORD and i < len(args):
                    items.append(_short(v))
                else:
                    items.append(f"{k}={_short(v)}")
            text = f"{name}(" + ", ".join(items) + ")"
            with command(text):
                return func(*args, **kwargs)
        return inner
    return wrap


def code_version() -> str:
    """This code: "bifurc <version>", with ", git <commit>" when it runs from a checkout (``-dirty``: with local
    changes)."""
    commit = git_commit()
    return f"bifurc {__version__}" + (f", git {commit}" if commit else "")


def cf_attrs(source: str = "") -> dict:
    """``Conventions``, ``history`` (UTC time, call, version, commit) and ``source`` for a new dataset."""
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    version = code_version()
    call = current_call() or "Python API"
    import heyoka as hy
    return {"Conventions": CONVENTIONS, "history": f"{now}: {call} ({version})",
            "source": f"bifurc {__version__} (heyoka {hy.__version__} Taylor integration)"
                      + (f": {source}" if source else "")}
