"""A progress line of named stages for the long commands (``zone``, ``machine``).

One tqdm line on stderr, ``desc: n/total stage [elapsed]``, shown only on a terminal and
silenced by ``--quiet``. Calling the object with a stage's name closes the stage before it.
"""

from __future__ import annotations

import sys


class Stages:
    """``stage = Stages("zone", 5, quiet)``; ``stage("passes")`` at the start of each stage;
    ``stage.finish()`` when the last one ends; ``stage.close()`` always (a ``with`` block)."""

    def __init__(self, desc: str, total: int, quiet: bool = False) -> None:
        from tqdm import tqdm

        self.bar = tqdm(total=total, desc=desc, unit="stage", disable=True if quiet else None,
                        file=sys.stderr, bar_format="{desc}: {n}/{total} {postfix} [{elapsed}]")
        self.names: list[str] = []

    def __call__(self, name: str) -> None:
        if self.names:
            self.bar.update()
        self.names.append(name)
        self.bar.set_postfix_str(name)

    def finish(self) -> None:
        self.bar.update(self.bar.total - self.bar.n)

    def close(self) -> None:
        self.bar.close()

    def __enter__(self) -> "Stages":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
