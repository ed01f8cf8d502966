"""``--set key.path=value``: settings of a run or study file changed on the command line.

Each item sets one key of the file's mapping before validation, so a bad key or value is
reported like one in the file: ``evoplan: error: FILE: key.path: message``. The value is read
as YAML (``--set algorithm.population=30``, ``--set problem.params.weights='{a: 0.5, b: 0.5}'``);
missing intermediate mappings are created.
"""

from __future__ import annotations

from typing import Any

from .errors import ConfigError
from .safe_yaml import load_text, short


def apply_settings(data: dict[str, Any], items: list[str], source: str) -> dict[str, Any]:
    """``data`` with every ``key.path=value`` of ``items`` set; a key given twice is refused
    (which one was meant is not for evoplan to guess)."""
    seen: dict[str, str] = {}
    for item in items:
        path, sep, text = item.partition("=")
        keys = [k.strip() for k in path.split(".")]
        if not sep or not all(keys):
            raise ConfigError(f"--set {item!r}: expected KEY.PATH=VALUE, e.g. algorithm.population=30")
        refuse_repeat(seen, ".".join(keys), text)
        value = load_text(text, f"--set {short(item)}") if text.strip() else ""  # limits as a file's
        node = data
        for i, key in enumerate(keys[:-1]):
            child = node.get(key)
            if child is None:
                child = node[key] = {}
            elif not isinstance(child, dict):
                where = ".".join(keys[: i + 1])
                raise ConfigError(f"{source}: {where}: is {child!r}, not a mapping (from --set {item})")
            node = child
        node[keys[-1]] = value
    return data


def refuse_repeat(seen: dict[str, str], key: str, text: str) -> None:
    """One-line error when ``key`` was already set by an earlier ``--set`` (``seen``: key -> text)."""
    if key in seen:
        raise ConfigError(f"--set {short(key)}: given twice ({short(seen[key])} and {short(text)}): "
                          "give each key once")
    seen[key] = text


def add_argument(parser, example: str = "--set algorithm.population=30 --set termination.generations=100") -> None:
    """The ``--set`` option of ``run``, ``study`` and ``machine`` (``example``: for its help)."""
    parser.add_argument("--set", dest="settings", action="append", default=[], metavar="KEY.PATH=VALUE",
                        help=f"change a setting of the file, e.g. {example} (repeatable)")
