"""`bifurc explore`: a stored diagram in the browser (hover a value, click it for its orbit), served on 127.0.0.1."""
from __future__ import annotations

#: the port a page is served on unless --port says otherwise (Bokeh's and Panel's own default)
DEFAULT_PORT = 5006


def register(subparsers):
    p = subparsers.add_parser("explore", help="explore a diagram in the browser: hover, click a value for its orbit",
                              description="Serve a stored diagram as a local web page (127.0.0.1 only) and open the "
                                          "browser: hover a value for its class, n:m, exponent with its interval and "
                                          "reason; click it for its time history (position with impacts, current, "
                                          "relay), phase portrait and periodic orbit with its Floquet multipliers; "
                                          "'Continue branch' overlays its branch; zooming sweeps the range anew on a "
                                          "finer grid. Needs the explore extra: pip install -e \".[explore]\". "
                                          "Ctrl-C stops it.")
    p.add_argument("dataset", help="netCDF diagram written by bifurc diagram (or bifurc.sweep)")
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
    ds = load(args.dataset, "diagram")
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
