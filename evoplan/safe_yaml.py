"""YAML input with limits: UTF-8 text, bounded size, depth and alias expansion, no duplicate keys.

Every file or ``--set`` value a user gives evoplan is read here. PyYAML's ``SafeLoader``
builds only plain data (no Python objects), but on its own it accepts inputs that break what
comes after it: a "billion laughs" alias bomb is small on disk and shared in memory, yet
expands exponentially when validated or printed; 20,000 nested brackets end in a
``RecursionError``; a repeated key silently keeps the last value. :class:`LimitedLoader`
refuses those while composing, and :func:`load_text` / :func:`load_file` turn every failure
into a :class:`~evoplan.errors.ConfigError` of one line that never quotes the input at length.
"""

from __future__ import annotations

import reprlib
from pathlib import Path
from typing import Any

import yaml
from yaml.constructor import ConstructorError
from yaml.nodes import CollectionNode, MappingNode

from .errors import ConfigError

MAX_BYTES = 4 * 1024 * 1024  # a run, study or zoning file; a control net of a few thousand poles
MAX_DEPTH = 64  # nested collections
MAX_ALIASES = 1000  # *alias uses
MAX_VALUES = 1_000_000  # scalars + collections once every alias is expanded


class YamlLimitError(yaml.YAMLError):
    """Input refused by a limit; ``problem`` and ``problem_mark`` as PyYAML's own errors."""

    def __init__(self, problem: str, mark=None) -> None:
        super().__init__(problem)
        self.problem, self.problem_mark = problem, mark


class LimitedLoader(yaml.SafeLoader):
    """``yaml.SafeLoader`` that refuses deep nesting, alias bombs and duplicate mapping keys."""

    def __init__(self, stream) -> None:
        super().__init__(stream)
        self._depth = 0
        self._aliases = 0

    def compose_node(self, parent, index):
        if self.check_event(yaml.AliasEvent):
            self._aliases += 1
            if self._aliases > MAX_ALIASES:
                raise YamlLimitError(f"more than {MAX_ALIASES} aliases", self.peek_event().start_mark)
        self._depth += 1
        if self._depth > MAX_DEPTH:
            raise YamlLimitError(f"nested deeper than {MAX_DEPTH} levels", self.peek_event().start_mark)
        try:
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def get_single_node(self):
        node = super().get_single_node()
        if node is not None:
            n = expanded_size(node)
            if n > MAX_VALUES:
                raise YamlLimitError(f"expands to more than {MAX_VALUES} values through its aliases",
                                     node.start_mark)
        return node

    def construct_mapping(self, node, deep=False):
        if isinstance(node, MappingNode):
            seen: set = set()
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    continue
                key = self.construct_object(key_node, deep=True)
                try:
                    duplicate = key in seen
                    seen.add(key)
                except TypeError:  # an unhashable key: the base class reports it
                    continue
                if duplicate:
                    raise ConstructorError(None, None, f"duplicate key {short(key)}", key_node.start_mark)
        return super().construct_mapping(node, deep=deep)


def expanded_size(root) -> int:
    """Number of values ``root`` stands for once every alias is copied out (shared nodes memoized)."""
    sizes: dict[int, int] = {}
    stack = [(root, False)]
    while stack:
        node, children_done = stack.pop()
        if id(node) in sizes:
            continue
        if not isinstance(node, CollectionNode):
            sizes[id(node)] = 1
            continue
        children = [c for pair in node.value for c in pair] if isinstance(node, MappingNode) else list(node.value)
        if children_done:
            sizes[id(node)] = min(1 + sum(sizes[id(c)] for c in children), MAX_VALUES + 1)
        else:
            stack.append((node, True))
            stack.extend((c, False) for c in children if id(c) not in sizes)
    return sizes[id(root)]


_short = reprlib.Repr()
_short.maxstring = _short.maxother = 60
_short.maxlevel, _short.maxlist, _short.maxdict = 2, 4, 4


ECHO_MAX = 100  # characters of an input an error line may echo


def short(value: Any) -> str:
    """``repr(value)`` cut to at most ``ECHO_MAX`` characters (an input is never echoed at
    length): ``reprlib`` bounds each string and container, and the total is cut too, since a
    list of mappings of long strings stays long in ``reprlib``'s bounds."""
    text = _short.repr(value)
    return text if len(text) <= ECHO_MAX else text[:ECHO_MAX - 3] + "..."


def key_text(key: Any) -> str:
    """A key of a key path as printed in an error: itself if short and printable, else its short repr."""
    text = str(key)
    return text if text.isprintable() and len(text) <= 60 else short(key)


def load_text(text: str, source: str) -> Any:
    """The data of YAML ``text``; any failure is one ``ConfigError`` line naming ``source``."""
    if len(text) > MAX_BYTES:
        raise ConfigError(f"{source}: larger than {MAX_BYTES // (1024 * 1024)} MiB: not a settings file")
    try:
        return yaml.load(text, Loader=LimitedLoader)  # noqa: S506 - LimitedLoader is a SafeLoader
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f"{source}:{mark.line + 1}" if mark is not None else source
        problem = getattr(e, "problem", None) or str(e).splitlines()[0]
        raise ConfigError(f"{where}: invalid YAML: {problem}") from None
    except RecursionError:
        raise ConfigError(f"{source}: invalid YAML: nested too deeply") from None
    except (ValueError, OverflowError) as e:  # a scalar PyYAML cannot convert (an int of 5000 digits)
        raise ConfigError(f"{source}: invalid YAML: {str(e).splitlines()[0][:120]}") from None


def read_text(path: str | Path) -> str:
    """The UTF-8 text of ``path`` (a BOM allowed); missing, unreadable, binary or oversized: one line."""
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            data = fh.read(MAX_BYTES + 1)
    except FileNotFoundError:
        raise ConfigError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise ConfigError(f"{path}: is a directory, not a file") from None
    except OSError as e:
        raise ConfigError(f"{path}: cannot read ({e.strerror})") from None
    if len(data) > MAX_BYTES:
        raise ConfigError(f"{path}: larger than {MAX_BYTES // (1024 * 1024)} MiB: not a settings file")
    if b"\0" in data:
        raise ConfigError(f"{path}: a binary file, not YAML text")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise ConfigError(f"{path}: not UTF-8 text (byte 0x{data[e.start]:02x} at offset {e.start})") from None


def load_file(path: str | Path) -> Any:
    """The data of the YAML file ``path``, read with :func:`read_text` and :func:`load_text`."""
    return load_text(read_text(path), str(path))
