"""``evoplan examples [NAME] [--out DIR]``: the run and study files shipped with evoplan.

Without NAME, lists them (name and the first sentence of the file's opening comment). With NAME (``kubota_vega`` or
``kubota_vega.yaml``), copies that file to DIR (default: the current folder) and prints its
path, ready for ``evoplan run`` or ``evoplan study``. The files travel inside the installed
package (``evoplan.examples``, the repository's ``runs/*.yaml``), so this works from a wheel
installed anywhere. A part file the example names (``file: parts/wavy_mesh.stl``) is copied
with it, to the same relative place under DIR.
"""

from __future__ import annotations

import argparse
from importlib import resources
from pathlib import Path

from ..errors import EvoplanError
from . import COMMANDS


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("examples", help=COMMANDS["examples"])
    p.add_argument("name", nargs="?", help="the example to copy, e.g. kubota_vega")
    p.add_argument("--out", default=".", help="folder to copy it into (default: here)")
    return p


def shipped() -> dict[str, resources.abc.Traversable]:
    """Name -> file of every shipped example, sorted by name."""
    root = resources.files("evoplan.examples")
    files = {f.name.removesuffix(".yaml"): f for f in root.iterdir() if f.name.endswith(".yaml")}
    return dict(sorted(files.items()))


_ABBREVIATIONS = ("Eq.", "Eqs.", "Sec.", "al.", "Fig.", "e.g.", "i.e.", "vs.", "No.", "cf.")


def summary(text: str) -> str:
    """The first sentence of a YAML file's opening comment (whole, never cut), or its kind."""
    words: list[str] = []
    for line in text.splitlines():
        if not line.startswith("#"):
            break
        body = line.lstrip("#").strip()
        if not body:
            if words:
                break
            continue
        words += body.split()
    for i, word in enumerate(words):
        if word.endswith((".", "!", "?")) and not word.endswith(_ABBREVIATIONS):
            return " ".join(words[: i + 1])
    if words:
        return " ".join(words)
    return "study" if "\nalgorithms:" in f"\n{text}" else "run"


def referenced(text: str) -> list[str]:
    """The shipped files (relative paths, e.g. ``parts/wavy_mesh.stl``) a run file's values
    name, so that a copied example finds them beside it."""
    import yaml

    root = resources.files("evoplan.examples")
    found: list[str] = []

    def walk(node):
        if isinstance(node, dict):
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)
        elif isinstance(node, str) and "/" in node and not Path(node).is_absolute() \
                and ".." not in Path(node).parts:
            target = root.joinpath(*Path(node).parts)
            if target.is_file() and node not in found:
                found.append(node)

    walk(yaml.safe_load(text))
    return found


def main(args: argparse.Namespace) -> int:
    files = shipped()
    if not args.name:
        import shutil
        import textwrap

        width = max(map(len, files), default=0)
        columns = max(60, shutil.get_terminal_size((100, 24)).columns)
        for name, f in files.items():
            lines = textwrap.wrap(summary(f.read_text()), columns - width - 2) or [""]
            print(f"{name:<{width}}  {lines[0]}")
            for line in lines[1:]:
                print(f"{'':<{width}}  {line}")
        return 0
    name = args.name.removesuffix(".yaml")
    if name not in files:
        raise EvoplanError(f"no example {args.name!r} (known: {', '.join(files)})")
    out = Path(args.out)
    if out.exists() and not out.is_dir():
        raise EvoplanError(f"--out {out}: not a folder")
    target = out / f"{name}.yaml"
    text = files[name].read_text()
    parts = referenced(text)
    for dest in [target, *(out / p for p in parts)]:
        if dest.exists():
            raise EvoplanError(f"{dest}: already exists")
    out.mkdir(parents=True, exist_ok=True)
    root = resources.files("evoplan.examples")
    for p in parts:
        (out / p).parent.mkdir(parents=True, exist_ok=True)
        (out / p).write_bytes(root.joinpath(*Path(p).parts).read_bytes())
    target.write_text(text)
    print(target)
    return 0
