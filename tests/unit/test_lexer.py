"""VHDL-AMS lexer: tokens carry file:line:col, comments are kept per line, and every character that is not
VHDL is one SourceError at its exact line and column."""

from __future__ import annotations

import pytest

from wrsim.errors import Loc, SourceError
from wrsim.frontend.lexer import tokenize


def kinds(text: str) -> list[tuple[str, str, str]]:
    """(file:line:col, kind, text) of every token but the end of file."""
    return [(str(t.loc), t.kind, t.text) for t in tokenize(text, "f.vhd").tokens[:-1]]


def test_tokens_carry_line_and_column():
    # a tab is one column; a block comment over two lines moves the line count on
    text = "Entity E is\n\tq == 2.5E-3 * X'dot; /* two\nlines */ r := 16#FF#;"
    assert kinds(text) == [
        ("f.vhd:1:1", "kw", "entity"),
        ("f.vhd:1:8", "id", "e"),
        ("f.vhd:1:10", "kw", "is"),
        ("f.vhd:2:2", "id", "q"),
        ("f.vhd:2:4", "op", "=="),
        ("f.vhd:2:7", "num", "2.5E-3"),
        ("f.vhd:2:14", "op", "*"),
        ("f.vhd:2:16", "id", "x"),
        ("f.vhd:2:17", "op", "'"),
        ("f.vhd:2:18", "id", "dot"),
        ("f.vhd:2:21", "op", ";"),
        ("f.vhd:3:10", "id", "r"),
        ("f.vhd:3:12", "op", ":="),
        ("f.vhd:3:15", "num", "255"),
        ("f.vhd:3:21", "op", ";"),
    ]
    lexed = tokenize(text, "f.vhd")
    assert lexed.tokens[1].raw == "E"  # identifiers keep their spelling for messages
    assert lexed.tokens[-1].kind == "eof" and str(lexed.tokens[-1].loc) == "f.vhd:3:22"


def test_tick_is_an_attribute_after_a_name_and_a_character_literal_otherwise():
    assert kinds("x'dot c := 'a';") == [
        ("f.vhd:1:1", "id", "x"),
        ("f.vhd:1:2", "op", "'"),
        ("f.vhd:1:3", "id", "dot"),
        ("f.vhd:1:7", "id", "c"),
        ("f.vhd:1:9", "op", ":="),
        ("f.vhd:1:12", "char", "a"),
        ("f.vhd:1:15", "op", ";"),
    ]


def test_strings_and_comments():
    lexed = tokenize('r "say ""hi""" -- [N*m/A] torque constant\n-- second\n', "f.vhd")
    assert [(t.kind, t.text) for t in lexed.tokens[:-1]] == [("id", "r"), ("str", 'say "hi"')]
    assert lexed.comments == {1: "[N*m/A] torque constant", 2: "second"}


@pytest.mark.parametrize(
    "text, line, col, message",
    [
        ("a := b $ c;", 1, 8, "unexpected character '$'"),
        ("\tq == \u00b5;", 1, 7, "unexpected character '\u00b5'"),
        ("x\n/* one\n two */ @", 3, 9, "unexpected character '@'"),
        ('assert x report "abc\n;', 1, 17, "unterminated string literal"),
        ('report "abc', 1, 8, "unterminated string literal"),
        ("x;\n  /* never closed\n\n", 2, 3, "unterminated /* comment"),
        ("c := 1.0x;", 1, 9, "malformed number '1.0x'"),
        ("c := 1.0e;", 1, 9, "malformed number '1.0e'"),
        ("c :=\n   12abc;", 2, 6, "malformed number '12a'"),
        ("c := 1_;", 1, 7, "malformed number '1_'"),
    ],
)
def test_lexical_errors_are_one_message_at_the_exact_position(text, line, col, message):
    with pytest.raises(SourceError) as err:
        tokenize(text, "dir/f.vhd")
    assert err.value.loc == Loc("dir/f.vhd", line, col)
    assert str(err.value) == f"dir/f.vhd:{line}:{col}: {message}"


def test_a_time_unit_right_after_a_number_is_read_as_the_unit():
    """`1ns`, `2ms`: the LRM asks for a space before the unit; the common simulators (and wrsim) read `1 ns`. Only the
    units of type time are split off: `12abc` stays a malformed number (above)."""
    toks = tokenize("wait for 1ns; x := 2.5ms + 3 sec;", "t.vhd").tokens
    assert [(t.kind, t.text) for t in toks[2:4]] == [("num", "1"), ("id", "ns")]
    assert [(t.kind, t.text) for t in toks[7:9]] == [("num", "2.5"), ("id", "ms")]
    assert toks[3].loc.col == 11
