"""The expression grammar of the subset: logical, relational, adding, multiplying and miscellaneous operators,
primaries (literals, physical literals of type time, aggregates, parenthesized expressions), names, calls,
attributes and association lists. Each parse method's docstring starts with the rule it reads, in the notation of
IEEE 1076 (`::=`, `[ ]` optional, `{ }` repeated, `|` alternatives; reserved words in lower case)."""

from __future__ import annotations

import re

from wrsim.errors import SourceError
from wrsim.frontend import ast
from wrsim.frontend.cursor import TokenCursor
from wrsim.frontend.lexer import Token

__all__ = ["ExpressionParser", "depth", "MAX_NESTING", "MAX_DEPTH", "TIME_UNITS"]

MAX_NESTING = 64  # parentheses, calls and attribute arguments inside one another
MAX_DEPTH = 256  # operators on the longest path of an expression tree (a flat sum of N terms: N - 1)

_RELOPS = ("=", "/=", "<", "<=", ">", ">=")
_LOGIC = ("and", "or", "xor", "nand", "nor", "xnor")


TIME_UNITS = {"fs": 1e-15, "ps": 1e-12, "ns": 1e-9, "us": 1e-6, "ms": 1e-3, "sec": 1.0, "min": 60.0, "hr": 3600.0}


class ExpressionParser(TokenCursor):
    """The expression grammar, on the token cursor."""

    # ------------------------------------------------------------------ expressions
    def expression(self) -> ast.Expr:
        """expression ::= relation { logical_operator relation }

        One more than MAX_NESTING levels of parentheses or calls, or an operator tree deeper than
        MAX_DEPTH, is a SourceError (recursion and the evaluation of the tree stay bounded)."""
        self.nesting += 1
        try:
            if self.nesting > MAX_NESTING:
                raise self.error(f"expression nested more than {MAX_NESTING} levels deep")
            e = self.logical()
        finally:
            self.nesting -= 1
        return self.bounded(e)

    def bounded(self, e: ast.Expr) -> ast.Expr:
        """`e`, if its operator tree is at most MAX_DEPTH deep (checked once, on the outermost expression)."""
        if self.nesting == 0 and depth(e) > MAX_DEPTH:
            raise SourceError(
                e.loc,
                f"expression more than {MAX_DEPTH} operations deep: split it with intermediate quantities or constants",
            )
        return e

    def logical(self) -> ast.Expr:
        """logical_expression ::= relation { and relation } | relation { or relation } | ... (one operator, or
        parentheses)"""
        left = self.relation()
        op = None
        while self.at_kw(*_LOGIC):
            t = self.advance()
            if op is not None and t.text != op:
                raise self.error("mixing logical operators needs parentheses", t)
            op = t.text
            left = ast.Binary(t.text, left, self.relation(), t.loc)
        return left

    def relation(self) -> ast.Expr:
        """relation ::= simple_expression [ relational_operator simple_expression ]"""
        left = self.simple_expression()
        if self.at_op(*_RELOPS):
            t = self.advance()
            left = ast.Binary(t.text, left, self.simple_expression(), t.loc)
        return left

    def simple_expression(self) -> ast.Expr:
        """simple_expression ::= [ sign ] term { adding_operator term }"""
        t = self.tok
        if self.at_op("-", "+"):
            self.advance()
            left: ast.Expr = ast.Unary(t.text, self.term(), t.loc)
        else:
            left = self.term()
        while self.at_op("+", "-", "&"):
            op = self.advance()
            left = ast.Binary(op.text, left, self.term(), op.loc)
        return self.bounded(left)

    def term(self) -> ast.Expr:
        """term ::= factor { multiplying_operator factor }"""
        left = self.factor()
        while self.at_op("*", "/") or self.at_kw("mod", "rem"):
            op = self.advance()
            left = ast.Binary(op.text, left, self.factor(), op.loc)
        return left

    def factor(self) -> ast.Expr:
        """factor ::= primary [ ** primary ] | abs primary | not primary"""
        t = self.tok
        if self.accept_kw("abs"):
            return ast.Unary("abs", self.primary(), t.loc)
        if self.accept_kw("not"):
            return ast.Unary("not", self.primary(), t.loc)
        left = self.primary()
        if self.at_op("**"):
            op = self.advance()
            return ast.Binary("**", left, self.primary(), op.loc)
        return left

    def primary(self) -> ast.Expr:
        """primary ::= numeric_literal [ time_unit ] | string_literal | character_literal | name | aggregate
        | ( expression )"""
        t = self.tok
        if t.kind == "num":
            self.advance()
            if self.tok.kind == "id" and self.tok.text in TIME_UNITS:  # a physical literal of type time
                unit = self.advance()
                return ast.Num(float(t.text) * TIME_UNITS[unit.text], False, t.loc, time=True)
            return ast.Num(float(t.text), "." not in t.text, t.loc)
        if t.kind == "str":
            self.advance()
            return ast.Str(t.text, t.loc)
        if t.kind == "char":
            self.advance()
            return ast.Char(t.text, t.loc)
        if self.at_op("-", "+"):
            raise self.error("a sign inside an expression must be parenthesized, e.g. a * (-b)")
        if self.accept_op("("):
            if self.tok.kind == "num" and self.peek().is_("op", "=>"):
                return self.named_aggregate(t)
            if self.at_kw("others"):
                raise self.unsupported("aggregate choice 'others'")
            first = self.expression()
            if self.at_op("=>"):
                raise self.unsupported("named aggregate with a choice other than an integer literal")
            if self.accept_op(","):
                items = [first, self.expression()]
                while self.accept_op(","):
                    items.append(self.expression())
                self.expect_op(")")
                return ast.Aggregate(items, t.loc)
            self.expect_op(")")
            return first
        if t.kind == "id":
            return self.name_expr()
        if t.is_("kw", "null"):
            raise self.unsupported("null literal")
        raise self.error(f"expected an expression, found {self.describe(t)}")

    def named_aggregate(self, t: Token) -> ast.Expr:
        """aggregate ::= ( integer_literal => expression { , integer_literal => expression } )

        `(0 => a, 1 => b)`: integer-literal choices covering 0 .. n-1 once each, in any order (a one-element
        aggregate can only be written so)."""
        items: dict[int, ast.Expr] = {}
        while True:
            choice = self.tok
            if choice.kind != "num" or not re.fullmatch(r"\d+", choice.text):
                raise self.unsupported("named aggregate with a choice other than an integer literal", choice)
            self.advance()
            self.expect_op("=>")
            if int(choice.text) in items:
                raise self.error(f"choice {choice.text} appears twice in the aggregate", choice)
            items[int(choice.text)] = self.expression()
            if not self.accept_op(","):
                break
        self.expect_op(")")
        if sorted(items) != list(range(len(items))):
            raise self.error(f"the aggregate's choices {sorted(items)} are not 0 .. {len(items) - 1}", t)
        return ast.Aggregate([items[k] for k in range(len(items))], t.loc)

    def name_expr(self) -> ast.Expr:
        """name ::= identifier { . identifier } [ ( association_list ) ] [ ' attribute_designator { '
        attribute_designator } [ ( expression { , expression } ) ] ]"""
        t = self.tok
        name = self.ident()
        while self.at_op(".") and self.peek().kind in ("id", "kw"):
            self.advance()
            name += "." + (self.advance().text)
        index = None
        if self.at_op("("):
            call = ast.Call(name, self.association_list(), t.loc)
            if not (self.at_op("'") and len(call.args) == 1 and call.args[0].formal is None):
                return call
            index = call.args[0].actual  # q(k)'dot: an attribute of an array element
        if self.at_op("'"):
            tick = self.advance()
            if self.tok.kind not in ("id", "kw"):
                raise self.error("expected an attribute name after the tick", tick)
            attr = self.advance().text
            while self.at_op("'") and self.peek().kind in ("id", "kw"):  # q'dot'dot: an attribute of an attribute
                self.advance()
                attr += "'" + self.advance().text
            args = []
            if self.accept_op("("):
                args.append(self.expression())
                while self.accept_op(","):
                    args.append(self.expression())
                self.expect_op(")")
            return ast.Attr(name, attr, args, tick.loc, index)
        return ast.Name(name, t.loc)

    def association_list(self) -> list[ast.Assoc]:
        """( association_list ) ::= ( [ formal => ] ( expression | open ) { , [ formal => ] ( expression | open ) } )"""
        self.expect_op("(")
        out = []
        while True:
            t = self.tok
            formal = None
            if self.tok.kind == "id" and self.peek().is_("op", "=>"):
                formal = self.advance().text
                self.advance()
            if self.accept_kw("open"):
                out.append(ast.Assoc(formal, None, t.loc))
            else:
                out.append(ast.Assoc(formal, self.expression(), t.loc))
            if not self.accept_op(","):
                break
        self.expect_op(")")
        return out


def depth(e: ast.Expr) -> int:
    """Operators on the longest path from the root of `e` to a leaf (computed without recursion)."""
    deepest, stack = 0, [(e, 0)]
    while stack:
        node, d = stack.pop()
        deepest = max(deepest, d)
        if isinstance(node, ast.Binary):
            stack += [(node.left, d + 1), (node.right, d + 1)]
        elif isinstance(node, ast.Unary):
            stack.append((node.operand, d + 1))
        elif isinstance(node, ast.Call):
            stack += [(a.actual, d + 1) for a in node.args if a.actual is not None]
        elif isinstance(node, (ast.Attr, ast.Aggregate)):
            stack += [(x, d + 1) for x in (node.args if isinstance(node, ast.Attr) else node.items)]
    return deepest
