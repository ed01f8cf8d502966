"""``evoplan examples [NAME] [--out DIR]``: the run and study files shipped with evoplan.

Without NAME, lists them (name and first comment line). With NAME (``kubota_vega`` or
``kubota_vega.yaml``), copies that file to DIR (default: the current folder) and prints its
path, ready for ``evoplan run`` or ``evoplan study``. The files travel inside the installed
package (``evoplan.examples``, the repository's ``runs/*.yaml``), so this works from a wheel
installed anywhere.
"""

from __future__ import annotations

import argparse
from importlib import resources
from pathlib import Path

from ..errors import EvoplanError


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("examples", help="list the shipped run and study files, or copy one")
    p.add_argument("name", nargs="?", help="the example to copy, e.g. kubota_vega")
    p.add_argument("--out", default=".", help="folder to copy it into (default: here)")
    return p


def shipped() -> dict[str, resources.abc.Traversable]:
    """Name -> file of every shipped example, sorted by name."""
    root = resources.files("evoplan.examples")
    files = {f.name.removesuffix(".yaml"): f for f in root.iterdir() if f.name.endswith(".yaml")}
    return dict(sorted(files.items()))


def summary(text: str) -> str:
    """The first comment line of a YAML file, or its kind."""
    for line in text.splitlines():
        if line.startswith("#"):
            return line.lstrip("# ").strip()
    return "study" if "\nalgorithms:" in f"\n{text}" else "run"


def main(args: argparse.Namespace) -> int:
    files = shipped()
    if not args.name:
        width = max(map(len, files), default=0)
        for name, f in files.items():
            print(f"{name:<{width}}  {summary(f.read_text())}")
        return 0
    name = args.name.removesuffix(".yaml")
    if name not in files:
        raise EvoplanError(f"no example {args.name!r} (known: {', '.join(files)})")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise EvoplanError(f"--out {out}: not a folder")
    target = out / f"{name}.yaml"
    if target.exists():
        raise EvoplanError(f"{target}: already exists")
    out.mkdir(parents=True, exist_ok=True)
    target.write_text(files[name].read_text())
    print(target)
    return 0
