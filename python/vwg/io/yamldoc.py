"""YAML files read with the line of every key, so errors can name the file, the line and the field."""

from __future__ import annotations

import copy
import math
import re
from pathlib import Path
from typing import Any, ClassVar

import yaml

from vwg.errors import WorldFileError
from vwg.io.files import read_text

__all__ = ["REQUIRED", "YamlDoc", "field_text"]

REQUIRED: Any = object()
MAX_NODES = 1_000_000  # values in a document, aliases expanded
MAX_DEPTH = 100        # lists and mappings inside each other (a world file needs fewer than 10)
MAX_INT_DIGITS = 100   # digits of an integer (a seed up to 2**64 - 1 has 20)
Path_ = tuple[Any, ...]
_INT_TAG = "tag:yaml.org,2002:int"
_SURROGATE = re.compile("[\ud800-\udfff]")


class _Refused(yaml.MarkedYAMLError):
    """What the loader refuses before building any value, at the place in the text."""

    def __init__(self, problem: str, mark: Any) -> None:
        super().__init__(problem=problem, problem_mark=mark)


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader with limits on what a small text expands to, checked while the tree is
    composed, before any value is built: PyYAML composes and builds recursively, so a deep nesting
    (``[[[...]]]``) or an alias inside the node it names (``a: &x [*x]``) would end in a
    RecursionError, and a 5,000-digit integer in Python's ValueError for long integers."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self._depth = 0
        self._open: list[str] = []  # anchors of the nodes being composed (PyYAML refuses a duplicate anchor)

    def compose_node(self, parent: Any, index: Any) -> Any:
        mark = self.peek_event().start_mark
        node = self._compose_node(parent, index)
        # PyYAML composes a mapping's key with index None. `? [a, b]` (or an alias of a list) as a key:
        # no field is named by one, and Python cannot make a dict key of a list.
        if isinstance(parent, yaml.MappingNode) and index is None and not isinstance(node, yaml.ScalarNode):
            kind = "a list" if isinstance(node, yaml.SequenceNode) else "a mapping"
            raise _Refused(f"a key must be text or a number, got {kind}", mark)
        return node

    def _compose_node(self, parent: Any, index: Any) -> Any:
        event = self.peek_event()
        if isinstance(event, yaml.AliasEvent):
            if event.anchor in self._open:
                raise _Refused(f"the alias *{event.anchor} is inside the value it names (&{event.anchor}): a value "
                               "cannot contain itself", event.start_mark)
            return super().compose_node(parent, index)
        if self._depth >= MAX_DEPTH:
            raise _Refused(f"nested more than {MAX_DEPTH} levels deep: vwg's YAML files hold at most {MAX_DEPTH} "
                           "levels of lists and mappings inside each other", event.start_mark)
        anchor = getattr(event, "anchor", None)
        self._depth += 1
        if anchor is not None:
            self._open.append(anchor)
        try:
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1
            if anchor is not None:
                self._open.pop()

    def compose_scalar_node(self, anchor: Any) -> Any:
        node = super().compose_scalar_node(anchor)
        if node.tag == _INT_TAG:
            digits = node.value.lstrip("+-").replace("_", "")
            if digits[:2].lower() in ("0x", "0o", "0b"):
                digits = digits[2:]
            if len(digits) > MAX_INT_DIGITS:
                raise _Refused(f"an integer of {len(digits)} digits: vwg's YAML files hold integers of at most "
                               f"{MAX_INT_DIGITS} digits", node.start_mark)
        if _SURROGATE.search(node.value):
            # PyYAML reads the escapes "\ud83d\ude00" as two halves: a pair is one character, a half alone none.
            try:
                node.value = node.value.encode("utf-16-le", "surrogatepass").decode("utf-16-le")
            except UnicodeDecodeError as e:
                half = node.value.encode("utf-16-le", "surrogatepass")[e.start:e.start + 2].decode(
                    "utf-16-le", "surrogatepass")
                raise _Refused(f"\\u{ord(half):04X} is half of a UTF-16 surrogate pair without its other half, "
                               "not a character", node.start_mark) from None
        return node

    def construct_object(self, node: Any, deep: bool = False) -> Any:
        try:
            return super().construct_object(node, deep)
        except yaml.YAMLError:
            raise
        except Exception as e:  # PyYAML's own constructors: int("abc") for `!!int abc`, a 13th month
            raise _Refused(f"cannot read this {node.tag.rpartition(':')[2] or 'value'}: {e}", node.start_mark) \
                from None


def field_text(path: Path_) -> str:
    """A key path as a field name: ``("robots", 0, "start")`` -> ``robots[0].start``."""
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


class YamlDoc:
    """A parsed YAML document and the line of each key path (``("alphabet", "events", 0)``)."""

    #: The last documents parsed, by path and text: loading a world reads its file more than once (its
    #: kind, then its content), and a world of a hundred robots took 0.1 s a parse.
    _parsed: ClassVar[dict[tuple[str, str], tuple[dict[Path_, int], yaml.Node | None, Any]]] = {}
    _KEEP = 4

    def __init__(self, path: str | Path, text: str | None = None) -> None:
        self.path = Path(path)
        if text is None:

            text = read_text(self.path)
        self.text = text
        key = (str(self.path), text)
        seen = YamlDoc._parsed.get(key)
        if seen is not None:  # the same text: its parse again, the values a copy of their own
            lines, self.node, data = seen
            self.lines, self.data = dict(lines), copy.deepcopy(data)
            return
        self._parse()
        YamlDoc._parsed[key] = (dict(self.lines), self.node, copy.deepcopy(self.data))  # kept as parsed
        while len(YamlDoc._parsed) > YamlDoc._KEEP:
            YamlDoc._parsed.pop(next(iter(YamlDoc._parsed)))

    def _parse(self) -> None:
        text = self.text
        try:
            loader = _Loader(text)  # PyYAML's reader refuses a control character here, before parsing
        except yaml.reader.ReaderError as e:
            raise self._bad_character(e) from None
        try:
            node = loader.get_single_node()
            self.lines: dict[Path_, int] = {}
            self._budget = MAX_NODES
            self._mappings: dict[int, tuple[yaml.MappingNode, list[Any]]] = {}
            if node is not None:
                self._walk(node, ())  # counted before the values are built: a billion laughs stays text
            self.data = loader.construct_document(node) if node is not None else None
            # Building a mapping with a merge key (<<: *a) puts the merged keys into its node; the
            # tree is given back as the text has it, so a key overriding a merged one is no duplicate.
            for mapping, pairs in self._mappings.values():
                mapping.value = pairs
        except yaml.YAMLError as e:
            mark = getattr(e, "problem_mark", None)
            problem = getattr(e, "problem", None) or str(e)
            prefix = "" if isinstance(e, _Refused) else "not valid YAML: "
            raise WorldFileError(str(self.path), "", f"{prefix}{problem}", line=mark.line + 1 if mark else 0,
                                 column=mark.column + 1 if mark else 0) from None
        finally:
            loader.dispose()
        #: The composed tree (the line of every node), for checks of the text itself (duplicate keys).
        self.node: yaml.Node | None = node

    def _bad_character(self, e: yaml.reader.ReaderError) -> WorldFileError:
        """A character YAML does not allow (a NUL byte, ESC, U+FFFE) at its line and column."""
        before = self.text[:e.position]
        line = before.count("\n") + 1
        column = e.position - (before.rfind("\n") + 1) + 1
        # UTF-16 text read as UTF-8 has a NUL byte in every ASCII character, the first within two.
        hint = " (is the file UTF-16? vwg reads UTF-8)" if "\0" in self.text[:2] else ""
        return WorldFileError(str(self.path), "", f"not valid YAML: unacceptable character #x{e.character:04x}: "
                                                  f"{e.reason}{hint}", line=line, column=column)

    def _walk(self, node: yaml.Node, path: Path_) -> None:
        # Aliases make a document's tree exponentially bigger than its text ("billion laughs"): a
        # world file has a few thousand nodes at most.
        self._budget -= 1
        if self._budget < 0:
            raise WorldFileError(str(self.path), "", f"more than {MAX_NODES} values once its aliases (*name) are "
                                                     "expanded", line=node.start_mark.line + 1)
        self.lines.setdefault(path, node.start_mark.line + 1)
        if isinstance(node, yaml.MappingNode):
            self._mappings[id(node)] = (node, list(node.value))
            for key, value in node.value:
                k = key.value  # text: the loader refuses a list or a mapping as a key
                digits = k.lstrip("-") if isinstance(k, str) else ""
                # "12": 1 is found as 12 too; only ASCII digits ("²" is a digit to isdigit, not to int)
                if digits.isascii() and digits.isdigit() and len(digits) <= MAX_INT_DIGITS:
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


KIND_NAMES = {dict: "a mapping", list: "a list", str: "text", int: "an integer", float: "a number",
               bool: "true or false"}


def check_kind(doc: YamlDoc, path: Path_, value: Any, kind: type | tuple[type, ...]) -> None:
    kinds = kind if isinstance(kind, tuple) else (kind,)
    ok = any(isinstance(value, k) for k in kinds)
    if ok and isinstance(value, bool) and bool not in kinds:
        ok = False  # YAML true/false is not a number here
    if not ok:
        expected = " or ".join(KIND_NAMES.get(k, k.__name__) for k in kinds)
        raise doc.error(path, f"expected {expected}, got {type(value).__name__} {value!r}")
