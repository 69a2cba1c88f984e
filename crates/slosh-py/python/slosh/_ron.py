"""A reader of the RON text slosh writes (``summary.ron``, ``slosh theory --ron``).

RON values become Python values: structs ``(a: 1, b: 2)`` and ``Name(a: 1)`` become dicts,
lists ``[...]`` and tuples ``(x, y)`` lists, ``Some(x)`` and newtype variants such as
``Float(1.0)`` their inner value, ``None`` None, ``true``/``false`` bools, other bare names
(enum variants such as ``NotEvaluated``, raw ones such as ``r#None`` too) strings, ``inf``/``NaN`` floats.
"""

from __future__ import annotations

import math
import re
from typing import Any

_TOKEN = re.compile(
    r"""
    (?P<ws>\s+|//[^\n]*|/\*.*?\*/)
  | (?P<string>"(?:[^"\\]|\\.)*")
  | (?P<char>'(?:[^'\\]|\\.)')
  | (?P<number>[+-]?(?:\d[\d_]*\.?[\d_]*(?:[eE][+-]?\d+)?|\.\d+(?:[eE][+-]?\d+)?)(?![A-Za-z_]))
  | (?P<raw>r\#[A-Za-z_][A-Za-z0-9_]*)
  | (?P<ident>[+-]?[A-Za-z_][A-Za-z0-9_]*)
  | (?P<punct>[()\[\]{},:])
    """,
    re.VERBOSE | re.DOTALL,
)

_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", "0": "\0", "\\": "\\", '"': '"', "'": "'"}


def _unescape(body: str) -> str:
    out = []
    i = 0
    while i < len(body):
        c = body[i]
        if c != "\\":
            out.append(c)
            i += 1
            continue
        nxt = body[i + 1]
        if nxt == "u" and body[i + 2] == "{":
            end = body.index("}", i)
            out.append(chr(int(body[i + 3 : end], 16)))
            i = end + 1
        elif nxt == "x":
            out.append(chr(int(body[i + 2 : i + 4], 16)))
            i += 4
        else:
            out.append(_ESCAPES.get(nxt, nxt))
            i += 2
    return "".join(out)


def _tokens(text: str) -> list[tuple[str, str]]:
    tokens = []
    pos = 0
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None:
            raise ValueError(f"RON: unexpected text at offset {pos}: {text[pos:pos + 20]!r}")
        pos = m.end()
        kind = m.lastgroup
        if kind != "ws":
            tokens.append((kind, m.group()))
    return tokens


class _Parser:
    def __init__(self, text: str) -> None:
        self.tokens = _tokens(text)
        self.pos = 0

    def peek(self) -> tuple[str, str] | None:
        return self.tokens[self.pos] if self.pos < len(self.tokens) else None

    def take(self) -> tuple[str, str]:
        tok = self.peek()
        if tok is None:
            raise ValueError("RON: unexpected end of text")
        self.pos += 1
        return tok

    def expect(self, punct: str) -> None:
        kind, value = self.take()
        if (kind, value) != ("punct", punct):
            raise ValueError(f"RON: expected {punct!r}, found {value!r}")

    def at(self, punct: str) -> bool:
        return self.peek() == ("punct", punct)

    def value(self) -> Any:
        kind, tok = self.take()
        if kind == "string":
            return _unescape(tok[1:-1])
        if kind == "char":
            return _unescape(tok[1:-1])
        if kind == "number":
            t = tok.replace("_", "")
            if re.fullmatch(r"[+-]?\d+", t):
                return int(t)
            return float(t)
        if kind == "raw":
            # A raw identifier (`r#None`): an enum variant named like a keyword.
            name = tok[2:]
            if self.at("("):
                inner = self.group()
                return inner[0] if isinstance(inner, list) and len(inner) == 1 else inner
            return name
        if kind == "ident":
            sign = -1.0 if tok.startswith("-") else 1.0
            name = tok.lstrip("+-")
            if name == "inf":
                return sign * math.inf
            if name == "NaN":
                return math.nan
            if name in ("true", "false") and not self.at("("):
                return name == "true"
            if name == "None" and not self.at("("):
                return None
            if self.at("("):
                inner = self.group()
                if isinstance(inner, list) and len(inner) == 1:
                    return inner[0]
                return inner
            return name
        if tok == "(":
            self.pos -= 1
            return self.group()
        if tok == "[":
            items = []
            while not self.at("]"):
                items.append(self.value())
                if not self.at("]"):
                    self.expect(",")
            self.expect("]")
            return items
        if tok == "{":
            d = {}
            while not self.at("}"):
                key = self.value()
                self.expect(":")
                d[key] = self.value()
                if not self.at("}"):
                    self.expect(",")
            self.expect("}")
            return d
        raise ValueError(f"RON: unexpected {tok!r}")

    def group(self) -> Any:
        """``(a: 1, ...)`` as a dict, ``(x, ...)`` as a list, ``()`` as an empty list."""
        self.expect("(")
        nxt = self.tokens[self.pos + 1] if self.pos + 1 < len(self.tokens) else None
        is_struct = self.peek() is not None and self.peek()[0] in ("ident", "raw") and nxt == (
            "punct",
            ":",
        )
        if is_struct:
            d = {}
            while not self.at(")"):
                _, key = self.take()
                key = key[2:] if key.startswith("r#") else key
                self.expect(":")
                d[key] = self.value()
                if not self.at(")"):
                    self.expect(",")
            self.expect(")")
            return d
        items = []
        while not self.at(")"):
            items.append(self.value())
            if not self.at(")"):
                self.expect(",")
        self.expect(")")
        return items


def loads(text: str) -> Any:
    """Parses RON text into Python values (see the module's docstring)."""
    parser = _Parser(text)
    value = parser.value()
    if parser.peek() is not None:
        raise ValueError(f"RON: unexpected {parser.peek()[1]!r} after the value")
    return value
