"""`bifurc study`: run a named study of bifurc.studies (diagram, report, comparison with the thesis)."""
from ._common import add_force_option


def register(subparsers):
    p = subparsers.add_parser("study", help="run a named, reproducible study (bifurc/studies/)")
    p.add_argument("name", help="study name: thesis-1dof-relay, thesis-replay, thesis-orbits, regime-maps or "
                                "prototype-progression")
    p.add_argument("--quick", action="store_true", help="reduced size")
    p.add_argument("-o", "--output", default="out/study", help="output folder")
    p.add_argument("--case", action="append", default=None, help="run only this case (repeatable)")
    add_force_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..studies.run import _written, run_study
    run_study(args.name, args.output, quick=args.quick, cases=args.case, overwrite=args.force,
              hint="use --force")
    print(_written(args.name, args.output))
    return 0
