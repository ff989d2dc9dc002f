"""Safe YAML loading that remembers source lines, and typed reads with one-line errors.

Only plain YAML (mappings, sequences, scalars) is accepted: the document is composed into
nodes and converted by hand, so no Python object is ever constructed from a tag.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

from qdsega.errors import FormationError

KeyPath = tuple[str | int, ...]


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

    def line(self, path: KeyPath) -> int | None:
        """Line of ``path``, or of its nearest ancestor that has one."""
        for end in range(len(path), -1, -1):
            if path[:end] in self.lines:
                return self.lines[path[:end]]
        return None

    def error(self, path: KeyPath, message: str) -> FormationError:
        """A :class:`FormationError` located at ``path`` in this file."""
        return FormationError(
            message, file=self.file, line=self.line(path), key_path=format_key_path(path) or None
        )


def load_yaml(file: Path) -> YamlDocument:
    """Read ``file`` as plain YAML; raise :class:`FormationError` for anything else."""
    try:
        text = file.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FormationError("file not found", file=file) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise FormationError(f"cannot read file ({exc.__class__.__name__})", file=file) from None
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.MarkedYAMLError as exc:
        mark = exc.problem_mark or exc.context_mark
        line = None if mark is None else mark.line + 1
        problem = exc.problem or exc.context or "invalid YAML"
        raise FormationError(f"YAML syntax error: {problem}", file=file, line=line) from None
    except yaml.YAMLError as exc:
        raise FormationError(f"YAML error: {exc}", file=file) from None
    if root is None:
        raise FormationError("file is empty", file=file)
    lines: dict[KeyPath, int] = {}
    data = _to_plain(root, (), lines, file)
    return YamlDocument(file=file, data=data, lines=lines)


_SCALAR_CONSTRUCTOR = yaml.SafeLoader("")


def _to_plain(node: yaml.Node, path: KeyPath, lines: dict[KeyPath, int], file: Path) -> Any:
    lines[path] = node.start_mark.line + 1
    where = {"file": file, "line": node.start_mark.line + 1, "key_path": format_key_path(path)}
    if isinstance(node, yaml.ScalarNode):
        try:
            return _SCALAR_CONSTRUCTOR.construct_object(node)
        except yaml.constructor.ConstructorError:
            raise FormationError(f"unsupported YAML tag {node.tag}", **where) from None
    if isinstance(node, yaml.SequenceNode):
        if node.tag != "tag:yaml.org,2002:seq":
            raise FormationError(f"unsupported YAML tag {node.tag}", **where)
        return [_to_plain(item, (*path, i), lines, file) for i, item in enumerate(node.value)]
    if isinstance(node, yaml.MappingNode):
        if node.tag != "tag:yaml.org,2002:map":
            raise FormationError(f"unsupported YAML tag {node.tag}", **where)
        result: dict[str, Any] = {}
        for key_node, value_node in node.value:
            key = _to_plain(key_node, path, {}, file)
            if not isinstance(key, str):
                raise FormationError(f"keys must be text, got {key!r}", **where)
            if key in result:
                raise FormationError(
                    "duplicate key",
                    file=file,
                    line=key_node.start_mark.line + 1,
                    key_path=format_key_path((*path, key)),
                )
            result[key] = _to_plain(value_node, (*path, key), lines, file)
        return result
    raise FormationError("unsupported YAML node", **where)  # pragma: no cover - yaml has 3 kinds


class Reader:
    """Typed reads from a :class:`YamlDocument`; every failure names file, line and key path."""

    def __init__(self, document: YamlDocument) -> None:
        self.document = document

    def error(self, path: KeyPath, message: str) -> FormationError:
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

    def choice(self, path: KeyPath, value: Any, choices: Iterable[str]) -> str:
        options = list(choices)
        if value not in options:
            raise self.error(path, f"expected one of {', '.join(options)}, got {value!r}")
        return value

    def number(
        self, path: KeyPath, value: Any, *, positive: bool = False, nonnegative: bool = False
    ) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.error(path, f"expected a number, got {_kind(value)}")
        if not math.isfinite(value):
            raise self.error(path, f"expected a finite number, got {value}")
        if positive and value <= 0:
            raise self.error(path, f"must be positive, got {value}")
        if nonnegative and value < 0:
            raise self.error(path, f"must not be negative, got {value}")
        return float(value)

    def integer(self, path: KeyPath, value: Any) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(path, f"expected an integer, got {_kind(value)}")
        return value

    def vector(
        self, path: KeyPath, value: Any, length: int, *, positive: bool = False
    ) -> tuple[float, ...]:
        items = self.sequence(path, value)
        if len(items) != length:
            raise self.error(path, f"expected {length} numbers, got {len(items)}")
        return tuple(self.number((*path, i), x, positive=positive) for i, x in enumerate(items))


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
        return f"text {value!r}" if value.strip() else "empty text"
    return f"{type(value).__name__} {value!r}"
