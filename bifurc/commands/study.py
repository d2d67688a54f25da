"""`bifurc study`: run a named study from studies/ (diagram, report, comparison with the thesis)."""
from ._common import add_force_option


def register(subparsers):
    p = subparsers.add_parser("study", help="run a named, reproducible study (see studies/)")
    p.add_argument("name", help="study name, e.g. thesis-1dof-relay")
    p.add_argument("--quick", action="store_true", help="reduced size")
    p.add_argument("-o", "--output", default="out/study", help="output folder")
    p.add_argument("--case", action="append", default=None, help="run only this case (repeatable)")
    add_force_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    try:
        from studies.run import run_study
    except ModuleNotFoundError:
        from maps.parameters import ParameterError
        raise ParameterError("the studies/ folder is not importable: run from the repository root") from None
    run_study(args.name, args.output, quick=args.quick, cases=args.case, overwrite=args.force,
              hint="use --force")
    print(f"wrote {args.output}/comparison.md and one .nc/.png/.md per case")
    return 0
