"""YAML files read with the line of every key, so errors can name the file, the line and the field."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import yaml

from .errors import WorldFileError

__all__ = ["REQUIRED", "YamlDoc", "field_text"]

REQUIRED: Any = object()
MAX_NODES = 1_000_000  # values in a document, aliases expanded
Path_ = tuple[Any, ...]


def field_text(path: Path_) -> str:
    """A key path as a field name: ``("robots", 0, "start")`` -> ``robots[0].start``."""
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


class YamlDoc:
    """A parsed YAML document and the line of each key path (``("alphabet", "events", 0)``)."""

    def __init__(self, path: str | Path, text: str | None = None) -> None:
        self.path = Path(path)
        if text is None:
            from .files import read_text

            text = read_text(self.path)
        self.text = text
        try:
            self.data = yaml.safe_load(text)
            node = yaml.compose(text, Loader=yaml.SafeLoader)
        except yaml.YAMLError as e:
            mark = getattr(e, "problem_mark", None)
            problem = getattr(e, "problem", None) or str(e)
            raise WorldFileError(str(self.path), "", f"not valid YAML: {problem}",
                                 line=mark.line + 1 if mark else 0) from None
        self.lines: dict[Path_, int] = {}
        self._budget = MAX_NODES
        if node is not None:
            self._walk(node, ())

    def _walk(self, node: yaml.Node, path: Path_) -> None:
        # Aliases make a document's tree exponentially bigger than its text ("billion laughs"): a
        # world file has a few thousand nodes at most.
        self._budget -= 1
        if self._budget < 0:
            raise WorldFileError(str(self.path), "", f"more than {MAX_NODES} values once its aliases (*name) are "
                                                     "expanded", line=node.start_mark.line + 1)
        self.lines.setdefault(path, node.start_mark.line + 1)
        if isinstance(node, yaml.MappingNode):
            for key, value in node.value:
                k = yaml.safe_load(yaml.serialize(key)) if not isinstance(key, yaml.ScalarNode) else key.value
                if isinstance(k, str) and k.lstrip("-").isdigit():
                    k = int(k)
                self.lines[(*path, k)] = key.start_mark.line + 1
                self._walk(value, (*path, k))
        elif isinstance(node, yaml.SequenceNode):
            for i, item in enumerate(node.value):
                self._walk(item, (*path, i))

    def line_of(self, path: Path_) -> int:
        while path and path not in self.lines:
            path = path[:-1]
        return self.lines.get(path, 0)

    def error(self, path: Path_, message: str) -> WorldFileError:
        return WorldFileError(str(self.path), field_text(path), message, line=self.line_of(path))

    def get(self, path: Path_, kind: type | tuple[type, ...] | None = None, default: Any = REQUIRED) -> Any:
        """The value at `path`, checked to be of `kind`; `default` when absent (else an error)."""
        value: Any = self.data
        for i, p in enumerate(path):
            in_dict = isinstance(value, dict) and p in value
            in_list = isinstance(value, list) and isinstance(p, int) and 0 <= p < len(value)
            if in_dict or in_list:
                value = value[p]
            else:
                if default is not REQUIRED:
                    return default
                if i < len(path) - 1 or not isinstance(value, dict):
                    raise self.error(path[:i], f"expected a mapping with key '{p}'")
                raise self.error(path, "missing")
        if value is None and default is not REQUIRED:
            return default
        if kind is not None:
            check_kind(self, path, value, kind)
        return value

    def number(self, path: Path_, default: Any = REQUIRED, *, minimum: float | None = None,
               maximum: float | None = None, exclusive_minimum: bool = False, integer: bool = False) -> Any:
        """A finite number at `path`, optionally within bounds."""
        value = self.get(path, int if integer else (int, float), default)
        if value is default and default is not REQUIRED:
            return value
        if not math.isfinite(value):
            raise self.error(path, f"expected a finite number, got {value!r}")
        if minimum is not None and (value < minimum or (exclusive_minimum and value == minimum)):
            relation = ">" if exclusive_minimum else ">="
            raise self.error(path, f"expected a number {relation} {minimum}, got {value!r}")
        if maximum is not None and value > maximum:
            raise self.error(path, f"expected a number <= {maximum}, got {value!r}")
        return value


_KIND_NAMES = {dict: "a mapping", list: "a list", str: "text", int: "an integer", float: "a number",
               bool: "true or false"}


def check_kind(doc: YamlDoc, path: Path_, value: Any, kind: type | tuple[type, ...]) -> None:
    kinds = kind if isinstance(kind, tuple) else (kind,)
    ok = any(isinstance(value, k) for k in kinds)
    if ok and isinstance(value, bool) and bool not in kinds:
        ok = False  # YAML true/false is not a number here
    if not ok:
        expected = " or ".join(_KIND_NAMES.get(k, k.__name__) for k in kinds)
        raise doc.error(path, f"expected {expected}, got {type(value).__name__} {value!r}")
