"""Sequential statements of the subset (the bodies of functions, processes and procedurals): return, null, if, case,
for loop, wait, signal and variable assignment (also VHDL-2008's conditional and selected forms), break. A case and
the conditional and selected forms are read as the if statements they are equivalent to. Each parse method's
docstring starts with the rule it reads, in the notation of IEEE 1076 and 1076.1."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from wrsim.frontend import ast
from wrsim.frontend.expressions import ExpressionParser
from wrsim.frontend.lexer import Token

__all__ = ["StatementParser", "MAX_BLOCKS"]

MAX_BLOCKS = 32  # if/case/loop bodies inside one another


class StatementParser(ExpressionParser):
    """Sequential statements, on top of the expression grammar."""

    def sequence(self, stop: tuple[str, ...]) -> list[ast.SeqStmt]:
        """sequence_of_statements ::= { sequential_statement } (up to one of the reserved words `stop`)"""
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

    def sequential_statement(self) -> ast.SeqStmt:
        """sequential_statement ::= return_statement | null_statement | if_statement | loop_statement
        | exit_statement | next_statement | wait_statement | break_statement | signal_assignment_statement
        | variable_assignment_statement; a loop is `for ... loop`, `while condition loop` or `loop`, and
        `exit [when condition] ;` / `next [when condition] ;` leave its innermost one (no loop labels)"""
        t = self.tok
        if self.accept_kw("return"):
            value = self.expression()
            self.expect_op(";")
            return ast.Return(value, t.loc)
        if self.accept_kw("null"):
            self.expect_op(";")
            return ast.NullStmt(t.loc)
        if self.accept_kw("if"):
            return self.if_statement(t)
        if self.accept_kw("case"):
            return self.case_statement(t)
        if self.accept_kw("with"):
            return ast.IfStmt(self.selected_arms(t, variable=True), t.loc)
        if self.accept_kw("for"):
            return self.loop_statement(t)
        if self.accept_kw("while"):
            cond = self.expression()
            self.expect_kw("loop")
            return self.loop_body(None, cond, t)
        if self.accept_kw("loop"):
            return self.loop_body(None, None, t)
        if self.at_kw("exit", "next"):
            kind = self.advance().text
            if self.tok.kind == "id":
                raise self.unsupported(f"'{kind}' with a loop label (it leaves the innermost loop)")
            stop: ast.SeqStmt = ast.LoopExit(kind, t.loc)
            if self.accept_kw("when"):
                stop = ast.IfStmt([(self.expression(), [stop])], t.loc)
            self.expect_op(";")
            return stop
        if self.accept_kw("wait"):
            return self.wait_statement(t)
        if self.at_kw("break"):
            return self.break_statement()
        if self.at_kw("report", "assert"):
            raise self.unsupported(f"'{self.tok.text}' statement in a function or process body")
        if self.tok.kind == "id" and self.peek().is_("op", "<="):
            return self.signal_assignment_statement(t)
        if self.tok.kind == "id" and self.peek().is_("op", ":="):
            target = self.advance().text
            self.advance()
            arms: list[tuple[ast.Expr | None, list[ast.SeqStmt]]] = []
            while not arms or (arms[-1][0] is not None and self.accept_kw("else")):
                value = self.expression()
                arms.append(
                    (self.expression() if self.accept_kw("when") else None, [ast.VarAssign(target, value, t.loc)])
                )
            self.expect_op(";")
            return self.conditional(arms, t)
        if self.tok.kind == "id" and self.peek().is_("op", "("):
            raise self.unsupported("assignment to a vector element or procedure call", t)
        raise self.error(f"expected a sequential statement, found {self.describe(t)}")

    def if_statement(self, t: Token) -> ast.IfStmt:
        """After `if`: if_statement ::= if condition then sequence_of_statements { elsif condition then
        sequence_of_statements } [ else sequence_of_statements ] end if ;"""
        branches: list[tuple[ast.Expr | None, list[ast.SeqStmt]]] = []
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
        return ast.IfStmt(branches, t.loc)

    def case_statement(self, t: Token) -> ast.IfStmt:
        """After `case`: case_statement ::= case expression is case_statement_alternative
        { case_statement_alternative } end case ;   case_statement_alternative ::= when choices =>
        sequence_of_statements: the if statement over `selector = choice` it is equivalent to (the choices of a case
        cover every value once, so their order does not matter)."""
        selector = self.expression()
        self.expect_kw("is")
        arms: list[tuple[ast.Expr | None, list[ast.SeqStmt]]] = []
        while self.accept_kw("when"):
            if arms and arms[-1][0] is None:
                raise self.error("'when others' must be the last alternative of a case statement")
            arms.append((self.matches(selector, self.choices(), t), self.sequence(("when", "end"))))
        if not arms:
            raise self.error(f"expected 'when' (an alternative of the case statement), found {self.describe(self.tok)}")
        self.end_of("case")
        return ast.IfStmt(arms, t.loc)

    def choices(self) -> list[ast.Expr] | None:
        """After `when`: choices ::= choice { | choice } | others, and the `=>` (None: others)."""
        choices = self.choice_list()
        self.expect_op("=>")
        return choices

    def choice_list(self) -> list[ast.Expr] | None:
        """choices ::= choice { | choice } | others (None: others); a choice is a simple expression."""
        if self.accept_kw("others"):
            return None
        choices = [self.simple_expression()]
        while self.accept_op("|"):
            choices.append(self.simple_expression())
        if self.at_kw("to", "downto"):
            raise self.unsupported("a range as a choice (write its values with |)")
        return choices

    @staticmethod
    def matches(selector: ast.Expr, choices: list[ast.Expr] | None, t: Token) -> ast.Expr | None:
        """The condition `selector = c1 or selector = c2 ...` of `choices` (None: others)."""
        if choices is None:
            return None
        cond: ast.Expr = ast.Binary("=", selector, choices[0], t.loc)
        for choice in choices[1:]:
            cond = ast.Binary("or", cond, ast.Binary("=", selector, choice, t.loc), t.loc)
        return cond

    def selected_arms(self, t: Token, variable: bool = False) -> list[tuple[ast.Expr | None, list[ast.SeqStmt]]]:
        """After `with`: selected_signal_assignment ::= with expression select target <= [ delay_mechanism ]
        waveform when choices { , waveform when choices } ;  (VHDL-2008, `variable`: also selected_variable_assignment
        ::= with expression select target := expression when choices { , ... } ;) as (condition, statements)."""
        selector = self.expression()
        self.expect_kw("select")
        target = self.ident("signal or variable name")
        assign = variable and self.accept_op(":=")
        if not assign:
            self.expect_op("<=")
        mechanism = None if assign else self.delay_mechanism()
        arms: list[tuple[ast.Expr | None, list[ast.SeqStmt]]] = []
        while True:
            stmt: ast.SeqStmt | None
            if mechanism is None:
                stmt = ast.VarAssign(target, self.expression(), t.loc)
            else:
                stmt = self.waveform(target, mechanism, t)
            self.expect_kw("when")
            cond = self.matches(selector, self.choice_list(), t)
            arms.append((cond, [stmt] if stmt else []))
            if cond is None or not self.accept_op(","):
                break
        self.expect_op(";")
        return arms

    @staticmethod
    def conditional(arms: list[tuple[ast.Expr | None, list[ast.SeqStmt]]], t: Token) -> ast.SeqStmt:
        """The statement of conditional arms: the only arm's statement, else the if statement over them."""
        if len(arms) == 1 and arms[0][0] is None:
            return arms[0][1][0] if arms[0][1] else ast.NullStmt(t.loc)
        return ast.IfStmt(arms, t.loc)

    def loop_statement(self, t: Token) -> ast.ForLoop | ast.WhileLoop:
        """After `for`: loop_statement ::= for identifier in ( simple_expression ( to | downto ) simple_expression
        | name'range | name'reverse_range ) loop sequence_of_statements end loop ;"""
        var = self.ident("loop variable")
        self.expect_kw("in")
        low = high = rattr = None
        downto = False
        first = self.simple_expression()
        if isinstance(first, ast.Attr) and first.attr in ("range", "reverse_range") and not self.at_kw("to", "downto"):
            rattr = first
        else:
            low = first
            if self.accept_kw("downto"):
                downto = True
            else:
                self.expect_kw("to")
            high = self.simple_expression()
        self.expect_kw("loop")
        return self.loop_body(ast.ForLoop(var, low, high, downto, rattr, [], t.loc), None, t)

    def loop_body(self, loop: ast.ForLoop | None, cond: ast.Expr | None, t: Token) -> ast.ForLoop | ast.WhileLoop:
        """After `loop`: sequence_of_statements end loop ; -- the for loop `loop` gets the body, else a while
        loop (`cond` None: a plain loop)."""
        body = self.sequence(("end",))
        self.end_of("loop")
        if loop is not None:
            loop.body = body
            return loop
        return ast.WhileLoop(cond, body, t.loc)

    def wait_statement(self, t: Token) -> ast.Wait:
        """After `wait`: wait_statement ::= wait [ on sensitivity_list ] [ until condition ]
        [ for time_expression ] ;"""
        on = self.names() if self.accept_kw("on") else []
        until = self.expression() if self.accept_kw("until") else None
        timeout = self.expression() if self.accept_kw("for") else None
        self.expect_op(";")
        return ast.Wait(on, until, timeout, t.loc)

    def signal_assignment_statement(self, t: Token) -> ast.SeqStmt:
        """signal_assignment_statement ::= target <= [ delay_mechanism ] waveform { when condition else waveform }
        [ when condition ] ;  (the conditional form is VHDL-2008's)"""
        target = self.advance().text
        self.advance()
        mechanism = self.delay_mechanism()
        arms: list[tuple[ast.Expr | None, list[ast.SeqStmt]]] = []
        while not arms or (arms[-1][0] is not None and self.accept_kw("else")):
            stmt = self.waveform(target, mechanism, t)
            arms.append((self.expression() if self.accept_kw("when") else None, [stmt] if stmt else []))
        self.expect_op(";")
        return self.conditional(arms, t)

    def delay_mechanism(self) -> tuple[bool, ast.Expr | None]:
        """delay_mechanism ::= transport | [ reject time_expression ] inertial: whether it is transport, and the
        pulse rejection limit of `reject` (None: the delay's, inertial's default)."""
        if self.accept_kw("transport"):
            return True, None
        reject = self.expression() if self.accept_kw("reject") else None
        if reject is not None:
            self.expect_kw("inertial")
        else:
            self.accept_kw("inertial")
        return False, reject

    def waveform(self, target: str, mechanism: tuple[bool, ast.Expr | None], t: Token) -> ast.SeqSignalAssign | None:
        """waveform ::= waveform_element { , waveform_element } | unaffected;   waveform_element ::= expression
        [ after time_expression ]: the assignment it makes (None: none)."""
        if self.accept_kw("unaffected"):
            return None
        elements: list[tuple[ast.Expr, ast.Expr | None]] = []
        while not elements or self.accept_op(","):
            elements.append((self.expression(), self.expression() if self.accept_kw("after") else None))
        (value, after), *more = elements
        return ast.SeqSignalAssign(target, value, t.loc, after, *mechanism, more)

    def break_statement(self) -> ast.Break:
        """break_statement ::= break [ break_element { , break_element } ] [ on sensitivity_list ] [ when condition ] ;
        break_element ::= quantity_name => expression (concurrent or sequential); the quantity name may be q'dot"""
        t = self.tok
        self.expect_kw("break")
        on: list[ast.Expr] = []
        sets: list[tuple[str, ast.Expr]] = []
        if self.at_kw("for"):
            raise self.unsupported("break for ... use (a break list with a selector quantity)")
        while self.tok.kind == "id" and (
            self.peek().is_("op", "=>") or (self.peek().is_("op", "'") and self.peek(2).is_("id", "dot"))
        ):  # q => value, q'dot => value, ...
            name = self.ident()
            if self.accept_op("'"):
                self.advance()
                name += "'dot"
            self.expect_op("=>")
            sets.append((name, self.expression()))
            if not self.accept_op(","):
                break
        if self.accept_kw("on"):
            on = self.names()
        when = self.expression() if self.accept_kw("when") else None
        self.expect_op(";")
        return ast.Break(on, t.loc, sets, when)

    def names(self) -> list[ast.Expr]:
        """sensitivity_list ::= name { , name }"""
        out = [self.name_expr()]
        while self.accept_op(","):
            out.append(self.name_expr())
        return out
