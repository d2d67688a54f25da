"""`bifurc report`: markdown classification report of a diagram dataset."""
from ._common import add_force_option, check_outputs, parse_floats


def register(subparsers):
    p = subparsers.add_parser("report", help="period-1/period-2 classification report of a diagram")
    p.add_argument("dataset", help="netCDF written by `bifurc diagram`")
    p.add_argument("-o", "--output", default=None, help="markdown file (default: print)")
    p.add_argument("--at", default=None, help="comma-separated parameter values to tabulate")
    p.add_argument("--period-of", choices=("full", "mechanical"), default="full",
                   help="period convention: full (the whole state, coil current included) or mechanical (the "
                        "bar's position and velocity alone: the thesis' period-n)")
    add_force_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..storage.load import load
    from ..storage.files import write_text
    from ..report import classification_report
    at = parse_floats(args.at, "--at") if args.at else None
    check_outputs(args, args.output)
    ds = load(args.dataset, kind="diagram")
    text = classification_report(ds, at=at, period_of=args.period_of)
    if args.output:
        write_text(args.output, text, overwrite=args.force)
        print(f"wrote {args.output}")
    else:
        print(text)
    return 0
