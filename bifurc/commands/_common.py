"""Options shared by the subcommands: scene, preset, parameter overrides, initial state."""
from __future__ import annotations

import argparse

from maps.parameters import ParameterError

__all__ = ["add_scene_options", "parse_sets", "parse_x0", "scene_kwargs"]


def add_scene_options(parser: argparse.ArgumentParser, default_scene: str = "thesis-1dof") -> None:
    g = parser.add_argument_group("scene and parameters")
    g.add_argument("--scene", default=default_scene, help="scene name (see `bifurc scenes`)")
    g.add_argument("--preset", default=None,
                   help="parameter preset: thesis-text, matlab-listing or dynamics-listing "
                        "(default: the scene's own)")
    g.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter by its name (repeatable), e.g. --set V=90")
    g.add_argument("--relay-hz", type=float, default=None, help="shortcut for --set relay_hz=...")
    g.add_argument("--x0", default=None, metavar="x=0.001,v=0",
                   help="initial state components by name (others: the scene's default)")
    g.add_argument("--circuit", choices=("thesis", "kvl"), default=None,
                   help="circuit form: thesis (eq 4.16, i and di/dt) or kvl (charge form)")
    g.add_argument("--ac-sign", choices=("physical", "listing"), default=None,
                   help="AC force sign: physical (default) or as in listing C.2")
    g.add_argument("--dc-law", choices=("listing", "fit", "measured"), default=None,
                   help="DC-force law: listing (listing C.9), fit (eqs 4.6-4.7) or measured (Table 4.1 "
                        "only, zero beyond 29 mm); default: the preset's (matlab-listing: listing, "
                        "thesis-text: fit)")
    g.add_argument("--tol", type=float, default=1e-12, help="heyoka tolerance (default 1e-12)")


def _parse_pairs(items, option: str) -> dict:
    out = {}
    for item in items or []:
        name, sep, value = item.partition("=")
        name = name.strip()
        if not sep or not name:
            raise ParameterError(f"{option} {item!r}: expected NAME=VALUE")
        try:
            out[name] = float(value)
        except ValueError:
            raise ParameterError(f"{option} {item!r}: value of {name!r} is not a number") from None
    return out


def parse_sets(items) -> dict:
    """['V=90', 'k=1e6'] -> {'V': 90.0, 'k': 1e6}; a malformed item names itself.

    Names are checked later by the scene, which lists its allowed names.
    """
    return _parse_pairs(items, "--set")


def parse_x0(text) -> dict:
    """'x=0.001,v=0' -> {'x': 0.001, 'v': 0.0} (state components by name, SI units)."""
    if not text:
        return {}
    return _parse_pairs([p for p in text.split(",") if p.strip()], "--x0")


def scene_kwargs(args) -> dict:
    """Keyword arguments for maps.simulate / sweeps from the shared options."""
    params = parse_sets(args.sets)
    if args.relay_hz is not None:
        params["relay_hz"] = args.relay_hz
    return dict(params=params, preset=args.preset, x0=parse_x0(args.x0), tol=args.tol,
                circuit=args.circuit, ac_sign=args.ac_sign, dc_law=args.dc_law)
