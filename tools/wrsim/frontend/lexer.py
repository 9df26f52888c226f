"""VHDL-AMS lexer: source text -> tokens with file:line:col, plus the comments per line (the parser reads
`-- [unit]` annotations from them)."""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

from wrsim.errors import Loc, SourceError

__all__ = ["Token", "Lexed", "tokenize", "KEYWORDS"]

KEYWORDS = frozenset(
    """
abs access across after alias all and architecture array assert attribute begin block body break buffer
bus case component configuration constant disconnect downto else elsif end entity exit file for function
generate generic group guarded if impure in inertial inout is label library limit linkage literal loop map
mod nand nature new next noise nor not null of on open or others out package port postponed procedural
procedure process pure quantity range record reference register reject rem report return rol ror select
severity shared signal sla sll spectrum sra srl subnature subtype terminal then through to tolerance
transport type unaffected units until use variable wait when while with xnor xor
""".split()
)

_DELIMS = [
    "=>",
    "**",
    ":=",
    "/=",
    ">=",
    "<=",
    "<>",
    "==",
    "&",
    "'",
    "(",
    ")",
    "*",
    "+",
    ",",
    "-",
    ".",
    "/",
    ":",
    ";",
    "<",
    "=",
    ">",
    "|",
    "[",
    "]",
]

_NUMBER = re.compile(r"\d(_?\d)*(\.\d(_?\d)*)?([eE][+-]?\d(_?\d)*)?")
_BASED = re.compile(r"(\d+)#([0-9a-zA-Z_]*)#")
_MAX_DIGITS = 64  # digits of one literal: 64 binary digits is the widest integer VHDL has
_MAX_INTEGER = 2**63 - 1  # VHDL-2008 integers are at most 64-bit
_IDENT = re.compile(r"[A-Za-z](_?[A-Za-z0-9])*")
TIME_UNITS = frozenset({"fs", "ps", "ns", "us", "ms", "sec", "min", "hr"})  # the units of the predefined type time


@dataclass(frozen=True)
class Token:
    kind: str  # "id", "kw", "num", "str", "char", "op", "eof"
    text: str  # lower case for identifiers and keywords, raw otherwise
    loc: Loc
    raw: str = ""  # the spelling in the file (identifiers keep their case for messages)

    def is_(self, kind: str, text: str | None = None) -> bool:
        return self.kind == kind and (text is None or self.text == text)


@dataclass
class Lexed:
    tokens: list[Token]
    comments: dict[int, str]  # line -> text of the `--` comment on that line (without the dashes)
    lines: list[str]


def tokenize(text: str, path: str) -> Lexed:
    """Split `text` into tokens; raises SourceError at the first character that is not VHDL."""
    tokens: list[Token] = []
    comments: dict[int, str] = {}
    i, line, line_start, n = 0, 1, 0, len(text)

    def loc_at(pos: int) -> Loc:
        return Loc(path, line, pos - line_start + 1)

    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
            line_start = i
            continue
        if c in " \t\r\f\v":
            i += 1
            continue
        if text.startswith("--", i):
            end = text.find("\n", i)
            end = n if end < 0 else end
            comments[line] = text[i + 2 : end].strip()
            i = end
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            if end < 0:
                raise SourceError(loc_at(i), "unterminated /* comment")
            line += text.count("\n", i, end)
            if "\n" in text[i:end]:
                line_start = text.rfind("\n", i, end) + 1
            i = end + 2
            continue
        loc = loc_at(i)
        m = _IDENT.match(text, i)
        if m:
            word = m.group(0)
            low = word.lower()
            tokens.append(Token("kw" if low in KEYWORDS else "id", low, loc, word))
            i = m.end()
            continue
        if "0" <= c <= "9":
            mb = _BASED.match(text, i)
            if mb:
                tokens.append(Token("num", str(_based_value(mb.group(1), mb.group(2), loc)), loc, mb.group(0)))
                i = mb.end()
                continue
            m = _NUMBER.match(text, i)
            assert m is not None  # text[i] is a digit
            _check_decimal(m.group(0), loc)
            tokens.append(Token("num", m.group(0).replace("_", ""), loc, m.group(0)))
            i = m.end()
            if i < n and (text[i].isalpha() or text[i] == "_"):
                unit = _IDENT.match(text, i)
                if unit is None or unit.group(0).lower() not in TIME_UNITS:
                    raise SourceError(loc_at(i), f"malformed number {text[m.start() : i + 1]!r}")
                # `1ns`: the LRM asks for a space before the unit; the common simulators read it as `1 ns`
                tokens.append(Token("id", unit.group(0).lower(), loc_at(i), unit.group(0)))
                i = unit.end()
            continue
        if c == '"':
            j = i + 1
            buf = []
            while True:
                if j >= n or text[j] == "\n":
                    raise SourceError(loc, "unterminated string literal")
                if text[j] == '"':
                    if j + 1 < n and text[j + 1] == '"':
                        buf.append('"')
                        j += 2
                        continue
                    break
                buf.append(text[j])
                j += 1
            tokens.append(Token("str", "".join(buf), loc, text[i : j + 1]))
            i = j + 1
            continue
        if c == "'":
            # A tick after a name or ')' is an attribute; otherwise 'x' is a character literal.
            prev = tokens[-1] if tokens else None
            attribute = prev is not None and (
                prev.kind == "id"
                or prev.is_("op", ")")
                or prev.is_("op", "]")
                or (prev.kind == "kw" and prev.text in ("range", "all"))
            )
            if not attribute and i + 2 < n and text[i + 2] == "'":
                tokens.append(Token("char", text[i + 1], loc, text[i : i + 3]))
                i += 3
                continue
            tokens.append(Token("op", "'", loc, "'"))
            i += 1
            continue
        for d in _DELIMS:
            if text.startswith(d, i):
                tokens.append(Token("op", d, loc, d))
                i += len(d)
                break
        else:
            raise SourceError(loc, f"unexpected character {c!r}")
    tokens.append(Token("eof", "", Loc(path, line, i - line_start + 1), "end of file"))
    return Lexed(tokens, comments, text.splitlines())


def _based_value(base_text: str, digits: str, loc: Loc) -> int:
    """The value of the based literal `base#digits#` (IEEE 1076 15.5.3): base 2..16, digits below the base,
    underscores only between digits."""
    literal = f"{base_text}#{digits}#"
    base = int(base_text) if len(base_text) <= 3 else 0
    if not 2 <= base <= 16:
        raise SourceError(loc, f"based literal {literal[:40]!r}: the base must be 2 to 16")
    if not digits or digits.startswith("_") or digits.endswith("_") or "__" in digits:
        raise SourceError(loc, f"based literal {literal[:40]!r}: digits with single underscores between them expected")
    plain = digits.replace("_", "")
    if len(plain) > _MAX_DIGITS:
        raise SourceError(loc, f"based literal {literal[:40]!r}...: more than {_MAX_DIGITS} digits")
    bad = next((d for d in plain if int(d, 36) >= base), None)
    if bad is not None:
        raise SourceError(loc, f"based literal {literal[:40]!r}: digit '{bad}' is not a base-{base} digit")
    value = int(plain, base)
    if value > _MAX_INTEGER:
        raise SourceError(loc, f"based literal {literal[:40]!r}: {value} is out of the integer range")
    return value


def _check_decimal(literal: str, loc: Loc) -> None:
    """A decimal literal must denote a finite number (and an integer literal one in the integer range)."""
    plain = literal.replace("_", "")
    if len(plain) > 400 or not math.isfinite(float(plain)):
        raise SourceError(loc, f"number {literal[:40]!r}{'...' if len(literal) > 40 else ''} is out of range")
    if "." not in plain and "e" not in plain.lower() and int(plain) > _MAX_INTEGER:
        raise SourceError(loc, f"integer {literal[:40]!r} is out of the integer range")
