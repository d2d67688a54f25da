"""Output files: never overwritten silently, one writer at a time, the user's umask, compressed netCDF.

- :func:`refuse_existing` raises :class:`FileExistsError` for an existing output unless
  ``overwrite`` (the API's ``overwrite=False``, the command line's ``--force``).
- :func:`output_lock` takes ``<output>.lock`` with ``fcntl.flock`` (POSIX only: on Windows
  it is a no-op); a second writer of the same output gets :class:`OutputBusy` at once.
- :func:`write_netcdf` writes through a temporary file and ``os.replace`` (a reader never
  sees half a file), with the mode the user's umask gives (not ``mkstemp``'s 0600), zlib
  level 4 with shuffle on every numeric variable, and the CF global attributes of
  :func:`maps.provenance.cf_attrs` where the dataset lacks them.
- :func:`save_figure` checks the figure format before anything is written.
"""
from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
import threading
from pathlib import Path

from maps.parameters import ParameterError
from maps.provenance import cf_attrs

try:
    import fcntl
except ImportError:  # not POSIX: no lock
    fcntl = None

#: variable attribute: the name of a variable stored under another one (:func:`stored_names`)
STORED_AS = "bifurc_name"
#: on disk and in memory, a simulation's elapsed time [s] is a plain coordinate ``t``: units "s", no
#: ``standard_name = "time"`` and no epoch, so that ``xr.open_dataset`` reads it as float seconds (a CF
#: time coordinate needs "<unit> since <epoch>", which every netCDF reader decodes to dates); named ``t``, not
#: ``time``, since CF checkers take a coordinate named ``time`` for a CF time axis (IOOS checker, section 5.1)
ELAPSED_ATTRS = {"units": "s", "long_name": "time", "comment": "elapsed time from the start of the integration"}
#: files written before 0.2 stored elapsed time as a CF time coordinate with a nominal epoch;
#: :func:`bifurc.storage.load.read` gives such a variable :data:`ELAPSED_ATTRS` back
LEGACY_ELAPSED_UNITS = "s since 1970-01-01 00:00:00"


def without_time_axis(attrs: dict) -> dict:
    """An elapsed time's attributes without those of a CF time axis (``standard_name``, ``calendar``)."""
    return {k: v for k, v in attrs.items() if k not in ("standard_name", "calendar")}

#: dataset attributes that name a parameter with a variable of its own
PARAMETER_ATTRS = ("swept_parameter", "swept_parameter2", "continuation_parameter")
#: zlib level of every numeric netCDF variable (4: most of level 9's gain at a fraction of its time)
ZLIB_LEVEL = 4
#: per-variable encodings kept when a dataset read from a file is written again
_KEEP_ENCODING = ("dtype", "_FillValue", "scale_factor", "add_offset", "units", "calendar")
_UMASK_LOCK = threading.Lock()


class OutputBusy(FileExistsError):
    """Another run is writing the same output (its ``<output>.lock`` is held)."""


class BadFileError(ValueError):
    """An input file that cannot be used: corrupt, truncated, or of another kind."""


class OutputError(OSError):
    """An output that cannot be written (read-only or full file system, no permission): one line."""


def refuse_existing(path, overwrite: bool = False, hint: str = "pass overwrite=True") -> None:
    """Raise :class:`IsADirectoryError` if ``path`` is a folder (``overwrite`` or not), and
    :class:`FileExistsError` if it exists and ``overwrite`` is false."""
    if path is not None and os.path.isdir(path):
        raise IsADirectoryError(f"{path} is a folder, not a file; name a file to write")
    if path is not None and not overwrite and os.path.lexists(path):
        raise FileExistsError(f"{path} exists; {hint} to replace it")


def size_text(n: float) -> str:
    """Bytes in words: "0.92 MB", "6.9e+04 GB"."""
    return f"{n / 1e6:.3g} MB" if n < 1e9 else f"{n / 1e9:.3g} GB"


def proc_field(path: str, key: str):
    """The first word after ``key:`` in a /proc file such as /proc/meminfo (None: no such file or line)."""
    try:
        with open(path) as fh:
            for line in fh:
                if line.startswith(f"{key}:"):
                    return line.split()[1]
    except OSError:
        pass
    return None


def _reason(exc) -> str:
    """An OS error's reason in words ("read-only file system", "no space left on device")."""
    return (exc.strerror or str(exc) or type(exc).__name__).lower()


def check_writable(path, need_bytes: float = 0) -> Path:
    """Before computing: ``path`` can be written. Its folder, or the nearest existing folder above it
    (nothing is created), accepts a new file (a probe file is written and removed) and its file
    system has ``need_bytes`` free; else :class:`OutputError` in one line (a folder at ``path``:
    :class:`IsADirectoryError`; a file where a folder must be: :class:`NotADirectoryError`)."""
    path = Path(path)
    refuse_existing(path, overwrite=True)
    folder = next((p for p in path.absolute().parents if os.path.lexists(p)), Path("/"))
    if not folder.is_dir():
        raise NotADirectoryError(f"cannot write {path}: {folder} is a file, not a folder")
    try:
        fd, probe = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".probe", dir=folder)
        os.close(fd)
        os.unlink(probe)
        free = shutil.disk_usage(folder).free
    except OSError as exc:
        raise OutputError(f"cannot write {path}: {_reason(exc)}") from None
    if need_bytes > free:
        raise OutputError(f"cannot write {path}: it needs about {size_text(need_bytes)} and its file system has "
                          f"{size_text(free)} free")
    return path


def user_umask() -> int:
    """The process umask (read without changing it where /proc allows)."""
    umask = proc_field("/proc/self/status", "Umask")
    if umask is not None:
        return int(umask, 8)
    with _UMASK_LOCK:
        mask = os.umask(0o077)
        os.umask(mask)
    return mask


def _lock_path(path) -> Path:
    return Path(str(path) + ".lock")


def make_parent(path) -> Path:
    """Create the folder of ``path`` (one line if a file stands where a folder must be); returns ``path``."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        blocker = next((p for p in reversed(path.parents) if p.exists() and not p.is_dir()), path.parent)
        raise NotADirectoryError(f"cannot write {path}: {blocker} is a file, not a folder") from None
    return path


@contextlib.contextmanager
def output_lock(path):
    """Hold ``<path>.lock`` (``fcntl.flock``, exclusive, non-blocking) while writing ``path``.

    Raises :class:`OutputBusy` at once if another run holds it. The lock file is removed on
    release. POSIX only: without ``fcntl`` (Windows) nothing is locked.
    """
    if fcntl is None:
        yield
        return
    lock = _lock_path(make_parent(path))
    while True:
        try:
            fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as exc:
            raise OutputError(f"cannot write {path}: {_reason(exc)} (its lock {lock})") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise OutputBusy(f"{path} is being written by another run (lock {lock} held); "
                             "wait for it or choose another output") from None
        try:  # the holder before us may have removed the file we locked: lock the current one
            if os.stat(lock).st_ino == os.fstat(fd).st_ino:
                break
        except FileNotFoundError:
            pass
        os.close(fd)
    try:
        yield
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(lock)
        os.close(fd)


@contextlib.contextmanager
def output_guard(path, overwrite: bool = False):
    """Around a call that writes ``path`` (None: nothing to guard): it must be writable (:func:`check_writable`,
    before any work), the output lock is held during the call, an existing output is refused unless ``overwrite``,
    and a ``<path>.parts/`` folder this call created is removed again if the call fails before completing any part
    (a refused argument leaves nothing that would block the corrected call).  An interrupted call keeps its
    completed parts: a rerun resumes."""
    if path is None:
        yield
        return
    parts = Path(str(path) + ".parts")
    check_writable(path)
    with output_lock(path):
        refuse_existing(path, overwrite)
        fresh = not parts.exists()
        try:
            yield
        except BaseException:
            if fresh and parts.is_dir() and all(f.name.startswith("manifest") for f in parts.iterdir()):
                shutil.rmtree(parts, ignore_errors=True)
            raise


def _encoding(ds) -> dict:
    """zlib on every numeric variable; no ``_FillValue`` on a coordinate variable (CF-1.10 2.5.1)."""
    enc = {}
    for name, var in ds.variables.items():
        if var.ndim and var.dtype.kind in "fiub":
            keep = {k: v for k, v in var.encoding.items() if k in _KEEP_ENCODING}
            enc[name] = {**keep, "zlib": True, "complevel": ZLIB_LEVEL, "shuffle": True}
            if name in ds.dims:
                enc[name]["_FillValue"] = None
    return enc


def stored_names(ds) -> dict:
    """CF-1.10 2.3: no two variable names may differ only by case. A parameter's variable beside a
    state of the same letter (``V`` and ``v`` in a sweep or branch in ``V``) is stored as
    ``V_parameter`` (any other clash as ``NAME_2``, ...), with attribute :data:`STORED_AS` giving
    its name back; returns {name: stored name} of the renamed variables."""
    params = {ds.attrs.get(k) for k in PARAMETER_ATTRS}
    groups = {}
    for name in ds.variables:
        groups.setdefault(str(name).lower(), []).append(name)
    taken, out = {str(n).lower() for n in ds.variables}, {}
    for names in groups.values():
        keep = next((n for n in names if n not in params), names[0])
        for k, name in enumerate([n for n in names if n != keep], start=2):
            new = f"{name}_parameter" if name in params else f"{name}_{k}"
            while new.lower() in taken:
                new += "_"
            taken.add(new.lower())
            out[name] = new
    return out


def _publish(tmp, path) -> None:
    """Give ``tmp`` the mode of a newly created file under the user's umask, then rename it to ``path``."""
    os.chmod(tmp, 0o666 & ~user_umask())
    os.replace(tmp, path)


def _temporary(path: Path) -> str:
    make_parent(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    return tmp


def write_netcdf(ds, path, overwrite: bool = False) -> Path:
    """Write ``ds`` to netCDF ``path`` atomically, zlib-compressed, with CF provenance; returns the path.

    ``Conventions``, ``history`` and ``source`` are added where ``ds`` lacks them (``ds`` itself is
    not changed). The file gets the permissions of any file the user creates (umask).
    """
    path = Path(path)
    refuse_existing(path, overwrite)
    out = ds.copy(deep=False)
    out.attrs = {**cf_attrs(), **ds.attrs}
    renamed = stored_names(out)
    if renamed:
        out = out.rename(renamed)
        for old, new in renamed.items():
            out[new].attrs = {**out[new].attrs, STORED_AS: old}
    for name, var in out.variables.items():
        if var.attrs.get("standard_name") == "time" and var.attrs.get("units") == "s":  # an elapsed time
            out[name].attrs = without_time_axis(var.attrs)
    try:
        tmp = _temporary(path)
    except OSError as exc:
        raise OutputError(f"cannot write {path}: {_reason(exc)}") from None
    try:
        out.to_netcdf(tmp, encoding=_encoding(out))
        _publish(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        if isinstance(exc, (OSError, RuntimeError)) and not isinstance(exc, OutputError):  # netCDF: "HDF error"
            raise OutputError(f"cannot write {path}: {_write_failure(exc, path)}") from None
        raise
    return path


def _write_failure(exc, path) -> str:
    """Why writing ``path`` failed: a full file system is named as such (netCDF says "HDF error")."""
    with contextlib.suppress(OSError):
        if shutil.disk_usage(Path(path).parent).free < 1e6:
            return "no space left on device"
    return _reason(exc) if isinstance(exc, OSError) else " ".join(str(exc).split())


def write_text(path, text: str, overwrite: bool = False) -> Path:
    """Write ``text`` to ``path`` (refused if it exists and not ``overwrite``); returns the path."""
    path = Path(path)
    refuse_existing(path, overwrite)
    try:
        make_parent(path).write_text(text)
    except OSError as exc:
        if isinstance(exc, (NotADirectoryError, IsADirectoryError)):
            raise
        raise OutputError(f"cannot write {path}: {_reason(exc)}") from None
    return path


def check_figure_path(path, what: str = "figure path") -> Path:
    """``path`` as a Path if matplotlib can write its format (by extension), else :class:`ParameterError`."""
    from matplotlib.backend_bases import FigureCanvasBase
    path = Path(path)
    formats = FigureCanvasBase.get_supported_filetypes()
    ext = path.suffix[1:].lower()
    if ext not in formats:
        found = f".{ext} is not a figure format" if ext else "no extension gives the figure format"
        raise ParameterError(f"{what} {str(path)!r}: {found}; use one of "
                             f"{', '.join('.' + f for f in sorted(formats))}")
    return path


def check_figure_output(path, overwrite: bool = False, what: str = "figure path") -> Path:
    """Before drawing: the format is one matplotlib writes and an existing file is not in the way."""
    path = check_figure_path(path, what)
    refuse_existing(path, overwrite)
    return path


def save_figure(fig, path, overwrite: bool = False, dpi: int = 130, close: bool = True) -> Path:
    """Save ``fig`` to ``path`` (format from the extension, checked first) and close it if ``close``."""
    path = make_parent(check_figure_output(path, overwrite))
    try:
        fig.savefig(path, dpi=dpi)
    except OSError as exc:
        raise OutputError(f"cannot write {path}: {_reason(exc)}") from None
    if close:
        import matplotlib.pyplot as plt
        plt.close(fig)
    return path
