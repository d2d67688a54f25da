"""Options shared by the subcommands: scene, preset, parameter overrides, initial state."""
from __future__ import annotations

import argparse

from maps.laws import DC_LAWS, SOIL_LAWS
from maps.parameters import ParameterError


def add_parameter_options(parser, default_scene: str = "thesis-1dof"):
    """--scene, --preset, --set in a group "scene and parameters"; returns the group."""
    g = parser.add_argument_group("scene and parameters")
    g.add_argument("--scene", default=default_scene, help="scene name (see `bifurc scenes`), or package.module:NAME for a user's "
                        "system (a maps.Scene, a HybridSystem or a function returning one)")
    g.add_argument("--preset", default=None,
                   help="parameter preset: thesis-text, matlab-listing or dynamics-listing "
                        "(default: the scene's own)")
    g.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter by its name (repeatable), e.g. --set V=90")
    return g


def add_scene_options(parser: argparse.ArgumentParser, default_scene: str = "thesis-1dof",
                      default_tol: float | None = 1e-12) -> None:
    """The parameter options, --relay-hz, --x0, --circuit, --ac-sign and --tol (``default_tol`` None: the
    tolerance is a method's setting, added with its option group)."""
    g = add_parameter_options(parser, default_scene)
    g.add_argument("--relay-hz", type=float, default=None, help="shortcut for --set relay_hz=...")
    g.add_argument("--x0", default=None, metavar="x=0.001,v=0",
                   help="initial state components by name (others: the scene's default)")
    g.add_argument("--circuit", choices=("thesis", "kvl"), default=None,
                   help="circuit form: thesis (eq 4.16, i and di/dt) or kvl (charge form)")
    g.add_argument("--ac-sign", choices=("physical", "listing"), default=None,
                   help="AC force sign: physical (default) or as in listing C.2")
    g.add_argument("--dc-law", choices=tuple(DC_LAWS), default=None,
                   help="DC-force law: listing (listing C.9), fit (eqs 4.6-4.7), measured (Table 4.1 "
                        "only, zero beyond 29 mm) or catalogue (saturating: Table 4.1 and the catalogue's 7.4 N "
                        "at 24 V, about 5.1 N at the stop at 20 V); default: the preset's (matlab-listing: "
                        "listing, thesis-text: fit). Optional elements switch on when their parameter is set: "
                        "--set c_air=... (free-flight damping), e_rear=... (prototype rear stop), tau_dc=... "
                        "(DC coil L/R delay, antiphase relay); see bifurc params")
    g.add_argument("--soil", choices=tuple(SOIL_LAWS), default=None,
                   help="2-DOF soil law: viscous (listings C.4-C.6), coulomb (dry friction with sticking) or "
                        "drift (visco-elastic element and plastic slider, Pavlovskaia et al. 2001); "
                        "default: the scene's")
    g.add_argument("--compaction", action="store_true", default=None,
                   help="coulomb and drift soils: the resistance grows with depth, R0 (1 + depth/soil_depth_scale), "
                        "soil_depth_scale fitted to thesis Fig 5.22 (docs/model.md)")
    if default_tol is not None:
        g.add_argument("--tol", type=float, default=default_tol, help=f"heyoka tolerance (default {default_tol:g})")


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


def parse_floats(text, option: str) -> list:
    """'5,6.5' -> [5.0, 6.5]; anything else names the option."""
    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise ParameterError(f"{option} expects comma-separated numbers, got {text!r}") from None


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


def problem_kwargs(args) -> dict:
    """The keywords of :func:`maps.problem` from the shared options."""
    params = parse_sets(args.sets)
    if args.relay_hz is not None:
        params["relay_hz"] = args.relay_hz
    return dict(params=params, preset=args.preset, x0=parse_x0(args.x0), circuit=args.circuit, ac_sign=args.ac_sign,
                dc_law=args.dc_law, soil=args.soil, compaction=args.compaction)


def scene_kwargs(args) -> dict:
    """Keyword arguments for maps.simulate, orbits and branches: :func:`problem_kwargs` and ``tol``."""
    return dict(problem_kwargs(args), tol=args.tol)


def add_force_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--force", action="store_true", help="replace existing output files")


def check_outputs(args, *paths, need_bytes: float = 0) -> None:
    """Before any long work: refuse existing outputs unless --force (one line naming --force), a folder
    where a file is to go, and a folder that cannot take the file (read-only, full: ``need_bytes``)."""
    from ..storage.files import check_writable, refuse_existing
    for path in paths:
        if path is not None:
            refuse_existing(path, args.force, hint="use --force")
            check_writable(path, need_bytes)


def check_plot(args) -> None:
    """``--plot``: a format matplotlib writes, not in the way of an existing file (unless --force)."""
    if args.plot:
        from ..storage.files import check_figure_output, check_writable
        check_figure_output(args.plot, args.force, what="--plot")
        check_writable(args.plot)


#: seconds to wait for a Dask scheduler before saying it is unreachable
SCHEDULER_TIMEOUT = 3.0


def check_scheduler(address) -> None:
    """A ``tcp://host:port`` (or ``tls://``, or ``host:port``) scheduler must accept a connection
    within :data:`SCHEDULER_TIMEOUT` s; other schemes are left to Dask."""
    import socket
    from urllib.parse import urlsplit
    if address is None:
        return
    text = address if "://" in address else f"tcp://{address}"
    parts = urlsplit(text)
    if parts.scheme not in ("tcp", "tls"):
        return
    try:
        host, port = parts.hostname, parts.port
    except ValueError:
        host = port = None
    if not host or port is None:
        raise ParameterError(f"--scheduler {address!r}: expected tcp://host:port")
    try:
        socket.create_connection((host, port), timeout=SCHEDULER_TIMEOUT).close()
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise ParameterError(f"--scheduler {address}: no Dask scheduler reachable there within "
                             f"{SCHEDULER_TIMEOUT:g} s ({reason})") from None


def add_range_options(parser, default_param: str | None, default_n: int, suffix: str = "",
                      required: bool = True) -> None:
    """``--param``, ``--from``, ``--to``, ``--n`` (``suffix`` "2": the second parameter's, ``--param2`` ...);
    ``required=False``: a range that may be left out (the census' second parameter: ``--param2`` None)."""
    which = "second parameter" if suffix else "parameter"
    default = f" (default {default_param})" if default_param is not None else ""
    parser.add_argument(f"--param{suffix}", default=default_param, help=f"{which} to vary{default}")
    parser.add_argument(f"--from{suffix}", dest=f"start{suffix}", type=float, required=required,
                        help=f"first value of --param{suffix}")
    parser.add_argument(f"--to{suffix}", dest=f"stop{suffix}", type=float, required=required,
                        help=f"last value of --param{suffix}")
    parser.add_argument(f"--n{suffix}", type=int, default=default_n,
                        help=f"number of values of --param{suffix} (default {default_n})")


def add_grid_options(parser, what: str = "value", exclude=()) -> None:
    """The options of a grid of independent ``what``s (diagram values, map cells): the :class:`bifurc.Diagram`
    method's settings, the figure's period convention, where it runs and its outputs (:mod:`._options`)."""
    from ..sweeps.method import Diagram
    from ._options import add_run_options, add_settings_options
    add_settings_options(parser, Diagram, f"how each {what} is integrated and judged (bifurc.Diagram)", exclude)
    parser.add_argument("--period-of", choices=("full", "mechanical"), default="full",
                        help="the figure's period convention: full (the whole state) or mechanical (the bar "
                             "alone: the thesis' period-n); the dataset stores both")
    add_run_options(parser, what)
