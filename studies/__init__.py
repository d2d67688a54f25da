"""Named, reproducible studies: one small module each, run by ``python -m studies.run NAME``."""
