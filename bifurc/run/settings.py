"""Settings objects: frozen dataclasses that validate their own fields and name each default once.

A method (how an analysis is done: :class:`bifurc.Diagram`, :class:`bifurc.Census`, ...) and the :class:`bifurc.Run`
(where it runs) are :class:`Settings`.  Each field is declared with :func:`setting`: its default, its unit, its
allowed range or choices and a one-line help.  The same declaration validates the field (one
:class:`~maps.parameters.ParameterError` line naming it and its allowed range), is what a resume manifest records,
and is what the command line's options are generated from (:mod:`bifurc.commands._options`).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

from maps.parameters import ParameterError, validate_value

#: the modes of a grid of points and their branches: independent points, or each from the previous one's end state,
#: swept up then down (:func:`bifurc.run.grid.run_points`)
MODES = {"independent": ("independent",), "follow": ("up", "down")}


def setting(default, help: str, *, unit: str = "", low=None, high=None, whole: bool = False, choices=None,
            optional: bool = False, cli: str | None = None, flag: str | None = None, kind=None,
            low_open: bool = False):
    """A field of a :class:`Settings` class.

    ``low``/``high``: allowed range (inclusive); ``whole``: a whole number; ``choices``: allowed values;
    ``low_open``: ``low`` itself excluded; ``optional``: None is allowed (the default then says what None means in
    ``help``); ``cli``: the option's name
    on the command line (default ``--name-with-dashes``; "" for none); ``flag``: for a bool defaulting to True, the
    command line's negating switch (e.g. ``--no-lyapunov``); ``kind``: the value's type where it is not the
    default's (e.g. float for an optional number)."""
    meta = dict(help=help, unit=unit, low=low, high=high, whole=whole, choices=choices, optional=optional,
                cli=cli, flag=flag, kind=kind, low_open=low_open)
    return field(default=default, metadata=meta)


def check_field(name: str, value, meta: dict):
    """``value`` of the field ``name`` checked against its declaration; returns it normalised (an int for a whole
    number, a float for a number) or raises one :class:`~maps.parameters.ParameterError` line."""
    if value is None and meta.get("optional"):
        return None
    choices = meta.get("choices")
    if choices is not None:
        if value not in choices:
            raise ParameterError(f"{name} = {value!r}; allowed: {', '.join(map(str, choices))}")
        return value
    low, high, whole = meta.get("low"), meta.get("high"), meta.get("whole")
    if low is None and high is None and not whole:
        return value
    if whole and (isinstance(value, bool) or not isinstance(value, (int, float)) or
                  (isinstance(value, float) and not math.isfinite(value))):
        raise ParameterError(f"{name} = {value!r}: expected {_range_text(low, high, whole)}")
    if whole and value != int(value):
        raise ParameterError(f"{name} = {value!r}: a whole number is needed ({_range_text(low, high, whole)})")
    x = validate_value(name, value, -math.inf if low is None else low, math.inf if high is None else high,
                       low_open=bool(meta.get("low_open")), unit=meta.get("unit", ""))
    return int(x) if whole else float(x)


def _range_text(low, high, whole) -> str:
    what = "a whole number" if whole else "a number"
    if low is not None and high is not None:
        return f"{what} in [{low:g}, {high:g}]"
    if low is not None:
        return f"{what} >= {low:g}"
    if high is not None:
        return f"{what} <= {high:g}"
    return what


@dataclass(frozen=True)
class Settings:
    """Base of the method and run objects: every field checked against its :func:`setting` declaration."""

    def __post_init__(self):
        for f in dataclasses.fields(self):
            if f.metadata:
                object.__setattr__(self, f.name, check_field(f.name, getattr(self, f.name), f.metadata))
        self._check()

    def _check(self) -> None:
        """Checks across fields (a subclass's)."""

    def replace(self, **changes):
        """A copy with ``changes``; an unknown name is one line naming the valid ones."""
        names = [f.name for f in dataclasses.fields(self)]
        unknown = [k for k in changes if k not in names]
        if unknown:
            import difflib
            close = difflib.get_close_matches(str(unknown[0]), names, n=1, cutoff=0.75)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ParameterError(f"{type(self).__name__} has no setting {unknown[0]!r}{hint}; its settings: "
                                 f"{', '.join(names)}")
        return dataclasses.replace(self, **changes)

    def fields(self) -> dict:
        """{name: value} of every setting (what a manifest records)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    @classmethod
    def names(cls) -> tuple:
        return tuple(f.name for f in dataclasses.fields(cls))


def split_options(options: dict, *groups) -> list:
    """``options`` (the keyword convenience of an analysis) shared out among ``groups``, each a (Settings class or
    instance, or a tuple of names) in order: returns one dict per group.  A name no group takes is one line naming
    every valid one."""
    out = [dict() for _ in groups]
    valid = []
    for g in groups:
        valid.extend(g if isinstance(g, tuple) else g.names())
    for k, v in options.items():
        for i, g in enumerate(groups):
            if k in (g if isinstance(g, tuple) else g.names()):
                out[i][k] = v
                break
        else:
            import difflib
            close = difflib.get_close_matches(str(k), valid, n=1, cutoff=0.75)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            raise ParameterError(f"unknown option {k!r}{hint}; valid: {', '.join(valid)}")
    return out


def settle(cls, given, changes: dict):
    """An instance of ``cls``: ``given`` (an instance, or None for the defaults) with ``changes`` applied."""
    if given is not None and not isinstance(given, cls):
        raise ParameterError(f"expected a {cls.__name__} object, got {type(given).__name__}")
    base = given if given is not None else None
    if base is None:
        return cls(**changes)
    return base.replace(**changes) if changes else base
