"""`bifurc report`: markdown classification report of a diagram dataset."""


def register(subparsers):
    p = subparsers.add_parser("report", help="period-1/period-2 classification report of a diagram")
    p.add_argument("dataset", help="netCDF written by `bifurc diagram`")
    p.add_argument("-o", "--output", default=None, help="markdown file (default: print)")
    p.add_argument("--at", default=None, help="comma-separated parameter values to tabulate")
    p.set_defaults(func=run)


def run(args) -> int:
    from pathlib import Path

    from ..report import classification_report
    from ..storage import load
    if not Path(args.dataset).exists():
        raise FileNotFoundError(f"no dataset at {args.dataset}")
    ds = load(args.dataset)
    at = [float(v) for v in args.at.split(",")] if args.at else None
    text = classification_report(ds, at=at)
    if args.output:
        Path(args.output).write_text(text)
        print(f"wrote {args.output}")
    else:
        print(text)
    return 0
