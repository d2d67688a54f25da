"""The explorer: click a stored diagram's value and see its orbit (``bifurc explore``, ``ds.bifurc.explore()``)."""
