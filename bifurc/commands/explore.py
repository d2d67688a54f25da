"""`bifurc explore`: a stored diagram, regime map or census in the browser (hover, click for orbits), served on
127.0.0.1."""
from __future__ import annotations

#: the port a page is served on unless --port says otherwise (Bokeh's and Panel's own default)
DEFAULT_PORT = 5006


def register(subparsers):
    p = subparsers.add_parser("explore", help="explore a diagram, map or census in the browser: click for orbits",
                              description="Serve a stored diagram as a local web page (127.0.0.1 only) and open the "
                                          "browser: hover a value for its class, n:m, exponent with its interval and "
                                          "reason; click it for its time history (position with impacts, current, "
                                          "relay), phase portrait and periodic orbit with its Floquet multipliers; "
                                          "'Continue branch' overlays its branch; zooming sweeps the range anew on a "
                                          "finer grid. A regime map (bifurc map): click a cell for its time history "
                                          "and orbit. A census (bifurc attractors): click a value for its attractors "
                                          "(class, basin fraction with its interval), their basins and orbits. "
                                          "Needs the explore extra: pip install -e \".[explore]\". "
                                          "Ctrl-C stops it.")
    p.add_argument("dataset", help="netCDF diagram (bifurc diagram), regime map (bifurc map) or census "
                                   "(bifurc attractors)")
    p.add_argument("--port", type=int, default=DEFAULT_PORT,
                   help=f"port on 127.0.0.1 (1024 to 65535; default {DEFAULT_PORT})")
    p.add_argument("--no-browser", action="store_true", help="serve without opening the browser (print the address)")
    p.add_argument("--workers", type=int, default=None,
                   help="worker processes of a zoom's sweep (default: every available core)")
    p.set_defaults(func=run)


def check_port(port: int) -> None:
    """One line unless ``port`` is in 1024..65535 and free on 127.0.0.1."""
    import errno
    import socket

    from maps.parameters import ParameterError
    if not 1024 <= port <= 65535:
        raise ParameterError(f"--port {port}: allowed 1024 to 65535")
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        try:
            s.bind(("127.0.0.1", port))
        except OSError as exc:
            why = "in use" if exc.errno == errno.EADDRINUSE else (exc.strerror or str(exc)).lower()
            raise ParameterError(f"--port {port}: {why} on 127.0.0.1; choose another port (1024 to 65535)") from None


def run(args) -> int:
    from pathlib import Path

    from maps.parameters import ParameterError

    from ..storage.load import load
    if args.workers is not None and args.workers < 1:
        raise ParameterError(f"--workers {args.workers}: need at least 1")
    check_port(args.port)
    from ..storage.build import KINDS
    from ..storage.load import kind_of
    ds = load(args.dataset)
    kind = kind_of(ds)
    if kind not in ("diagram", "map", "attractors"):
        what = f"{'an' if kind[0] in 'aeiou' else 'a'} {kind} dataset (from {KINDS.get(kind, 'another tool')})" \
            if kind else "another kind of dataset"
        raise ParameterError(f"{args.dataset} holds {what}; bifurc explore needs a diagram, map or attractors "
                             f"dataset (from {KINDS['diagram']}, {KINDS['map']} or {KINDS['attractors']})")
    try:
        from ..explore.app import serve
    except ModuleNotFoundError as exc:
        raise ParameterError(f"bifurc explore needs {exc.name} (the explore extra): pip install "
                             f"\"bifurc[explore]\", or -e \".[explore]\" in a clone") from None
    print(f"bifurc explore: {args.dataset} on http://127.0.0.1:{args.port}/ (Ctrl-C stops it)", flush=True)
    try:
        serve(ds, args.port, show=not args.no_browser, title=f"bifurc explore {Path(args.dataset).name}", workers=args.workers)
    except KeyboardInterrupt:
        print("bifurc explore: stopped", flush=True)
    return 0
