"""What bifurc writes and reads: the table of dataset variables (:mod:`.schema`), the sweep
dataset's assembly and netCDF round trip (:mod:`.sweep_dataset`), safe file writing (atomic,
refusing an existing output, a lock per output: :mod:`.files`) and the user-facing loader with
one-line errors (:mod:`.load`, :func:`bifurc.load`).  Nothing is imported here: xarray loads
only where a dataset is built or read.
"""
