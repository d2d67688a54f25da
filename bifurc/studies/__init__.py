"""Named, reproducible studies: one small module each, run by ``python -m bifurc.studies.run NAME``."""
