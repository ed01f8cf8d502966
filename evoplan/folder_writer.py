"""One atomic folder writer: a command's results appear complete or not at all.

:func:`write_folder` writes every file into a temporary sibling folder ``.NAME.PID.partial``
(each file fsynced), then renames that folder to ``NAME`` in one step. A full disk (or any
write error) removes the temporary folder and is one line; a writer killed mid-way (SIGKILL
included) leaves only a hidden ``.partial`` folder, never a ``NAME`` that looks finished, and
the next writer removes the partial folders whose process is gone. ``--out`` may name a
folder that does not exist or an empty one (renaming onto an empty folder replaces it).
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

from .errors import EvoplanError

SUFFIX = ".partial"


def check_out(out: Path) -> None:
    """Refuse an ``--out`` that holds something (before any work is done)."""
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise EvoplanError(f"{out}: already exists and is not empty: choose another --out")


def remove_stale(out: Path) -> list[Path]:
    """Delete the ``.NAME.PID.partial`` folders of writers that died (their PID is gone)."""
    stale = []
    for p in out.parent.glob(f".{out.name}.*{SUFFIX}"):
        pid = p.name[len(out.name) + 2:-len(SUFFIX)]
        if pid.isdigit() and not _alive(int(pid)):
            shutil.rmtree(p, ignore_errors=True)
            stale.append(p)
    return stale


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def write_folder(out: str | Path, files: dict[str, bytes]) -> Path:
    """Write ``files`` (relative name -> bytes) as the folder ``out``, all or nothing."""
    out = Path(out)
    check_out(out)
    tmp = out.parent / f".{out.name}.{os.getpid()}{SUFFIX}"
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        remove_stale(out)
        shutil.rmtree(tmp, ignore_errors=True)
        tmp.mkdir()
        mode = 0o666 & ~_umask()
        for name, data in files.items():
            path = tmp / name
            path.parent.mkdir(parents=True, exist_ok=True)
            with open(path, "wb") as fh:
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
            os.chmod(path, mode)
        os.chmod(tmp, 0o777 & ~_umask())
        os.replace(tmp, out)
    except OSError as e:
        shutil.rmtree(tmp, ignore_errors=True)
        raise EvoplanError(f"{out}: cannot write the results ({e.strerror or type(e).__name__}); "
                           "nothing was written") from None
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    _fsync_dir(out.parent)
    return out


def _fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
