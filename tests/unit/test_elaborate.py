"""Elaboration: every semantic error is one SourceError/WrsimError at the VHDL-AMS position that causes it
(names, natures, types, the 1076.1 equation count, structural solvability, assertions with the instance path,
parameter sets), and static parts of expressions and functions fold symbolically."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from wrsim import paths
from wrsim.backend.ngspice.netlist import Analysis
from wrsim.backend.ngspice.raw import Waveforms
from wrsim.data.params import load_params
from wrsim.elab import symbolic as sy
from wrsim.elab.design import Design
from wrsim.elab.elaborate import elaborate
from wrsim.elab.library import Library, load_library
from wrsim.errors import SourceError, WrsimError
from wrsim.runner import simulate as run_simulation

ROOT = paths.ROOT
USES = (
    "library IEEE;\nuse IEEE.MATH_REAL.all;\nuse IEEE.ELECTRICAL_SYSTEMS.all;\n"
    "use IEEE.MECHANICAL_SYSTEMS.all;\nuse work.wr_common.all;\n"
)

RES = """entity res is
  generic (r : resistance := 1.0);
  port (terminal p, n : electrical);
end entity res;
architecture a of res is
  quantity v across i through p to n;
begin
  assert r > 0.0 report "res: r must be > 0" severity failure;
  v == r * i;
end architecture a;
"""


def tb(decls: str, stmts: str, generics: str = "") -> str:
    """A bench entity `tb` (no ports) with one architecture `s`."""
    g = f" generic ({generics});" if generics else ""
    return f"entity tb is{g} end entity tb;\narchitecture s of tb is\n{decls}\nbegin\n{stmts}\nend architecture s;\n"


@dataclass
class Source:
    """A model file written to tmp_path and the library it was loaded into (with vhdl/ieee, vhdl/common)."""

    path: Path
    text: str
    lib: Library

    def at(self, marker: str) -> str:
        """`file:line:col` of the first occurrence of `marker`."""
        k = self.text.index(marker)
        return f"{self.path}:{self.text.count(chr(10), 0, k) + 1}:{k - self.text.rfind(chr(10), 0, k)}"

    def elaborate(self, top: str = "tb", params=None, overrides=None) -> Design:
        return elaborate(self.lib, top, params, overrides)

    def error(self, top: str = "tb", params=None, overrides=None) -> WrsimError:
        with pytest.raises(WrsimError) as err:
            self.elaborate(top, params, overrides)
        return err.value


def source(tmp_path: Path, *units: str) -> Source:
    text = "".join(USES + u for u in units)
    path = tmp_path / "model.vhd"
    path.write_text(text, encoding="utf-8")
    return Source(path, text, load_library([ROOT / "vhdl" / "ieee", ROOT / "vhdl" / "common", path]))


def simulate(src: Source, tmp_path: Path) -> Waveforms:
    return run_simulation(src.elaborate(), Analysis(1e-3), tmp_path / "work", title="test")


def residual(design: Design, quantity: str) -> sy.S:
    return next(eq.residual for eq in design.top.equations if eq.paired == quantity)


def substitute(s: sy.S, values: dict[str, float]) -> sy.S:
    """`s` with the nodes in `values` replaced by constants, folded again."""
    if isinstance(s, sy.Node) and s.name in values:
        return sy.const(values[s.name])
    if isinstance(s, sy.Op):
        return sy.op(s.name, *(substitute(a, values) for a in s.args))
    if isinstance(s, sy.Cond):
        return sy.cond(*(substitute(a, values) for a in (s.test, s.then, s.other)))
    return s


# ------------------------------------------------------------------------------------------------ names
def test_unknown_name(tmp_path):
    src = source(tmp_path, tb("  quantity x : real;  -- [1] x", "  x == 2.0 * y;"))
    assert str(src.error()) == f"{src.at('y;')}: unknown name 'y'"


def test_unknown_entity_lists_the_known_entities(tmp_path):
    src = source(
        tmp_path,
        RES,
        tb("  terminal t : electrical;", "  u1: entity work.resx port map (p => t, n => electrical_ref);"),
    )
    assert str(src.error()) == f"{src.at('entity work.resx')}: unknown entity 'resx' (known entities: res, tb)"
    with pytest.raises(WrsimError, match=r"^unknown entity 'nope' \(known entities: res, tb\)$"):
        src.elaborate("nope")


def test_unknown_architecture_lists_the_existing_ones(tmp_path):
    other = "architecture b of res is\n  quantity v across i through p to n;\nbegin\n  v == 0.0;\nend architecture b;\n"
    src = source(
        tmp_path,
        RES,
        other,
        tb("  terminal t : electrical;", "  u1: entity work.res(c) port map (p => t, n => electrical_ref);"),
    )
    assert str(src.error()) == f"{src.at('entity work.res(c)')}: entity 'res' has no architecture 'c' (it has: a, b)"


def test_duplicate_declaration(tmp_path):
    src = source(tmp_path, tb("  quantity x : real;  -- [1] x\n  quantity x : real;  -- [1] again", "  x == 1.0;"))
    first = src.at("quantity x")
    assert str(src.error()) == f"{src.at('quantity x : real;  -- [1] again')}: 'x' is already declared at {first}"


def test_duplicate_instance_label(tmp_path):
    # found by the fuzzer: a repeated label made the second instance read the first one's generics
    src = source(
        tmp_path,
        RES,
        tb(
            "  terminal t : electrical;",
            "  u1: entity work.res port map (p => t, n => electrical_ref);\n"
            "  U1: entity work.res port map (p => t, n => electrical_ref);",
        ),
    )
    first, second = (src.at(label).rsplit(":", 1)[0] for label in ("u1: entity", "U1: entity"))
    assert str(src.error()) == (
        f"{second}:7: label 'u1' is already used in this architecture (at {first}:7): instance labels must be unique"
    )  # an instance is located at `entity`


# ------------------------------------------------------------------------------------------------ natures, ports
def test_nature_mismatch_in_a_port_map(tmp_path):
    src = source(
        tmp_path, RES, tb("  terminal t : rotational;", "  u1: entity work.res port map (p => t, n => electrical_ref);")
    )
    assert str(src.error()) == (
        f"{src.at('t, n =>')}: nature mismatch: port 'p' of res is electrical, terminal 't' is rotational"
    )


def test_nature_mismatch_in_a_branch_declaration(tmp_path):
    src = source(
        tmp_path,
        tb(
            "  terminal t : rotational;\n  terminal u : electrical;\n  quantity v across i through t to u;", "  v == i;"
        ),
    )
    assert str(src.error()) == (
        f"{src.at('quantity v')}: nature mismatch: terminal 't' is rotational, 'u' is electrical"
    )


def test_unconnected_port(tmp_path):
    src = source(tmp_path, RES, tb("  terminal t : electrical;", "  u1: entity work.res port map (p => t);"))
    assert str(src.error()) == f"{src.at('entity work.res')}: port 'n' of res is not connected (instance u1)"


def test_generic_map_to_a_nonexistent_generic(tmp_path):
    src = source(
        tmp_path,
        RES,
        tb(
            "  terminal t : electrical;",
            "  u1: entity work.res generic map (rr => 2.0)\n    port map (p => t, n => electrical_ref);",
        ),
    )
    assert str(src.error()) == f"{src.at('rr =>')}: res has no generic 'rr' (it has: r)"


def test_generic_without_value_names_the_instance(tmp_path):
    child = (
        "entity c is generic (g : real); port (quantity q : out real); end entity c;\n"
        "architecture a of c is\nbegin\n  q == g;\nend architecture a;\n"
    )
    src = source(tmp_path, child, tb("  quantity x : real;  -- [1] x", "  u: entity work.c port map (q => x);"))
    assert str(src.error()) == (
        f"{src.at('entity work.c')}: generic 'g' of c (instance tb.u) has no value: map it or give it a default"
    )


# ------------------------------------------------------------------------------------------------ types
def test_integer_times_real_is_a_type_mismatch(tmp_path):
    # VHDL has no implicit integer -> real conversion
    src = source(tmp_path, tb("  quantity x : real;  -- [1] x", "  x == 2 * x + 1.0;"))
    assert str(src.error()) == (
        f"{src.at('* x')}: type mismatch: integer * real (write real literals as 2.0, or convert with real(...))"
    )


def test_the_conversion_the_type_message_suggests_works(tmp_path):
    src = source(tmp_path, tb("  quantity x : real;  -- [1] x", "  x == real(2) * 1.5;"))
    assert residual(src.elaborate(), "x") == sy.op("-", sy.Node("x"), sy.const(3.0))


def test_generic_map_type_mismatch(tmp_path):
    child = (
        "entity c is generic (n : integer := 1); port (quantity q : out real); end entity c;\n"
        "architecture a of c is\nbegin\n  q == 1.0;\nend architecture a;\n"
    )
    src = source(
        tmp_path,
        child,
        tb("  quantity x : real;  -- [1] x", "  u: entity work.c generic map (n => 2.0) port map (q => x);"),
    )
    assert str(src.error()) == f"{src.at('2.0) port')}: type mismatch: generic 'n' of c is integer, actual is real"


# ------------------------------------------------------------------------------------------------ equations
def test_equation_count_names_the_unknowns(tmp_path):
    src = source(
        tmp_path,
        RES.replace("  v == r * i;\n", ""),
        tb(
            "  terminal t : electrical;\n  quantity x : real;  -- [1] x\n  quantity y : real;  -- [1] y",
            "  x == 1.0;\n  u1: entity work.res port map (p => t, n => electrical_ref);",
        ),
    )
    err = src.error()
    # the child is modelled first: 0 statements for its through quantity
    assert str(err).startswith(
        f"{src.at('architecture a of res')}: architecture a of res: 0 simultaneous "
        f"statement(s) for 1 unknown(s) (i); 1076.1 requires one equation per through "
        f"quantity, free quantity and out quantity port"
    )
    src = source(tmp_path, tb("  quantity x : real;  -- [1] x\n  quantity y : real;  -- [1] y", "  x == 1.0;"))
    assert str(src.error()).startswith(
        f"{src.at('architecture s')}: architecture s of tb: 1 simultaneous statement(s) for 2 unknown(s) (x, y)"
    )


def test_structurally_singular_architecture_names_the_competing_equations(tmp_path):
    src = source(
        tmp_path, tb("  quantity x : real;  -- [1] x\n  quantity y : real;  -- [1] y", "  x == 1.0;\n  2.0 * x == 3.0;")
    )
    assert str(src.error()) == (
        f"{src.at('architecture s')}: architecture s of tb is structurally singular: "
        f"the equations at {src.at('x == 1.0')}; {src.at('2.0 * x')} compete for the same "
        f"unknowns, and y is determined by none"
    )


def test_out_quantity_port_passed_on_to_a_child_is_determined_by_the_child(tmp_path):
    # 1076.1: a quantity that is the actual of an out quantity port is determined by the instance, also when
    # it is itself an out quantity port of the enclosing entity
    source_ = (
        "entity src is\n  port (quantity q : out real);  -- [1] q\nend entity src;\n"
        "architecture a of src is\nbegin\n  q == 1.0;\nend architecture a;\n"
    )
    wrap = (
        "entity wrap is\n  port (quantity q : out real);  -- [1] q\nend entity wrap;\n"
        "architecture a of wrap is\nbegin\n  u: entity work.src port map (q => q);\nend architecture a;\n"
    )
    src = source(
        tmp_path, source_, wrap, tb("  quantity x : real;  -- [1] x", "  w: entity work.wrap port map (q => x);")
    )
    assert [c.label for c in src.elaborate().top.children] == ["w"]


@pytest.mark.parametrize(
    "kind, stmt",
    [
        ("if", "  if domain = quiescent_domain use\n    x == 1.0;\n  else\n    x == 2.0;\n    y == 3.0;\n  end use;"),
        ("case", "  case 1 use\n    when 1 => x == 1.0;\n    when others => x == 2.0; y == 3.0;\n  end case;"),
    ],
)
def test_branches_with_different_equation_counts(tmp_path, kind, stmt):
    src = source(tmp_path, tb("  quantity x : real;  -- [1] x\n  quantity y : real;  -- [1] y", stmt))
    assert str(src.error()) == (
        f"{src.at(stmt.split(maxsplit=1)[0] + ' ')}: the branches of this simultaneous "
        f"{kind} have different numbers of equations (1, 2); 1076.1 requires the same"
    )


# ------------------------------------------------------------------------------------------------ assertions
NESTED = [
    """entity leaf is
  generic (k : real := 1.0;                    -- [N] gain
           v : real_vector := (1.0, 2.5));     -- [m] table
end entity leaf;
architecture a of leaf is
  quantity q : real;                           -- [N] output
begin
  assert k < 10.0 report "leaf: k must be < 10" severity failure;
  q == k;
end architecture a;
""",
    """entity mid is
  generic (m : real := 1.0);                   -- [N] gain
end entity mid;
architecture a of mid is
begin
  inner: entity work.leaf generic map (k => 4.0 * m);
end architecture a;
""",
    tb("", "  outer: entity work.mid generic map (m => top_g);", "top_g : real := 2.0"),
]


def test_assertion_failure_reports_text_instance_path_and_generics(tmp_path):
    src = source(tmp_path, *NESTED)
    assert src.elaborate().tree.children[0].children[0].generics.values == {"k": 8.0, "v": [1.0, 2.5]}
    err = src.error(overrides={"top_g": 3.0})
    assert isinstance(err, SourceError)
    assert str(err) == f"{src.at('assert k')}: leaf: k must be < 10 (instance tb.outer.inner: k = 12, v = (1, 2.5))"


def test_assertion_in_the_entity_statement_part(tmp_path):
    ent = (
        "entity tb is\n  generic (a : real := -1.0);  -- [1] a\nbegin\n"
        '  assert a > 0.0 report "tb: a must be > 0" severity failure;\nend entity tb;\n'
        "architecture s of tb is\n  quantity x : real;  -- [1] x\nbegin\n  x == a;\nend architecture s;\n"
    )
    src = source(tmp_path, ent)
    assert str(src.error()) == f"{src.at('assert a')}: tb: a must be > 0 (instance tb: a = -1)"
    assert src.elaborate(overrides={"a": 2.0}).tree.generics.values == {"a": 2.0}


def test_notes_and_warnings_do_not_stop_elaboration(tmp_path):
    src = source(
        tmp_path,
        tb(
            "  quantity x : real;  -- [1] x",
            '  assert false report "a note" severity note;\n'
            '  assert false report "a warning" severity warning;\n  x == 1.0;',
        ),
    )
    assert residual(src.elaborate(), "x") == sy.op("-", sy.Node("x"), sy.const(1.0))


def test_assertion_on_a_quantity_must_be_static(tmp_path):
    src = source(
        tmp_path,
        tb(
            "  quantity x : real;  -- [1] x",
            '  assert x > 0.0 report "tb: x must be > 0" severity failure;\n  x == 1.0;',
        ),
    )
    msg = str(src.error())
    assert msg.startswith(f"{src.at('assert x')}: ") or msg.startswith(f"{src.at('x > 0.0')}: "), msg
    assert "static" in msg and "unknown name" not in msg, msg


# ------------------------------------------------------------------------------------------------ case-generate
CASE_GENERATE = """  g: case kind generate
    when one: 1 =>
      constant v : real := 1.0;
    begin
      x == v;
    end one;
    when 2 | 3 =>
      x == 2.0;
    OTHERS
  end generate g;"""


@pytest.mark.parametrize("kind, value", [(1, 1.0), (2, 2.0), (3, 2.0), (7, 7.0)])
def test_a_case_generate_elaborates_the_alternative_its_selector_chooses(tmp_path, kind, value):
    others = "when others =>\n      quantity y : real;\n    begin\n      y == real(kind);\n      x == y;"
    src = source(tmp_path, tb("  quantity x : real;", CASE_GENERATE.replace("OTHERS", others), "kind : integer := 1"))
    design = src.elaborate(overrides={"kind": kind})
    res = residual(design, "x")
    if kind == 7:  # what the alternative declares is named g__<name>
        assert res == sy.op("-", sy.Node("x"), sy.Node("g__y")) and "g__y" in design.top.quantities
        res = residual(design, "g__y")
        assert res == sy.op("-", sy.Node("g__y"), sy.const(value))
    else:
        assert res == sy.op("-", sy.Node("x"), sy.const(value))


@pytest.mark.parametrize(
    "generics, selector, message",
    [
        (
            "kind : integer := 5",
            "kind",
            "case-generate 'g': no alternative has the selector's value, and there is no others",
        ),
        ("kind : integer := 1", "integer(now)", "the selector and the choices of case-generate 'g' must be static"),
    ],
)
def test_a_case_generate_needs_a_static_selector_with_an_alternative(tmp_path, generics, selector, message):
    text = CASE_GENERATE.replace("OTHERS", "").replace("case kind", f"case {selector}")
    src = source(tmp_path, tb("  quantity x : real;", text, generics))
    assert str(src.error()).startswith(f"{src.at(selector + ' generate')}: {message}")


def test_a_case_generate_value_in_two_alternatives_is_an_error(tmp_path):
    text = CASE_GENERATE.replace("OTHERS", "when 3 =>\n      x == 3.0;")
    src = source(tmp_path, tb("  quantity x : real;", text, "kind : integer := 3"))
    assert str(src.error()) == f"{src.at('when 3')}: case-generate 'g': a second choice equals the selector's value"


# ------------------------------------------------------------------------------------------------ functions
COUNT = """  function count(m : integer) return real is
    variable y : real := 0.0;
  begin
    for k in 1 to m loop
      y := y + 1.0;
    end loop;
    return y;
  end function count;"""


def test_loop_bounds_must_be_static(tmp_path):
    src = source(tmp_path, tb(COUNT + "\n  quantity x : real;  -- [1] x", "  x == count(integer(x));"))
    assert str(src.error()) == f"{src.at('for k')}: loop bounds must be static (known at elaboration)"


def test_a_generic_is_a_static_loop_bound(tmp_path):
    child = (
        "entity c is\n  generic (n : integer := 3);  -- [1] count\n  port (quantity q : out real);  -- [1] q\n"
        "end entity c;\narchitecture a of c is\n" + COUNT + "\nbegin\n  q == count(n);\nend architecture a;\n"
    )
    src = source(
        tmp_path,
        child,
        tb("  quantity x : real;  -- [1] x", "  u: entity work.c generic map (n => 2) port map (q => x);"),
    )
    assert src.elaborate().tree.children[0].generics.values == {"n": 2.0}
    np.testing.assert_allclose(simulate(src, tmp_path)["x"], 2.0)


@pytest.mark.parametrize(
    "body",
    [
        "    y := x;",
        "    if x > 0.0 then\n      return 1.0;\n    end if;",
    ],
)
def test_function_that_can_end_without_return(tmp_path, body):
    f = (
        f"  function f(x : real) return real is\n    variable y : real := 0.0;\n  begin\n{body}\n"
        f"  end function f;\n  quantity x : real;  -- [1] x"
    )
    src = source(tmp_path, tb(f, "  x == f(x);"))
    assert str(src.error()) == f"{src.at('function f')}: function 'f' can end without a return statement"


STEPS = """  function steps(x : real; n : integer) return real is
    variable acc : real := 0.0;
    variable w : real := 0.0;
  begin
    if x < 0.0 then
      return -1.0;
    elsif x < 1.0 then
      for k in 1 to n loop
        w := w + 1.0;
        acc := acc + x * w;
      end loop;
      return acc;
    else
      return 1.0;
    end if;
  end function steps;"""


def test_functions_fold_to_constants_when_arguments_are_static(tmp_path):
    decls = (
        STEPS + "\n  constant c : real := steps(0.5, 3);\n"
        "  constant t : real := table_lookup(1.5, (0.0, 1.0, 2.0), (0.0, 10.0, 30.0));\n"
        + "\n".join(f"  quantity {q} : real;  -- [1] {q}" for q in ("a", "b", "cc", "d", "e"))
    )
    src = source(
        tmp_path,
        tb(
            decls,
            "  a == c;\n  b == steps(-2.0, 3);\n  cc == steps(g, 4);\n  d == t;\n  e == steps(4.0, 1) + sqrt(4.0);",
            "g : real := 0.25",
        ),
    )
    design = src.elaborate()
    expected = {"a": 0.5 * (1 + 2 + 3), "b": -1.0, "cc": 0.25 * (1 + 2 + 3 + 4), "d": 20.0, "e": 3.0}
    for q, value in expected.items():
        assert residual(design, q) == sy.op("-", sy.Node(q), sy.const(value)), q


def test_branches_on_quantities_become_conditional_expressions(tmp_path):
    src = source(
        tmp_path,
        tb(
            STEPS + "\n  quantity x : real;  -- [1] x\n  quantity z : real;  -- [1] z",
            "  x == 0.5;\n  z == steps(x, 2);",
        ),
    )
    res = residual(src.elaborate(), "z")
    assert isinstance(res, sy.Op) and isinstance(res.args[1], sy.Cond)
    for x, value in [(-3.0, -1.0), (0.5, 0.5 * (1 + 2)), (0.75, 0.75 * (1 + 2)), (2.0, 1.0)]:
        assert substitute(res, {"x": x, "z": 0.0}) == sy.const(-value), x


# ------------------------------------------------------------------------------------------------ domain
def if_use(cond: str) -> str:
    return f"  if {cond} use\n    w == 1.0;\n  else\n    w == 2.0;\n  end use;"


def w_over_time(src: Source, tmp_path: Path) -> np.ndarray:
    """w simulated: its first point is the DC operating point (quiescent domain), the rest the time domain."""
    return simulate(src, tmp_path)["w"]


@pytest.mark.parametrize(
    "cond, in_quiescent, in_time",
    [
        ("domain = quiescent_domain", 1.0, 2.0),
        ("quiescent_domain = domain", 1.0, 2.0),
        ("domain /= time_domain", 1.0, 2.0),
        ("domain = time_domain", 2.0, 1.0),
        ("domain /= quiescent_domain", 2.0, 1.0),
    ],
)
def test_domain_selects_the_quiescent_or_the_time_domain_branch(tmp_path, cond, in_quiescent, in_time):
    w = w_over_time(source(tmp_path, tb("  quantity w : real;  -- [1] w", if_use(cond))), tmp_path)
    assert w[0] == pytest.approx(in_quiescent)
    np.testing.assert_allclose(w[1:], in_time)


def test_domain_compared_with_a_number_is_an_error(tmp_path):
    src = source(tmp_path, tb("  quantity w : real;  -- [1] w", if_use("domain = 1.0")))
    assert str(src.error()) == (
        f"{src.at('= 1.0')}: 'domain' can only be compared with quiescent_domain or time_domain"
    )


def test_frequency_domain_is_never_the_domain_of_a_transient_run(tmp_path):
    src = source(tmp_path, tb("  quantity w : real;  -- [1] w", if_use("domain = frequency_domain")))
    np.testing.assert_allclose(w_over_time(src, tmp_path), 2.0)  # false at the quiescent point and after


# ------------------------------------------------------------------------------------------------ parameter sets
PARAM_MODEL = (
    """entity dev is
  generic (r  : resistance := 1.0;
           kt : real := 2.0;   -- [N*m/A] torque constant
           n  : integer := 2); -- [1] count
  port (terminal p, m : electrical);
end entity dev;
architecture a of dev is
  quantity v across i through p to m;
begin
  v == r * i;
end architecture a;
""",
    tb("  terminal t : electrical;", "  u1: entity work.dev port map (p => t, m => electrical_ref);"),
)


def params(tmp_path: Path, body: str):
    path = tmp_path / "set.txt"
    path.write_text("# test set\n" + body, encoding="utf-8")
    return path, load_params(path)


def test_parameter_set_values_are_converted_to_the_generic_units(tmp_path):
    src = source(tmp_path, *PARAM_MODEL)
    _, pset = params(tmp_path, "[dev]\nr = 550 mOhm\nkt = 0.0204 V*s/rad\n")
    assert src.elaborate(params=pset).tree.children[0].generics.values == pytest.approx(
        {"r": 0.55, "kt": 0.0204, "n": 2}
    )


def test_parameter_section_naming_no_entity_lists_the_entities(tmp_path):
    src = source(tmp_path, *PARAM_MODEL)
    path, pset = params(tmp_path, "[devv]\nr = 1 Ohm\n")
    assert str(src.error(params=pset)) == f"{path}:3: [devv] names no entity of the library (entities: dev, tb)"


def test_parameter_key_naming_no_generic_lists_the_generics(tmp_path):
    src = source(tmp_path, *PARAM_MODEL)
    path, pset = params(tmp_path, "[dev]\nr = 1 Ohm\nk_t = 1 N*m/A\n")
    assert str(src.error(params=pset)) == f"{path}:4: [dev] k_t: dev has no generic 'k_t' (it has: r, kt, n)"


@pytest.mark.parametrize("line, key, unit", [("r = 1 H", "r", "Ohm"), ("kt = 3 N*m", "kt", "N*m/A")])
def test_parameter_with_a_wrong_dimension_names_file_line_and_key(tmp_path, line, key, unit):
    src = source(tmp_path, *PARAM_MODEL)
    path, pset = params(tmp_path, f"[dev]\n{line}\n")
    msg = str(src.error(params=pset))
    assert re.match(
        rf"^{re.escape(str(path))}:3: \[dev\] {key}: cannot convert '{re.escape(line.split()[-1])}' .* "
        rf"to '{re.escape(unit)}'",
        msg,
    ), msg


def test_a_bad_value_from_a_parameter_set_names_the_set_and_key(tmp_path):
    from wrsim import load_library
    from wrsim.data.params import load_params

    bad = tmp_path / "bad.txt"
    bad.write_text("[dcpm_motor]\nra = -0.5 Ohm  # wrong sign\n", encoding="utf-8")
    with pytest.raises(SourceError) as err:
        elaborate(load_library(), "tb_motor_characteristic", load_params(bad), {})
    assert "dcpm_motor: ra must be > 0" in str(err.value)
    assert str(err.value).endswith(f"set by the parameter set at {bad}:2: [dcpm_motor] ra = -0.5")


_LOOPS = (
    "  function f(v : real) return real is\n    variable r : real := 0.0;\n  begin\n{body}\n    return r;\n"
    "  end function f;"
)


@pytest.mark.parametrize(
    "body, stmts, marker, message",
    [
        (
            "    while r < v loop\n      r := r + 1.0;\n    end loop;",
            "  y == f(x);",
            "while r",
            "unsupported construct: a while loop whose condition is not static (it reads quantities or signals)",
        ),
        (
            "    for k in 1 to 3 loop\n      r := r + real(k);\n      exit when r > v;\n    end loop;",
            "  y == f(x);",
            "exit when",
            "unsupported construct: 'exit' outside a loop, or under a condition that is not static",
        ),
        (
            "    loop\n    end loop;",
            "  y == f(1.0);",
            "loop\n    end",
            "function evaluation takes more than",
        ),
    ],
)
def test_a_loop_the_elaboration_cannot_unroll_is_one_located_error(tmp_path, body, stmts, marker, message):
    """Loops in functions and processes are unrolled at elaboration (their conditions static); a condition that reads
    quantities, an exit under one, or a loop that does not end is one error at the loop or the exit."""
    src = source(tmp_path, tb(_LOOPS.format(body=body) + "\n  quantity x, y : real;", f"  x == 1.0 + now;\n{stmts}"))
    err = src.error()
    assert isinstance(err, SourceError) and str(err).startswith(f"{src.at(marker)}: {message}"), str(err)


def test_a_loop_with_a_wait_that_is_not_the_whole_process_body_is_one_located_error(tmp_path):
    body = (
        "  p: process\n  begin\n    s <= 0.0;\n    while true loop\n      s <= 1.0;\n      wait for 1 ms;\n"
        "    end loop;\n  end process p;\n  x == s;"
    )
    src = source(tmp_path, tb("  signal s : real := 0.0;\n  quantity x : real;", body))
    err = src.error()
    assert str(err).startswith(f"{src.at('while true')}: unsupported construct: a while loop or plain loop with a wait")
