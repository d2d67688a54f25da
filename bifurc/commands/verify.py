"""`bifurc verify`: the numerical stability suite, a markdown report and a dataset."""
from ._common import add_force_option, check_outputs


def register(subparsers):
    p = subparsers.add_parser("verify", help="numerical stability suite on stiff and extreme cases")
    p.add_argument("--quick", action="store_true", help="the reduced suite (a few seconds)")
    p.add_argument("--case", action="append", default=None, help="run only this case (repeatable)")
    p.add_argument("-o", "--output", default="out/verify", help="output folder")
    add_force_option(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from pathlib import Path

    from ..verification.suite import VERDICTS, run_suite, write_report
    check_outputs(args, *(Path(args.output) / f for f in ("stability.nc", "stability.md")))
    ds = run_suite(quick=args.quick, names=args.case)
    path = write_report(ds, args.output, overwrite=args.force)
    verdicts = [VERDICTS[int(v)] for v in ds.verdict.values]
    unexpected = [str(c) for c, v, e in zip(ds.case.values, ds.verdict.values, ds.expected.values) if v != e]
    print(f"{len(verdicts)} cases: " + ", ".join(f"{v} {verdicts.count(v)}" for v in VERDICTS if v in verdicts))
    if unexpected:
        print("  not as expected: " + ", ".join(unexpected))
    print(f"  wrote {path} and {path.with_suffix('.nc')}")
    return 0
