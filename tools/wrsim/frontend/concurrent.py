"""Concurrent statements of the subset: simultaneous statements (simple, if-use, case-use, null, procedural),
instances, generate statements, processes, concurrent signal assignments (the A->D form, and the conditional and
selected ones as their equivalent processes), assertions and break.
Each parse method's docstring starts with the rule it reads, in the notation of IEEE 1076 and 1076.1."""

from __future__ import annotations

from abc import ABC, abstractmethod

from wrsim.errors import SourceError
from wrsim.frontend import ast
from wrsim.frontend.lexer import Token
from wrsim.frontend.statements import StatementParser

__all__ = ["ConcurrentParser"]


_SIGNAL_FUNCTIONS = ("event", "stable", "last_value")  # attributes whose prefix signal a read reads (1076-2008 10.2)


def _read_names(stmts: list, local: set[str] | frozenset[str] = frozenset()) -> list[ast.Expr]:
    """What `stmts` read that may be a signal, for a sensitivity (IEEE 1076-2008 10.2, `process (all)` and the
    process of a concurrent signal assignment): the simple names, the 'above attributes, and the prefixes of 'event,
    'stable and 'last_value; not the names in `local` (the process's own declarations) nor loop variables."""
    out: list[ast.Expr] = []
    local = {*local, *(s.var for s, _ in ast.nested(stmts) if isinstance(s, ast.ForLoop))}
    for s, _ in ast.nested(stmts):
        for x in (x for e in _read_by(s) for x in ast.expressions(e)):
            if isinstance(x, ast.Attr) and x.attr in _SIGNAL_FUNCTIONS:
                x = ast.Name(x.prefix, x.loc)
            if (isinstance(x, ast.Name) and x.ident not in local) or (isinstance(x, ast.Attr) and x.attr == "above"):
                out.append(x)
    return out


def _read_by(s: ast.SeqStmt) -> list[ast.Expr | None]:
    """The expressions sequential statement `s` evaluates itself (not those of the statements inside it)."""
    if isinstance(s, ast.IfStmt):
        return [cond for cond, _ in s.branches]
    if isinstance(s, ast.ForLoop):
        return [s.low, s.high]
    if isinstance(s, ast.WhileLoop):
        return [s.cond]
    if isinstance(s, ast.SeqSignalAssign):
        return [s.value, s.after, s.reject, *(x for element in s.more for x in element)]
    if isinstance(s, (ast.VarAssign, ast.Return)):
        return [s.value]
    if isinstance(s, ast.Break):
        return [*(v for _, v in s.sets), *s.on, s.cond]
    if isinstance(s, ast.Wait):
        return [*s.on, s.until, s.timeout]
    return []


_UNSUPPORTED_STMTS = {
    "block": "block statement",
    "postponed": "postponed process",
}


class ConcurrentParser(StatementParser, ABC):
    """Concurrent statements, on top of the sequential ones; the declarations they contain are the parser's."""

    @abstractmethod
    def local_declarations(self) -> list:
        """The variable and constant declarations of a function or process, up to `begin`."""

    @abstractmethod
    def declarations(self, stop: tuple[str, ...]) -> list:
        """The declarations of an architecture or generate statement, up to `stop`."""

    def concurrent_statement(self) -> ast.ConcurrentStmt:
        """concurrent_statement ::= [ label : ] ( component_instantiation_statement | simultaneous_if_statement
        | simultaneous_case_statement | generate_statement | simultaneous_procedural_statement
        | concurrent_assertion_statement | concurrent_break_statement | process_statement
        | simultaneous_null_statement | concurrent_signal_assignment_statement
        | simple_simultaneous_statement )"""
        label = None
        if self.tok.kind == "id" and self.peek().is_("op", ":"):
            label = self.advance().text
            self.advance()
        t = self.tok
        if self.at_kw(*_UNSUPPORTED_STMTS):
            raise self.unsupported(_UNSUPPORTED_STMTS[self.tok.text])
        if self.accept_kw("entity"):
            return self.instance(label, "entity", t)
        if self.accept_kw("component"):
            return self.instance(label, "component", t)
        if self.at_kw("configuration"):
            raise self.unsupported("configuration instantiation")
        if (
            label
            and self.tok.kind == "id"
            and (self.peek().is_("kw", "generic") or self.peek().is_("kw", "port") or self.peek().is_("op", ";"))
        ):
            return self.instance(label, "component", t)
        if self.accept_kw("if"):
            return self.if_use_or_generate(label, t)
        if self.accept_kw("case"):
            return self.case_use_or_generate(label, t)
        if self.accept_kw("for"):
            return self.for_generate(label, t)
        if self.accept_kw("procedural"):
            return ast.Procedural(*self.body_of("procedural"), t.loc)
        if self.accept_kw("assert"):
            return self.assertion(t)
        if self.at_kw("break"):
            return self.break_statement()
        if self.accept_kw("process"):
            return self.process(label, t)
        if self.accept_kw("null"):
            self.expect_op(";")
            return ast.SimultaneousNull(t.loc)
        if self.accept_kw("with"):
            return self.selected_assignment(label, t)
        lhs = self.simple_expression()
        if self.at_op("<="):
            return self.signal_assignment(lhs, label, t)
        if not self.accept_op("=="):
            raise self.error(f"expected '==' in simultaneous statement, found {self.describe(self.tok)}")
        rhs = self.simple_expression()
        self.tolerance_aspect()
        self.expect_op(";")
        return ast.SimpleSimultaneous(lhs, rhs, label, t.loc)

    def tolerance_aspect(self) -> None:
        """tolerance_aspect ::= tolerance string_expression

        Accepted and not used (1076.1): ngspice's tolerances are set per nature. The string is a literal or a
        string expression, e.g. the tolerance group of a subtype (`velocity'tolerance`)."""
        if self.accept_kw("tolerance"):
            if self.tok.kind == "str":
                self.advance()
            elif self.tok.kind == "id":
                self.simple_expression()
            else:
                raise self.error(
                    f"expected a tolerance group string after 'tolerance', found {self.describe(self.tok)}"
                )

    # ------------------------------------------------------------------ simultaneous statements
    def if_use_or_generate(self, label: str | None, t: Token) -> ast.SimultaneousIf | ast.Generate:
        """After `if`: simultaneous_if_statement ::= if condition use simultaneous_statement_part { elsif condition
        use simultaneous_statement_part } [ else simultaneous_statement_part ] end use [ label ] ;
        or an if-generate: if condition generate generate_statement_body"""
        cond = self.expression()
        if self.accept_kw("generate"):
            return self.generate(label, t, cond, None, None, None, False)
        self.expect_kw("use")
        arms: list[tuple[ast.Expr | None, list[ast.ConcurrentStmt]]] = [
            (cond, self.simultaneous_part(("elsif", "else", "end")))
        ]
        while self.accept_kw("elsif"):
            cond = self.expression()
            self.expect_kw("use")
            arms.append((cond, self.simultaneous_part(("elsif", "else", "end"))))
        if self.accept_kw("else"):
            arms.append((None, self.simultaneous_part(("end",))))
        self.end_of("use", name=label)
        return ast.SimultaneousIf(arms, label, t.loc)

    def case_use_or_generate(self, label: str | None, t: Token) -> ast.SimultaneousCase | ast.CaseGenerate:
        """After `case`: simultaneous_case_statement ::= case expression use simultaneous_alternative
        { simultaneous_alternative } end case [ label ] ;
        simultaneous_alternative ::= when ( choice { | choice } | others ) => simultaneous_statement_part
        or a case-generate (VHDL-2008): case expression generate case_generate_alternative
        { case_generate_alternative } end generate [ label ] ;
        case_generate_alternative ::= when [ alternative_label : ] choices => generate_statement_body"""
        selector = self.expression()
        if self.accept_kw("generate"):
            if label is None:
                raise self.error("a generate statement needs a label", t)
            alternatives = []
            while self.at_kw("when"):
                alt = self.advance()
                if self.tok.kind == "id" and self.peek().is_("op", ":"):  # an alternative label
                    self.advance()
                    self.advance()
                choices = self.choices()
                alternatives.append((choices, self.generate_body(label, None, None, None, None, False, alt)))
            if not alternatives:
                raise self.error(
                    f"expected 'when' (an alternative of the case-generate), found {self.describe(self.tok)}"
                )
            self.end_generate()
            return ast.CaseGenerate(label, selector, alternatives, t.loc)
        self.expect_kw("use")
        alts = []
        while self.accept_kw("when"):
            choices = self.choices()
            alts.append((choices, self.simultaneous_part(("when", "end"))))
        self.end_of("case", name=label)
        return ast.SimultaneousCase(selector, alts, label, t.loc)

    def simultaneous_part(self, stop: tuple[str, ...]) -> list[ast.ConcurrentStmt]:
        """simultaneous_statement_part ::= { simultaneous_statement } (up to one of the reserved words `stop`)"""
        with self.block():
            out: list[ast.ConcurrentStmt] = []
            while not self.at_kw(*stop):
                s = self.concurrent_statement()
                if isinstance(s, (ast.Instance, ast.Assertion, ast.Break)):
                    raise SourceError(s.loc, "only simultaneous statements are allowed inside if-use/case-use")
                out.append(s)
        return out

    def body_of(self, kind: str) -> tuple[list, list]:
        """`[is] declarations begin statements end [postponed] <kind> [label];` of a process or procedural:
        simultaneous_procedural_statement ::= procedural [ is ] procedural_declarative_part begin
        procedural_statement_part end procedural [ label ] ;"""
        self.accept_kw("is")
        decls = self.local_declarations()
        self.expect_kw("begin")
        body = self.sequence(("end",))
        self.expect_kw("end")
        if kind == "process":
            self.accept_kw("postponed")
        self.expect_kw(kind)
        if self.tok.kind == "id":
            self.advance()
        self.expect_op(";")
        return decls, body

    # ------------------------------------------------------------------ generate statements
    def for_generate(self, label: str | None, t: Token) -> ast.Generate:
        """After `for`: for_generate_statement ::= for identifier in simple_expression ( to | downto )
        simple_expression generate generate_statement_body"""
        var = self.ident("generate parameter")
        self.expect_kw("in")
        low = self.simple_expression()
        downto = self.accept_kw("downto")
        if not downto:
            self.expect_kw("to")
        high = self.simple_expression()
        self.expect_kw("generate")
        return self.generate(label, t, None, var, low, high, downto)

    def generate(
        self,
        label: str | None,
        t: Token,
        cond: ast.Expr | None,
        var: str | None,
        low: ast.Expr | None,
        high: ast.Expr | None,
        downto: bool,
    ) -> ast.Generate:
        """After `generate` of an if- or for-generate: generate_statement_body end generate [ label ] ;"""
        if label is None:
            raise self.error("a generate statement needs a label", t)
        body = self.generate_body(label, cond, var, low, high, downto, t)
        self.end_generate()
        return body

    def end_generate(self) -> None:
        """end generate [ label ] ;"""
        self.expect_kw("end")
        self.expect_kw("generate")
        if self.tok.kind == "id":
            self.advance()
        self.expect_op(";")

    def generate_body(
        self,
        label: str,
        cond: ast.Expr | None,
        var: str | None,
        low: ast.Expr | None,
        high: ast.Expr | None,
        downto: bool,
        t: Token,
    ) -> ast.Generate:
        """generate_statement_body ::= [ block_declarative_part begin ] { concurrent_statement }
        [ end [ alternative_label ] ; ] (the inner `end` of VHDL-2008, not that of `end generate`)"""
        decls = []
        if not self.accept_kw("begin") and self.at_kw(
            "terminal",
            "quantity",
            "constant",
            "signal",
            "subtype",
            "nature",
            "component",
            "function",
            "alias",
            "attribute",
            "limit",
        ):
            decls = self.declarations(("begin",))
            self.expect_kw("begin")
        stmts = []
        with self.block():
            while not self.at_kw("end", "when"):
                stmts.append(self.concurrent_statement())
        if self.at_kw("end") and not self.peek().is_("kw", "generate"):
            self.advance()
            if self.tok.kind == "id":
                self.advance()
            self.expect_op(";")
        return ast.Generate(label, cond, var, low, high, downto, decls, stmts, t.loc)

    # ------------------------------------------------------------------ instances
    def instance(self, label: str | None, kind: str, t: Token) -> ast.Instance:
        """component_instantiation_statement ::= label : ( [ component ] component_name | entity entity_name
        [ ( architecture_identifier ) ] ) [ generic map ( association_list ) ] [ port map ( association_list ) ] ;"""
        if label is None:
            raise self.error("an instance needs a label", t)
        name = self.ident("entity or component name")
        while self.accept_op("."):
            name = self.ident("entity name")
        arch = None
        if kind == "entity" and self.accept_op("("):
            arch = self.ident("architecture name")
            self.expect_op(")")
        gmap = pmap = []
        if self.accept_kw("generic"):
            self.expect_kw("map")
            gmap = self.association_list()
        if self.accept_kw("port"):
            self.expect_kw("map")
            pmap = self.association_list()
        self.expect_op(";")
        return ast.Instance(label, kind, name, arch, gmap, pmap, t.loc)

    # ------------------------------------------------------------------ processes, signals, assertions
    def process(self, label: str | None, t: Token) -> ast.Process:
        """After `process`: process_statement ::= process [ ( sensitivity_list ) ] [ is ] process_declarative_part
        begin process_statement_part end [ postponed ] process [ label ] ;"""
        sensitivity: list[ast.Expr] = []
        every = False
        if self.accept_op("("):
            every = self.accept_kw("all")
            if not every:
                sensitivity = self.names()
            self.expect_op(")")
        decls, body = self.body_of("process")
        if every:  # VHDL-2008: sensitive to every signal it reads (elaboration keeps the signals and 'above)
            sensitivity = _read_names(body, {d.name for d in decls})
        return ast.Process(label, sensitivity, decls, body, t.loc, implied=every)

    def signal_assignment(self, lhs: ast.Expr, label: str | None, t: Token) -> ast.SignalAssign | ast.Process:
        """concurrent_signal_assignment_statement ::= target <= [ delay_mechanism ] waveform
        { when condition else waveform } [ when condition ] ;   waveform ::= expression [ after time_expression ]
        | unaffected.  `s <= '1' when condition else '0';` (or `s(k) <= ...`) on a condition of the analog side is
        the A->D form; any other is the equivalent process, sensitive to the signals it reads (IEEE 1076 11.6)."""
        self.expect_op("<=")
        if isinstance(lhs, ast.Name):
            target, index = lhs.ident, None
        elif isinstance(lhs, ast.Call) and len(lhs.args) == 1 and isinstance(lhs.args[0].actual, ast.Num):
            target, index = lhs.name, int(lhs.args[0].actual.value)
        else:
            raise self.unsupported("signal assignment target other than a name or name(k)", t)
        mechanism = self.delay_mechanism()
        arms: list[tuple[ast.SeqSignalAssign | None, ast.Expr | None]] = []
        while not arms or (arms[-1][1] is not None and self.accept_kw("else")):
            arms.append((self.waveform(target, mechanism, t), self.expression() if self.accept_kw("when") else None))
        self.expect_op(";")
        first, last = arms[0], arms[-1]
        if (
            len(arms) == 2
            and first[1] is not None
            and last[1] is None
            and mechanism == (False, None)
            and all(s is not None and s.after is None and not s.more and isinstance(s.value, ast.Char) for s, _ in arms)
            and [s.value.value for s, _ in arms if s is not None and isinstance(s.value, ast.Char)] == ["1", "0"]
        ):
            return ast.SignalAssign(target, index, first[1], t.loc)
        if index is not None:
            raise self.unsupported("a conditional signal assignment to an element name(k)", t)
        return self.equivalent_process(label, [(cond, [s] if s else []) for s, cond in arms], t)

    def selected_assignment(self, label: str | None, t: Token) -> ast.Process:
        """After `with`: a concurrent selected signal assignment (StatementParser.selected_arms) as its process."""
        return self.equivalent_process(label, list(self.selected_arms(t)), t)

    def equivalent_process(self, label: str | None, arms: list[tuple[ast.Expr | None, list]], t: Token) -> ast.Process:
        """The process of a concurrent signal assignment: an if over its arms, sensitive to every name it reads
        (elaboration keeps the signals and 'above among them: `Process.implied`)."""
        body: list = arms[0][1] if len(arms) == 1 and arms[0][0] is None else [ast.IfStmt(arms, t.loc)]
        return ast.Process(label, _read_names(body), [], body, t.loc, implied=True)

    def assertion(self, t: Token) -> ast.Assertion:
        """After `assert`: concurrent_assertion_statement ::= assert condition [ report string_literal ]
        [ severity identifier ] ;"""
        cond = self.expression()
        report = "assertion violation"
        severity = "error"
        if self.accept_kw("report"):
            if not self.at("str"):
                raise self.unsupported("report expression other than one string literal")
            rt = self.advance()
            report = rt.text
            if self.at_op("&"):
                raise self.unsupported("report expression other than one string literal ('&')", rt)
        if self.accept_kw("severity"):
            severity = self.ident("severity level")
        self.expect_op(";")
        return ast.Assertion(cond, report, severity, t.loc)
