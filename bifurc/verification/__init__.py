"""Verification of the integrator, apart from the analysis: is a computed number right?

- :mod:`~bifurc.verification.suite`: the numerical stability suite (stiff, chattering,
  grazing and extreme cases against extended precision; ``bifurc verify``);
- :mod:`~bifurc.verification.accuracy`: work-precision study (error against run time;
  ``bifurc accuracy``);
- :mod:`~bifurc.verification.baselines`: scipy and the thesis' fixed-step RK4, written
  independently of heyoka.
"""
from .accuracy import plot_work_precision, reference_solution, work_precision
from .baselines import solve_rk4_bisection, solve_scipy
from .suite import CASES, QUICK, VERDICTS, run_case, run_suite, write_report

__all__ = ["CASES", "QUICK", "VERDICTS", "run_case", "run_suite", "write_report", "work_precision",
           "reference_solution", "plot_work_precision", "solve_scipy", "solve_rk4_bisection"]
