"""Sequential statements (function bodies) and concurrent statements (simultaneous statements, if-use,
case-use, instances, signal assignments, assertions, break) of the subset."""
from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from wrsim.errors import SourceError
from wrsim.frontend import ast as ir
from wrsim.frontend.expressions import ExpressionParser
from wrsim.frontend.lexer import Token

__all__ = ["StatementParser", "MAX_BLOCKS"]

MAX_BLOCKS = 32         # if/case/loop bodies inside one another

_UNSUPPORTED_STMTS = {
    "block": "block statement",
    "with": "selected signal assignment",
    "postponed": "postponed process",
}


class StatementParser(ExpressionParser):
    """Statements, on top of the expression grammar."""

    # ------------------------------------------------------------------ sequential statements
    def sequence(self, stop: tuple[str, ...]) -> list[ir.SeqStmt]:
        out = []
        with self.block():
            while not self.at_kw(*stop):
                out.append(self.sequential_statement())
        return out

    @contextmanager
    def block(self) -> Iterator[None]:
        """A statement list inside another statement: at most MAX_BLOCKS deep."""
        self.blocks += 1
        try:
            if self.blocks > MAX_BLOCKS:
                raise self.error(f"statements nested more than {MAX_BLOCKS} levels deep")
            yield
        finally:
            self.blocks -= 1

    def sequential_statement(self) -> ir.SeqStmt:
        t = self.tok
        if self.accept_kw("return"):
            value = self.expression()
            self.expect_op(";")
            return ir.Return(value, t.loc)
        if self.accept_kw("null"):
            self.expect_op(";")
            return ir.NullStmt(t.loc)
        if self.accept_kw("if"):
            branches: list[tuple[ir.Expr | None, list[ir.SeqStmt]]] = []
            cond = self.expression()
            self.expect_kw("then")
            branches.append((cond, self.sequence(("elsif", "else", "end"))))
            while self.accept_kw("elsif"):
                cond = self.expression()
                self.expect_kw("then")
                branches.append((cond, self.sequence(("elsif", "else", "end"))))
            if self.accept_kw("else"):
                branches.append((None, self.sequence(("end",))))
            self.end_of("if")
            return ir.IfStmt(branches, t.loc)
        if self.accept_kw("for"):
            var = self.ident("loop variable")
            self.expect_kw("in")
            low = high = rattr = None
            downto = False
            first = self.simple_expression()
            if isinstance(first, ir.Attr) and first.attr in ("range", "reverse_range") and not self.at_kw(
                    "to", "downto"):
                rattr = first
            else:
                low = first
                if self.accept_kw("downto"):
                    downto = True
                else:
                    self.expect_kw("to")
                high = self.simple_expression()
            self.expect_kw("loop")
            body = self.sequence(("end",))
            self.end_of("loop")
            return ir.ForLoop(var, low, high, downto, rattr, body, t.loc)
        if self.accept_kw("wait"):
            on = self.names() if self.accept_kw("on") else []
            until = self.expression() if self.accept_kw("until") else None
            timeout = self.expression() if self.accept_kw("for") else None
            self.expect_op(";")
            return ir.Wait(on, until, timeout, t.loc)
        if self.at_kw("break"):
            return self.break_statement()
        if self.at_kw("while", "case", "loop", "exit", "next", "report", "assert"):
            raise self.unsupported(f"'{self.tok.text}' statement in a function or process body")
        if self.tok.kind == "id" and self.peek().is_("op", "<="):
            target = self.advance().text
            self.advance()
            if self.at_kw("reject"):
                raise self.unsupported("'reject' delay mechanism (`after` alone is inertial; or transport)")
            transport = self.accept_kw("transport")
            if not transport:
                self.accept_kw("inertial")
            value = self.expression()
            after = self.expression() if self.accept_kw("after") else None
            if self.at_op(","):
                raise self.unsupported("a waveform of several elements (one value, optionally `after` a delay)")
            self.expect_op(";")
            return ir.SeqSignalAssign(target, value, t.loc, after, transport)
        if self.tok.kind == "id" and self.peek().is_("op", ":="):
            target = self.advance().text
            self.advance()
            value = self.expression()
            self.expect_op(";")
            return ir.VarAssign(target, value, t.loc)
        if self.tok.kind == "id" and self.peek().is_("op", "("):
            raise self.unsupported("assignment to a vector element or procedure call", t)
        raise self.error(f"expected a sequential statement, found {self.describe(t)}")

    def local_declarations(self) -> list:
        """The variable and constant declarations of a function or process, up to `begin` (the parser's)."""
        raise NotImplementedError

    def declarations(self, stop: tuple[str, ...]) -> list:
        """The declarations of an architecture or generate statement, up to `stop` (the parser's)."""
        raise NotImplementedError

    def generate(self, label: str | None, t: Token, cond: ir.Expr | None, var: str | None, low: ir.Expr | None,
                 high: ir.Expr | None, downto: bool) -> ir.Generate:
        """After `generate`: `[declarations begin] statements end generate [label];`."""
        if label is None:
            raise self.error("a generate statement needs a label", t)
        decls = []
        if not self.accept_kw("begin") and self.at_kw("terminal", "quantity", "constant", "signal", "subtype",
                                                       "nature", "component", "function", "alias", "attribute",
                                                       "limit"):
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
        return ir.Generate(label, cond, var, low, high, downto, decls, stmts, t.loc)

    def break_statement(self) -> ir.Break:
        """`break [q => e, ...] [on s, ...] [when c];` (concurrent or sequential)."""
        t = self.tok
        self.expect_kw("break")
        on: list[ir.Expr] = []
        sets: list[tuple[str, ir.Expr]] = []
        if self.at_kw("for"):
            raise self.unsupported("break for ... use (a break list with a selector quantity)")
        while self.tok.kind == "id" and self.peek().is_("op", "=>"):     # q => value, ...
            name = self.ident()
            self.advance()
            sets.append((name, self.expression()))
            if not self.accept_op(","):
                break
        if self.accept_kw("on"):
            on = self.names()
        when = self.expression() if self.accept_kw("when") else None
        self.expect_op(";")
        return ir.Break(on, t.loc, sets, when)

    def names(self) -> list[ir.Expr]:
        """`name, name, ...` (a sensitivity list)."""
        out = [self.name_expr()]
        while self.accept_op(","):
            out.append(self.name_expr())
        return out

    def body_of(self, kind: str) -> tuple[list, list]:
        """`[is] declarations begin statements end [postponed] <kind> [label];` of a process or procedural."""
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

    def process(self, label: str | None, t: Token) -> ir.Process:
        """After `process`: `[(s, ...)] [is] declarations begin statements end [postponed] process [label];`."""
        sensitivity: list[ir.Expr] = []
        if self.accept_op("("):
            if self.at_kw("all"):
                raise self.unsupported("process (all)")
            sensitivity = self.names()
            self.expect_op(")")
        decls, body = self.body_of("process")
        return ir.Process(label, sensitivity, decls, body, t.loc)

    # ------------------------------------------------------------------ concurrent statements
    def concurrent_statement(self) -> ir.ConcurrentStmt:
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
        if label and self.tok.kind == "id" and (self.peek().is_("kw", "generic") or self.peek().is_("kw", "port")
                                                or self.peek().is_("op", ";")):
            return self.instance(label, "component", t)
        if self.accept_kw("if"):
            cond = self.expression()
            if self.accept_kw("generate"):
                return self.generate(label, t, cond, None, None, None, False)
            self.expect_kw("use")
            arms: list[tuple[ir.Expr | None, list[ir.ConcurrentStmt]]] = [
                (cond, self.simultaneous_part(("elsif", "else", "end")))]
            while self.accept_kw("elsif"):
                cond = self.expression()
                self.expect_kw("use")
                arms.append((cond, self.simultaneous_part(("elsif", "else", "end"))))
            if self.accept_kw("else"):
                arms.append((None, self.simultaneous_part(("end",))))
            self.end_of("use", name=label)
            return ir.SimultaneousIf(arms, label, t.loc)
        if self.accept_kw("case"):
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
            return ir.SimultaneousCase(selector, alts, label, t.loc)
        if self.accept_kw("for"):
            var = self.ident("generate parameter")
            self.expect_kw("in")
            low = self.simple_expression()
            downto = self.accept_kw("downto")
            if not downto:
                self.expect_kw("to")
            high = self.simple_expression()
            self.expect_kw("generate")
            return self.generate(label, t, None, var, low, high, downto)
        if self.accept_kw("procedural"):
            return ir.Procedural(*self.body_of("procedural"), t.loc)
        if self.accept_kw("assert"):
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
            return ir.Assertion(cond, report, severity, t.loc)
        if self.at_kw("break"):
            return self.break_statement()
        if self.accept_kw("process"):
            return self.process(label, t)
        if self.accept_kw("null"):
            self.expect_op(";")
            return ir.SimultaneousNull(t.loc)
        lhs = self.simple_expression()
        if self.at_op("<="):
            return self.signal_assignment(lhs, t)
        if not self.accept_op("=="):
            raise self.error(f"expected '==' in simultaneous statement, found {self.describe(self.tok)}")
        rhs = self.simple_expression()
        self.tolerance_aspect()
        self.expect_op(";")
        return ir.SimpleSimultaneous(lhs, rhs, label, t.loc)

    def signal_assignment(self, lhs: ir.Expr, t: Token) -> ir.SignalAssign:
        """`s <= '1' when cond else '0';` or `s(k) <= ...` — the one A->D form of an AMS architecture."""
        self.expect_op("<=")
        if isinstance(lhs, ir.Name):
            target, index = lhs.ident, None
        elif isinstance(lhs, ir.Call) and len(lhs.args) == 1 and isinstance(lhs.args[0].actual, ir.Num):
            target, index = lhs.name, int(lhs.args[0].actual.value)
        else:
            raise self.unsupported("signal assignment target other than a name or name(k)", t)
        form = ("concurrent signal assignment other than s <= '1' when <condition> else '0' (digital logic belongs in "
                "a digital file run by GHDL)")
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
        return ir.SignalAssign(target, index, cond, t.loc)

    def simultaneous_part(self, stop: tuple[str, ...]) -> list[ir.ConcurrentStmt]:
        with self.block():
            out: list[ir.ConcurrentStmt] = []
            while not self.at_kw(*stop):
                s = self.concurrent_statement()
                if isinstance(s, (ir.Instance, ir.Assertion, ir.Break)):
                    raise SourceError(s.loc, "only simultaneous statements are allowed inside if-use/case-use")
                out.append(s)
        return out

    def instance(self, label: str | None, kind: str, t: Token) -> ir.Instance:
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
        return ir.Instance(label, kind, name, arch, gmap, pmap, t.loc)
