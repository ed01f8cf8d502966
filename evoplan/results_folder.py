"""A run's results folder, claimed by one run at a time.

A new run creates its folder (parents included) and takes an exclusive ``flock`` on the
folder itself before anything is written into it; the lock is held until the run ends and is
released by the kernel when the process dies (SIGKILL included), so a crashed run never leaves
a stale lock, and no lock file is left in the folder. A second run aimed at the same ``--out``
(or resuming a folder that a live run is writing) gets a one-line error instead of silently
mixing its files with the first one's. A new run refuses a folder that already holds files.
"""

from __future__ import annotations

import errno
import fcntl
import os
import shutil
from pathlib import Path

from .errors import ConfigError

class FolderClaim:
    """An exclusive claim on a results folder; ``release()`` (or process exit) gives it up."""

    def __init__(self, out: Path, fd: int, created: bool) -> None:
        self.out, self._fd, self.created = out, fd, created

    def release(self) -> None:
        if self._fd is not None:
            os.close(self._fd)  # closing the descriptor drops the flock
            self._fd = None

    def abandon(self) -> None:
        """Release, and remove the folder if this claim created it (nothing of the run is kept)."""
        self.release()
        if self.created:
            shutil.rmtree(self.out, ignore_errors=True)


def _os_message(e: OSError) -> str:
    return e.strerror or type(e).__name__


def claim(out: Path, new: bool) -> FolderClaim:
    """Lock ``out`` for one run; ``new``: create it, and refuse a folder that holds files."""
    out = Path(out)
    created = False
    if new:
        if out.exists() and not out.is_dir():
            raise ConfigError(f"{out}: exists and is not a folder: choose another --out")
        try:
            created = not out.exists()
            out.mkdir(parents=True, exist_ok=True)
        except NotADirectoryError:
            raise ConfigError(f"{out}: a parent of this folder is a file: choose another --out") from None
        except OSError as e:
            raise ConfigError(f"{out}: cannot create the results folder ({_os_message(e)})") from None
    try:
        fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY)
    except OSError as e:
        raise ConfigError(f"{out}: cannot open the results folder ({_os_message(e)})") from None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as e:
        os.close(fd)
        if e.errno in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
            raise ConfigError(f"{out}: another evoplan run is writing into this folder") from None
        raise ConfigError(f"{out}: cannot lock the results folder ({_os_message(e)})") from None
    c = FolderClaim(out, fd, created)
    remove_stale_temp(out)  # a killed run's half-written files, before the folder is judged empty
    if new and any(out.iterdir()):
        c.release()
        raise ConfigError(f"{out}: already exists and is not empty: choose another --out, or --resume it")
    return c


def remove_stale_temp(out: Path) -> list[Path]:
    """Delete the temporary files of writes a killed run left half done (``.NAME.XXXX.tmp``)."""
    stale = [p for p in Path(out).glob(".*.tmp") if p.is_file()]
    for p in stale:
        p.unlink(missing_ok=True)
    return stale
