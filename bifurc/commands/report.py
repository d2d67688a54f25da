"""`bifurc report`: the markdown report of any bifurc dataset (diagram, map, attractors, branch, orbit, time
history, accuracy, stability)."""
from ._common import add_force_option, check_outputs, parse_floats


def register(subparsers):
    p = subparsers.add_parser("report", help="markdown report of a dataset (diagram, map, attractors, branch, ...)",
                              description="The markdown report of a netCDF file written by bifurc: the classification "
                                          "report of a diagram, the per-value table of an attractor census (each "
                                          "event with the parameter value where it was located), a summary of a "
                                          "map, branch, orbit, time history, accuracy or stability dataset.")
    p.add_argument("dataset", help="netCDF written by bifurc (diagram, map, attractors, continue, orbit, simulate, ...)")
    p.add_argument("-o", "--output", default=None, help="markdown file (default: print)")
    p.add_argument("--at", default=None, help="diagram only: comma-separated parameter values to tabulate")
    p.add_argument("--period-of", choices=("full", "mechanical"), default=None,
                   help="diagram only: period convention, full (the whole state, coil current included; the default) "
                        "or mechanical (the bar's position and velocity alone: the thesis' period-n)")
    add_force_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from maps.parameters import ParameterError

    from ..report import REPORTS, report
    from ..storage.files import BadFileError, write_text
    from ..storage.load import kind_of, load
    at = parse_floats(args.at, "--at") if args.at else None
    check_outputs(args, args.output)
    ds = load(args.dataset)
    kind = kind_of(ds)
    if kind not in REPORTS:
        raise BadFileError(f"{args.dataset} is not a bifurc dataset (no bifurc_kind attribute); reports exist for "
                           f"{', '.join(REPORTS)} datasets")
    if kind != "diagram":
        for name, given in (("--at", args.at), ("--period-of", args.period_of)):
            if given is not None:
                raise ParameterError(f"{name}: for a diagram dataset only; {args.dataset} holds {'an' if kind[0] in 'aeiou' else 'a'} {kind} dataset")
    kw = {"at": at, "period_of": args.period_of or "full"} if kind == "diagram" else {}
    try:
        text = report(ds, kind, **kw)
    except (KeyError, AttributeError) as exc:     # the kind's attribute, but not its variables
        missing = exc.args[0] if isinstance(exc, KeyError) else getattr(exc, "name", None) or exc
        raise BadFileError(f"{args.dataset} holds {'an' if kind[0] in 'aeiou' else 'a'} {kind} dataset without "
                           f"what its report reads ({missing!s}); written by another version, or incomplete") from None
    if args.output:
        write_text(args.output, text, overwrite=args.force)
        print(f"wrote {args.output}")
    else:
        print(text)
    return 0
