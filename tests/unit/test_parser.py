"""Parser: malformed VHDL-AMS is one SourceError at the offending token; every construct outside the subset
(docs/vhdl-ams-subset.md) is named as `unsupported construct: <what>`; `-- [unit]` comments become units."""

from __future__ import annotations

import re

import pytest

from wrsim import paths
from wrsim.errors import Loc, SourceError, WrsimError
from wrsim.frontend import ast
from wrsim.frontend.parser import parse_file, parse_text

ROOT = paths.ROOT


def arch(decls: str = "", stmts: str = "") -> str:
    """An AMS architecture (the quantity makes the file AMS; files without AMS are GHDL's)."""
    return f"architecture a of e is\n  quantity ams_q : real;\n  {decls}\nbegin\n  {stmts}\nend architecture a;\n"


def position(text: str, marker: str) -> tuple[int, int]:
    """1-based (line, column) of the first occurrence of `marker` in `text`."""
    k = text.index(marker)
    return text.count("\n", 0, k) + 1, k - (text.rfind("\n", 0, k) + 1) + 1


def parse_error(text: str) -> SourceError:
    with pytest.raises(SourceError) as err:
        parse_text(text, "m.vhd")
    return err.value


SYNTAX = [
    (
        "missing semicolon",
        "entity e is\n  port (terminal p : electrical)\nend entity e;\n",
        "end entity",
        "expected ';', found 'end'",
    ),
    ("missing end", "entity e is\n  port (terminal p : electrical);\n", None, "expected 'end', found end of file"),
    (
        "'=' for '=='",
        arch("quantity x : real;", "x = 1.0;"),
        "= 1.0",
        "expected '==' in simultaneous statement, found '='",
    ),
    (
        "sign inside an expression",
        arch("quantity x : real;", "x == 2.0 * -x;"),
        "-x",
        "a sign inside an expression must be parenthesized, e.g. a * (-b)",
    ),
    (
        "sign after **",
        arch("quantity x : real;", "x == 2.0 ** -1;"),
        "-1",
        "a sign inside an expression must be parenthesized, e.g. a * (-b)",
    ),
    (
        "mixed logical operators",
        arch("quantity x : real;", "if a and b or c use x == 1.0; end use;"),
        "or",
        "mixing logical operators needs parentheses",
    ),
    (
        "instance without label",
        arch("", "entity work.r port map (p => t);"),
        "entity work",
        "an instance needs a label",
    ),
]


@pytest.mark.parametrize("what, text, marker, message", SYNTAX, ids=[s[0] for s in SYNTAX])
def test_syntax_errors_point_at_the_offending_token(what, text, marker, message):
    err = parse_error(text)
    line, col = position(text, marker) if marker else (text.count("\n") + 1, 1)
    assert str(err) == f"m.vhd:{line}:{col}: {message}"


def test_end_name_must_repeat_the_unit_name():
    text = "entity motor is\nend entity moter;\n"
    err = parse_error(text)
    assert err.loc == Loc("m.vhd", *position(text, "moter"))
    assert "'moter'" in err.message and "'motor'" in err.message


UNSUPPORTED = [
    ("signal type", arch("signal s : bit_vector(3 downto 0);"), "(3", "constrained subtype indication"),
    (
        "signal port mode",
        "entity e is\n  port (signal clk : inout std_logic; terminal t : electrical);\nend entity e;\n",
        "inout",
        "signal port mode 'inout'",
    ),
    ("record nature", arch("nature r is record a : electrical; end record;"), "record", "record nature"),
    ("range constraint", arch("constant c : real range 0.0 to 1.0 := 0.5;"), "range 0", "range constraint"),
    (
        "aggregate with others",
        arch("constant c : real_vector := (others => 1.0);"),
        "others => 1.0",
        "aggregate choice 'others'",
    ),
    (
        "break for",
        arch("quantity x : real;", "break for x use x => 0.0;"),
        "for x",
        "break for ... use (a break list with a selector quantity)",
    ),
    (
        "impure function",
        "package p is\n  impure function f return real;\nend package p;\n",
        "impure",
        "impure function",
    ),
    (
        "configuration",
        "configuration c of e is\n  for a\n  end for;\nend configuration c;\n",
        "configuration",
        "configuration declaration",
    ),
    ("type declaration", arch("type t is range 0 to 3;"), "type", "type declaration"),
    ("report expression", arch("", 'assert true report "a" & "b";'), '"a"', "report expression"),
    (
        "exit with a loop label",
        arch(
            "function f(x : real) return real is\n  begin\n    while x > 0.0 loop\n      exit outer;\n"
            "    end loop;\n    return x;\n  end function f;"
        ),
        "outer",
        "'exit' with a loop label",
    ),
]


@pytest.mark.parametrize("what, text, marker, named", UNSUPPORTED, ids=[u[0] for u in UNSUPPORTED])
def test_each_unsupported_construct_is_named_at_its_position(what, text, marker, named):
    err = parse_error(text)
    assert err.loc == Loc("m.vhd", *position(text, marker)), str(err)
    assert err.message.startswith("unsupported construct: "), str(err)
    assert named in err.message


def test_a_case_generate_keeps_its_alternatives():
    """VHDL-2008: `when [label:] choices =>`, a body with or without declarations and an inner `end [label];`."""
    text = arch(
        "",
        "g: case n generate\n    when a1: 1 | 2 =>\n      quantity y : real;\n    begin\n      y == 1.0;\n"
        "    end a1;\n    when others =>\n      ams_q == 0.0;\n  end generate g;",
    )
    (st,) = parse_text(text, "m.vhd").units[0].stmts
    assert isinstance(st, ast.CaseGenerate) and st.label == "g" and st.selector == ast.Name("n", st.selector.loc)
    (first, one), (others, two) = st.alternatives
    assert [c.value for c in first] == [1, 2] and others is None
    assert [d.name for d in one.decls] == ["y"] and len(one.stmts) == 1 and one.label == "g"
    assert two.decls == [] and isinstance(two.stmts[0], ast.SimpleSimultaneous)
    assert one.cond is None and one.var is None  # elaborated once when chosen


def test_process_all_is_sensitive_to_what_it_reads():
    """`process (all)`: the names its statements read (signals among them at elaboration), the 'above it reads,
    the prefixes of 'event and 'stable; not its variables nor loop variables."""
    body = (
        "p: process (all)\n    variable v : real := 0.0;\n  begin\n    v := a + b;\n"
        "    if c'event and not d'stable and x'above(v) then\n      for k in 1 to 2 loop\n"
        "        v := v + real(k) * e;\n      end loop;\n    end if;\n    s <= v after t;\n  end process p;"
    )
    (st,) = parse_text(arch("", body), "m.vhd").units[0].stmts
    assert isinstance(st, ast.Process) and st.implied
    named = [x.ident if isinstance(x, ast.Name) else f"{x.prefix}'{x.attr}" for x in st.sensitivity]
    assert named == ["a", "b", "c", "d", "x'above", "e", "t"]


def test_trailing_unit_comments_become_units(tmp_path):
    text = (
        "entity e is\n"
        "  generic (\n"
        "    kt  : real       := 15.0e-3;  -- [N*m/A] torque constant k_t\n"
        "    ra  : resistance := 0.57;     -- armature resistance (unit from the subtype)\n"
        "    n   : integer    := 2;        -- [] count without unit\n"
        "    w0  : real       := 0.0);     -- [rad/s] initial speed\n"
        "  port (quantity q : out real;    -- [N] force\n"
        "        terminal p : electrical);\n"
        "end entity e;\n"
        "architecture a of e is\n"
        "  quantity omega : real;  -- [rad/s] speed\n"
        "begin\n"
        "end architecture a;\n"
    )
    path = tmp_path / "e.vhd"
    path.write_text(text, encoding="utf-8")
    ent, body = parse_file(path).units
    assert [(g.name, g.unit, g.comment) for g in ent.generics] == [
        ("kt", "N*m/A", "torque constant k_t"),
        ("ra", None, "armature resistance (unit from the subtype)"),
        ("n", None, "count without unit"),
        ("w0", "rad/s", "initial speed"),
    ]
    assert ent.ports[0] == ast.QuantityPort("q", "out", "real", "N", Loc(str(path), 7, 9))
    assert body.decls[0].unit == "rad/s"


def test_units_of_a_library_model():
    ent = next(u for u in parse_file(ROOT / "vhdl" / "drive" / "dcpm_motor.vhd").units if isinstance(u, ast.Entity))
    units = {g.name: g.unit for g in ent.generics}
    assert units["ke"] == "V*s/rad" and units["kt"] == "N*m/A" and units["omega0"] is None  # angular_velocity
    assert units["ra"] is None  # resistance: units from the IEEE subtypes


def test_unreadable_file_is_a_user_error(tmp_path):
    bad = tmp_path / "latin1.vhd"
    bad.write_bytes(b"-- caf\xe9\n")
    with pytest.raises(WrsimError, match=rf"^{re.escape(str(bad))}: cannot read VHDL-AMS source: .*utf-8"):
        parse_file(bad)


@pytest.mark.parametrize("word", ["limit", "reference", "across", "break"])
def test_a_digital_unit_may_not_name_things_with_ams_reserved_words(word):
    text = (
        f"entity d is\n  port (clk : in std_logic);\nend entity d;\narchitecture a of d is\nbegin\n"
        f"  p: process (clk)\n    variable {word} : integer := 0;\n  begin\n    {word} := 1;\n  end process;\n"
        f"end architecture a;\n"
    )
    err = parse_error(text)
    assert err.loc == Loc("m.vhd", *position(text, word))
    assert err.message == (
        f"'{word}' is a reserved word of VHDL-AMS (IEEE 1076.1): a digital unit analysed next to "
        f"the AMS models cannot use it as a name"
    )


def test_a_case_statement_and_the_2008_assignments_are_their_if_statements():
    """In a process: `case`, and VHDL-2008's conditional and selected signal and variable assignments, read as the
    if statements they are equivalent to (corpus/sequential_case_tb simulates them)."""
    body = (
        "p: process (n) variable v : real; begin\n"
        "  case n is when 0 => v := 1.0; when 1 | 2 => v := 2.0; when others => null; end case;\n"
        "  v := 1.0 when n > 1 else 2.0;\n"
        "  with n select s <= 1.0 when 0, 2.0 when others;\n"
        "  s <= unaffected;\n"
        "end process p;"
    )
    (unit,) = parse_text(arch("signal s : real; signal n : integer;", body), "m.vhd").units
    (process,) = [st for st in unit.stmts if isinstance(st, ast.Process)]
    case, conditional, selected, unaffected = process.body
    assert [type(st) for st in process.body] == [ast.IfStmt, ast.IfStmt, ast.IfStmt, ast.NullStmt]
    conditions = [c for c, _ in case.branches]
    assert conditions[2] is None and isinstance(conditions[1], ast.Binary) and conditions[1].op == "or"
    assert [type(st) for _, stmts in conditional.branches for st in stmts] == [ast.VarAssign, ast.VarAssign]
    assert [type(st) for _, stmts in selected.branches for st in stmts] == [ast.SeqSignalAssign] * 2


@pytest.mark.parametrize(
    "stmt, marker, message",
    [
        ("case n is when others => null; when 0 => null; end case;", "when 0", "'when others' must be the last"),
        ("case n is when 0 to 3 => null; end case;", "to 3", "unsupported construct: a range as a choice"),
    ],
)
def test_a_case_statement_out_of_the_subset_is_located(stmt, marker, message):
    text = arch("signal n : integer;", f"p: process (n) begin {stmt} end process p;")
    err = parse_error(text)
    assert message in err.message
    assert err.loc.line == position(text, marker)[0]
