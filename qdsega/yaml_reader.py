"""Safe YAML loading that remembers source lines, and typed reads with one-line errors.

Only plain YAML (mappings, sequences, scalars) is accepted: the document is composed into
nodes and converted by hand, so no Python object is ever constructed from a tag; file size,
nesting and the number of values (aliases expanded) are bounded.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import yaml

from qdsega.errors import FormationError, QdsegaError

KeyPath = tuple[str | int, ...]
_Choice = TypeVar("_Choice", bound=str)


@dataclass(frozen=True)
class Interval:
    """The allowed values of one kind of number: ``low <= x <= high`` (``low < x`` if
    ``open_low``)."""

    low: float
    high: float
    open_low: bool = False

    def __contains__(self, value: float) -> bool:
        above = value > self.low if self.open_low else value >= self.low
        return above and value <= self.high

    def __str__(self) -> str:
        return f"{'(' if self.open_low else '['}{self.low:g}, {self.high:g}]"


MAX_FILE_BYTES = 64 * 1024
"""Largest YAML file read (bytes); shipped formations are about 1 KiB."""

MAX_YAML_DEPTH = 32
"""Deepest nesting of mappings and lists in a YAML file; formations need about 6."""

MAX_YAML_VALUES = 100_000
"""Values (mappings, lists, scalars, keys) in a YAML file, aliases expanded; legged12 has 114."""


def format_key_path(path: KeyPath) -> str:
    """``("units", 3, "parent")`` -> ``"units[3].parent"``."""
    text = ""
    for part in path:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else part)
    return text


@dataclass(frozen=True)
class YamlDocument:
    """A parsed YAML file: plain data plus the 1-based source line of every key path."""

    file: Path
    data: Any
    lines: dict[KeyPath, int]
    error_type: type[QdsegaError] = FormationError

    def line(self, path: KeyPath) -> int | None:
        """Line of ``path``, or of its nearest ancestor that has one."""
        for end in range(len(path), -1, -1):
            if path[:end] in self.lines:
                return self.lines[path[:end]]
        return None

    def error(self, path: KeyPath, message: str) -> QdsegaError:
        """An error of this file's kind located at ``path`` in it."""
        return self.error_type(
            message, file=self.file, line=self.line(path), key_path=format_key_path(path) or None
        )


def load_yaml(file: Path, *, error_type: type[QdsegaError] = FormationError) -> YamlDocument:
    """Read ``file`` as plain YAML; raise ``error_type`` (a formation's by default) for anything
    else, with the file, line and key path."""
    try:
        size = file.stat().st_size
        if size > MAX_FILE_BYTES:
            raise error_type(f"file is {size} bytes; at most {MAX_FILE_BYTES}", file=file)
        text = file.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error_type("file not found", file=file) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error_type(f"cannot read file ({exc.__class__.__name__})", file=file) from None
    try:
        root = _compose(text)
    except RecursionError:
        raise error_type(f"nested deeper than {MAX_YAML_DEPTH} levels", file=file) from None
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = None if mark is None else mark.line + 1
        problem = exc.problem or exc.context or "invalid YAML"
        raise error_type(f"YAML syntax error: {problem}", file=file, line=line) from None
    except yaml.reader.ReaderError as exc:  # a character YAML forbids (NUL, ...): no mark
        line = text.count("\n", 0, exc.position) + 1
        message = f"YAML syntax error: unacceptable character #x{exc.character:04x} ({exc.reason})"
        raise error_type(message, file=file, line=line) from None
    except yaml.YAMLError as exc:
        raise error_type(f"YAML error: {exc}", file=file) from None
    if root is None:
        raise error_type("file is empty", file=file)
    converter = _Converter(file, error_type)
    data = converter.plain(root, ())
    return YamlDocument(file=file, data=data, lines=converter.lines, error_type=error_type)


_FAST_LOADER: type[yaml.CSafeLoader] | None = getattr(yaml, "CSafeLoader", None)
"""libyaml's safe loader, where PyYAML was built with it: the same nodes, composed in C (a
formation reads about eight times faster than with the pure-Python loader)."""


def _compose(text: str) -> yaml.Node | None:
    """The document's root node, composed by libyaml where it can; a document it refuses is
    composed again by the pure-Python loader, whose error names the problem and its line
    in the words every installation gives."""
    if _FAST_LOADER is not None:
        try:
            return yaml.compose(text, Loader=_FAST_LOADER)
        except yaml.YAMLError:
            pass
    return yaml.compose(text, Loader=yaml.SafeLoader)


_SCALAR_CONSTRUCTOR = yaml.SafeLoader("")


class _Converter:
    """Composed YAML nodes -> plain data, recording the line of every key path.

    An alias (``*name``) is expanded into a copy of its anchor, so values are counted: a few
    lines of nested aliases could otherwise expand into billions. An alias inside its own
    anchor is refused.
    """

    def __init__(self, file: Path, error_type: type[QdsegaError]) -> None:
        self.file = file
        self.error_type = error_type
        self.lines: dict[KeyPath, int] = {}
        self.values = 0
        self.open: set[int] = set()
        """Nodes being converted (the current node's ancestors)."""

    def plain(self, node: yaml.Node, path: KeyPath, *, record: bool = True) -> Any:
        file = self.file

        def error(message: str) -> QdsegaError:
            """``message`` at this node, as the document's error type."""
            return self.error_type(
                message, file=file, line=node.start_mark.line + 1, key_path=format_key_path(path)
            )

        if id(node) in self.open:
            raise error("a YAML alias inside its own anchor")
        self.values += 1
        if self.values > MAX_YAML_VALUES:
            raise error(f"more than {MAX_YAML_VALUES} values (aliases expanded)")
        if record:
            self.lines[path] = node.start_mark.line + 1
        if len(path) > MAX_YAML_DEPTH:
            raise error(f"nested deeper than {MAX_YAML_DEPTH} levels")
        if isinstance(node, yaml.ScalarNode):
            try:
                return _SCALAR_CONSTRUCTOR.construct_object(node)
            except yaml.constructor.ConstructorError:
                raise error(f"unsupported YAML tag {node.tag}") from None
            except ValueError:  # an integer of more digits than Python converts
                message = f"a number of {len(node.value)} digits is too long"
                raise error(message) from None
        if isinstance(node, yaml.SequenceNode):
            if node.tag != "tag:yaml.org,2002:seq":
                raise error(f"unsupported YAML tag {node.tag}")
            self.open.add(id(node))
            items = [self.plain(item, (*path, i)) for i, item in enumerate(node.value)]
            self.open.discard(id(node))
            return items
        if not isinstance(node, yaml.MappingNode):  # pragma: no cover - yaml has 3 kinds
            raise error("unsupported YAML node")
        if node.tag != "tag:yaml.org,2002:map":
            raise error(f"unsupported YAML tag {node.tag}")
        self.open.add(id(node))
        result: dict[str, Any] = {}
        for key_node, value_node in node.value:
            key = self.plain(key_node, path, record=False)
            if not isinstance(key, str):
                raise error(f"keys must be text, got {_clip(key)}")
            if key in result:
                raise self.error_type(
                    "duplicate key",
                    file=file,
                    line=key_node.start_mark.line + 1,
                    key_path=format_key_path((*path, key)),
                )
            result[key] = self.plain(value_node, (*path, key))
        self.open.discard(id(node))
        return result


class Reader:
    """Typed reads from a :class:`YamlDocument`; every failure names file, line and key path."""

    def __init__(self, document: YamlDocument) -> None:
        self.document = document

    def error(self, path: KeyPath, message: str) -> QdsegaError:
        return self.document.error(path, message)

    def mapping(
        self,
        path: KeyPath,
        value: Any,
        *,
        required: Iterable[str] = (),
        optional: Iterable[str] = (),
    ) -> dict[str, Any]:
        """``value`` as a mapping with exactly the allowed keys."""
        if not isinstance(value, dict):
            raise self.error(path, f"expected a mapping, got {_kind(value)}")
        required, allowed = set(required), set(required) | set(optional)
        for key in value:
            if key not in allowed:
                raise self.error(
                    (*path, key), f"unknown key (allowed: {', '.join(sorted(allowed))})"
                )
        for key in sorted(required):
            if key not in value:
                raise self.error(path, f"missing required key '{key}'")
        return value

    def sequence(self, path: KeyPath, value: Any, *, min_length: int = 0) -> list[Any]:
        if not isinstance(value, list):
            raise self.error(path, f"expected a list, got {_kind(value)}")
        if len(value) < min_length:
            raise self.error(path, f"expected at least {min_length} item(s), got {len(value)}")
        return value

    def text(self, path: KeyPath, value: Any) -> str:
        if not isinstance(value, str) or not value.strip():
            raise self.error(path, f"expected non-empty text, got {_kind(value)}")
        return value

    def choice(self, path: KeyPath, value: Any, choices: Iterable[_Choice]) -> _Choice:
        options = list(choices)
        if value not in options:
            raise self.error(path, f"expected one of {', '.join(options)}, got {_clip(value)}")
        return value

    def number(self, path: KeyPath, value: Any, within: Interval) -> float:
        """``value`` as a number in ``within`` (never NaN or infinite)."""
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.error(path, f"expected a number, got {_kind(value)}")
        try:
            number = float(value)
        except OverflowError:  # an integer beyond the range of floats
            number = math.inf if value > 0 else -math.inf
        if math.isnan(number):
            raise self.error(path, "expected a number, got nan")
        if number not in within:
            raise self.error(path, f"must be in {within}, got {_clip(value)}")
        return number

    def integer(self, path: KeyPath, value: Any, within: Interval) -> int:
        """``value`` as an integer in ``within``."""
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(path, f"expected an integer, got {_kind(value)}")
        if value not in within:
            raise self.error(path, f"must be in {within}, got {_clip(value)}")
        return value

    def triple(self, path: KeyPath, value: Any, within: Interval) -> tuple[float, float, float]:
        """``value`` as 3 numbers (a position, a size, an axis), each in ``within``."""
        items = self.sequence(path, value)
        if len(items) != 3:
            raise self.error(path, f"expected 3 numbers, got {len(items)}")
        x, y, z = (self.number((*path, i), item, within) for i, item in enumerate(items))
        return (x, y, z)


def _kind(value: Any) -> str:
    if value is None:
        return "nothing"
    if isinstance(value, bool):
        return f"a boolean ({value})"
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, str):
        return f"text {_clip(value)}" if value.strip() else "empty text"
    return f"{type(value).__name__} {_clip(value)}"


def _clip(value: Any, width: int = 40) -> str:
    """``repr(value)``, cut to ``width`` characters: a message stays one short line."""
    text = repr(value)
    return text if len(text) <= width else text[: width - 3] + "..."
