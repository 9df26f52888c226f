"""Concurrent statements of the subset: simultaneous statements (simple, if-use, case-use, null, procedural),
instances, generate statements, processes, concurrent signal assignments (the A->D form), assertions and break.
Each parse method's docstring starts with the rule it reads, in the notation of IEEE 1076 and 1076.1."""

from __future__ import annotations

from abc import ABC, abstractmethod

from wrsim.errors import SourceError
from wrsim.frontend import ast
from wrsim.frontend.lexer import Token
from wrsim.frontend.statements import StatementParser

__all__ = ["ConcurrentParser"]

_UNSUPPORTED_STMTS = {
    "block": "block statement",
    "with": "selected signal assignment",
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
            return self.case_use(label, t)
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
        lhs = self.simple_expression()
        if self.at_op("<="):
            return self.signal_assignment(lhs, t)
        if not self.accept_op("=="):
            raise self.error(f"expected '==' in simultaneous statement, found {self.describe(self.tok)}")
        rhs = self.simple_expression()
        self.tolerance_aspect()
        self.expect_op(";")
        return ast.SimpleSimultaneous(lhs, rhs, label, t.loc)

    def tolerance_aspect(self) -> None:
        """tolerance_aspect ::= tolerance string_expression

        Accepted and not used (1076.1): ngspice's tolerances are set per nature."""
        if self.accept_kw("tolerance"):
            if self.tok.kind != "str":
                raise self.error(
                    f"expected a tolerance group string after 'tolerance', found {self.describe(self.tok)}"
                )
            self.advance()

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

    def case_use(self, label: str | None, t: Token) -> ast.SimultaneousCase:
        """After `case`: simultaneous_case_statement ::= case expression use simultaneous_alternative
        { simultaneous_alternative } end case [ label ] ;
        simultaneous_alternative ::= when ( choice { | choice } | others ) => simultaneous_statement_part"""
        selector = self.expression()
        if not self.accept_kw("use"):
            raise self.error("expected 'use' (simultaneous case); a case-generate is not supported")
        alts = []
        while self.accept_kw("when"):
            if self.accept_kw("others"):
                choices = None
            else:
                choices = [self.simple_expression()]
                while self.accept_op("|"):
                    choices.append(self.simple_expression())
            self.expect_op("=>")
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
        """After `generate`: generate_statement_body ::= [ block_declarative_part begin ] { concurrent_statement }
        end generate [ label ] ;"""
        if label is None:
            raise self.error("a generate statement needs a label", t)
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
            while not self.at_kw("end"):
                stmts.append(self.concurrent_statement())
        self.expect_kw("end")
        self.expect_kw("generate")
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
        if self.accept_op("("):
            if self.at_kw("all"):
                raise self.unsupported("process (all)")
            sensitivity = self.names()
            self.expect_op(")")
        decls, body = self.body_of("process")
        return ast.Process(label, sensitivity, decls, body, t.loc)

    def signal_assignment(self, lhs: ast.Expr, t: Token) -> ast.SignalAssign:
        """concurrent_signal_assignment_statement ::= target <= '1' when condition else '0' ;
        target ::= name | name ( integer_literal )  — the one A->D form of an AMS architecture."""
        self.expect_op("<=")
        if isinstance(lhs, ast.Name):
            target, index = lhs.ident, None
        elif isinstance(lhs, ast.Call) and len(lhs.args) == 1 and isinstance(lhs.args[0].actual, ast.Num):
            target, index = lhs.name, int(lhs.args[0].actual.value)
        else:
            raise self.unsupported("signal assignment target other than a name or name(k)", t)
        form = (
            "concurrent signal assignment other than s <= '1' when <condition> else '0' (digital logic belongs in "
            "a digital file run by GHDL)"
        )
        if not self.tok.is_("char", "1"):
            raise self.unsupported(form, t)
        self.advance()
        if not self.accept_kw("when"):
            raise self.unsupported(form, t)
        cond = self.expression()
        if not (self.accept_kw("else") and self.tok.is_("char", "0")):
            raise self.unsupported(form, t)
        self.advance()
        self.expect_op(";")
        return ast.SignalAssign(target, index, cond, t.loc)

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
