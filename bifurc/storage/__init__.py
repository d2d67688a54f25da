"""What bifurc writes and reads, the lowest floor of the package: the table of dataset variables
(:mod:`.schema`), the generic builder that records a dataset's kind (:mod:`.build`), safe file
writing (atomic, refusing an existing output, a lock per output: :mod:`.files`) and the user-facing
loader with one-line errors (:mod:`.load`, :func:`bifurc.load`).  The per-kind builders live next to
their producers (:mod:`bifurc.sweeps.dataset`, :mod:`bifurc.orbits.dataset`); nothing here imports
them.  Nothing is imported here: xarray loads only where a dataset is built or read.
"""
