"""Front-end: VHDL-AMS source -> tokens (`lexer`) -> design units (`parser`, the dataclasses of `ast`), every
node located by file:line:col. The subset it reads is docs/vhdl-ams-subset.md."""

from __future__ import annotations

from wrsim.frontend import ast
from wrsim.frontend.lexer import Lexed, Token, tokenize
from wrsim.frontend.parser import parse_file, parse_text, read_source

__all__ = ["ast", "Lexed", "Token", "tokenize", "parse_file", "parse_text", "read_source"]
