"""Verification of the integrator, apart from the analysis: is a computed number right?

- :mod:`~bifurc.verification.suite`: the numerical stability suite (stiff, chattering,
  grazing and extreme cases against extended precision; ``bifurc verify``);
- :mod:`~bifurc.verification.accuracy`: work-precision study (error against run time;
  ``bifurc accuracy``);
- :mod:`~bifurc.verification.baselines`: scipy and the thesis' fixed-step RK4, written
  independently of heyoka.
"""

from maps._lazy import lazy_exports

#: public name -> its submodule, imported on first use (``bifurc accuracy --help`` stays light)
_LAZY = {**dict.fromkeys(("plot_work_precision", "reference_solution", "work_precision"), "accuracy"),
         **dict.fromkeys(("solve_rk4_bisection", "solve_scipy"), "baselines"),
         **dict.fromkeys(("CASES", "QUICK", "VERDICTS", "run_case", "run_suite", "write_report"), "suite")}

__getattr__, __dir__ = lazy_exports(__name__, _LAZY, globals())
