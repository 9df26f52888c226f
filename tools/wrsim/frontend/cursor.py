"""The token cursor every parser stage shares: look-ahead, acceptance and expectation of tokens, identifiers, the
`[unit]` annotations of comments, and messages located at file:line:col."""

from __future__ import annotations

import re

from wrsim.errors import SourceError
from wrsim.frontend.lexer import Lexed, Token

__all__ = ["TokenCursor"]

_UNIT = re.compile(r"^\[([^\]]*)\]\s*(.*)$")


class TokenCursor:
    """Tokens of one file and a cursor over them."""

    def __init__(self, lexed: Lexed, path: str, library: str):
        self.toks = lexed.tokens
        self.comments = lexed.comments
        self.lines = lexed.lines
        self.path = path
        self.library = library
        self.i = 0
        self.nesting = 0  # expressions being parsed, one inside the other
        self.blocks = 0  # statement lists being parsed, one inside the other
        self.is_digital_file = False  # plain VHDL for GHDL (set by the design file's parse): bodies are skipped

    # ------------------------------------------------------------------ token helpers
    @property
    def tok(self) -> Token:
        return self.toks[self.i]

    def peek(self, k: int = 1) -> Token:
        return self.toks[min(self.i + k, len(self.toks) - 1)]

    def advance(self) -> Token:
        """The current token; the cursor moves on, but never past the end of the file."""
        t = self.toks[self.i]
        self.i = min(self.i + 1, len(self.toks) - 1)
        return t

    def at(self, kind: str, text: str | None = None) -> bool:
        return self.tok.is_(kind, text)

    def at_kw(self, *words: str) -> bool:
        return self.tok.kind == "kw" and self.tok.text in words

    def at_op(self, *ops: str) -> bool:
        return self.tok.kind == "op" and self.tok.text in ops

    def accept_kw(self, word: str) -> bool:
        if self.at("kw", word):
            self.i += 1
            return True
        return False

    def accept_op(self, op: str) -> bool:
        if self.at("op", op):
            self.i += 1
            return True
        return False

    def error(self, message: str, tok: Token | None = None) -> SourceError:
        return SourceError((tok or self.tok).loc, message)

    def describe(self, t: Token) -> str:
        return "end of file" if t.kind == "eof" else repr(t.raw or t.text)

    def expect_kw(self, word: str) -> Token:
        if not self.at("kw", word):
            raise self.error(f"expected '{word}', found {self.describe(self.tok)}")
        return self.advance()

    def expect_op(self, op: str) -> Token:
        if not self.at("op", op):
            raise self.error(f"expected '{op}', found {self.describe(self.tok)}")
        return self.advance()

    def ident(self, what: str = "identifier") -> str:
        if self.tok.kind != "id":
            if self.tok.kind == "kw":
                raise self.error(f"expected {what}, found reserved word '{self.tok.text}'")
            raise self.error(f"expected {what}, found {self.describe(self.tok)}")
        return self.advance().text

    def ident_list(self) -> list[str]:
        names = [self.ident()]
        while self.accept_op(","):
            names.append(self.ident())
        return names

    def unsupported(self, what: str, tok: Token | None = None) -> SourceError:
        return self.error(f"unsupported construct: {what}", tok)

    def unit_comment(self, *lines: int) -> tuple[str | None, str]:
        """The `[unit] text` annotation in the `--` comment on the first of `lines` that has one."""
        for line in lines:
            c = self.comments.get(line)
            if c is None:
                continue
            m = _UNIT.match(c)
            if m:
                return m.group(1).strip() or None, m.group(2).strip()
            return None, c
        return None, ""

    def end_of(self, *words: str, name: str | None = None) -> None:
        """`end [word...] [name] ;` — a repeated name must be the unit's (or label's) name."""
        self.expect_kw("end")
        for w in words:
            self.accept_kw(w)
        if self.tok.kind == "id":
            t = self.advance()
            if name is not None and t.text != name:
                raise self.error(f"end name '{t.raw}' does not match the name '{name}'", t)
        self.expect_op(";")

    def header_before(self, line: int) -> str:
        """The text of the comment lines right above `line` (a unit's header), top first."""
        out = []
        k = line - 1
        while k >= 1 and self.lines[k - 1].lstrip().startswith("--"):
            out.append(self.comments.get(k, ""))
            k -= 1
        return "\n".join(reversed(out))
