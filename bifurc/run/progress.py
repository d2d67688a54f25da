"""Progress of a grid: a bar over the planned work (text, or a widget in Jupyter), or none."""
from __future__ import annotations

import sys


class NoBar:
    def done(self, chunk):
        pass

    def close(self):
        pass


class PeriodBar:
    """Progress in relay periods integrated (copies included).  The total is the planned work: each
    value's first transient and record at the start, then what the values done used plus, for each
    value to come, the mean they used (never less than its first transient and record); the values
    done are shown beside it."""

    def __init__(self, bar, values: int, planned: int, unit: str):
        self.bar, self.values, self.planned, self.unit = bar, values, planned, unit
        self.count = self.used = 0

    def done(self, chunk):
        used = sum(max(int(getattr(r, "periods_integrated", 0)), 0) or self.planned for r in chunk)
        self.count += len(chunk)
        self.used += used
        self.bar.total = self.used + (self.values - self.count) * max(self.planned, self.used / self.count)
        self.bar.set_postfix_str(f"{self.count}/{self.values} {self.unit}", refresh=False)
        self.bar.update(used)

    def close(self):
        self.bar.close()


def progress_bar(values, planned, progress, desc, unit="values"):
    """A bar over ``values`` values of ``planned`` relay periods each (planned work), or one that shows nothing."""
    if not progress or values == 0:
        return NoBar()
    bar = tqdm_class()(total=values * planned, desc=desc, unit="period", unit_scale=True, file=sys.stderr, smoothing=0.1)
    return PeriodBar(bar, values, planned, unit)


def tqdm_class():
    """``tqdm.auto.tqdm`` where ipywidgets can be imported (a widget in Jupyter), else the text ``tqdm.tqdm``:
    ``tqdm.auto`` in Jupyter without ipywidgets warns (``TqdmWarning: IProgress not found``) and prints text anyway."""
    try:
        import ipywidgets  # noqa: F401
        from tqdm.auto import tqdm
    except ImportError:
        from tqdm import tqdm
    return tqdm
