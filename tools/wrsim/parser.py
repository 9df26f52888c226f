"""Recursive-descent parser for the VHDL-AMS subset of docs/vhdl-ams-subset.md: tokens -> ir.DesignFile.

Constructs outside the subset are recognised far enough to be named: `unsupported construct: ...` with
file:line:col. A hand-written parser was chosen over a grammar library because VHDL's ambiguities (calls vs
indexing, attribute ticks vs character literals, labels) need token look-ahead that is easier to keep
precise by hand, and because every message must point at the offending token."""
from __future__ import annotations

import re
from pathlib import Path

from . import ir
from .errors import SourceError, WrsimError
from .lexer import Lexed, Token, tokenize

__all__ = ["parse_text", "parse_file"]

_UNIT = re.compile(r"^\[([^\]]*)\]\s*(.*)$")
_RELOPS = ("=", "/=", "<", "<=", ">", ">=")
_LOGIC = ("and", "or", "xor", "nand", "nor", "xnor")
_UNSUPPORTED_STMTS = {
    "process": "process statement (digital VHDL runs in GHDL, not in the analog lowering)",
    "block": "block statement",
    "procedural": "procedural statement",
    "with": "selected signal assignment",
    "postponed": "postponed process",
}


def parse_file(path: str | Path, library: str = "work") -> ir.DesignFile:
    """Parse one .vhd file into design units of `library`."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise WrsimError(f"{p}: cannot read VHDL-AMS source: {e}") from None
    return parse_text(text, str(path), library)


def parse_text(text: str, path: str = "<string>", library: str = "work") -> ir.DesignFile:
    """Parse VHDL-AMS source text."""
    return _Parser(tokenize(text, path), path, library).design_file()


class _Parser:
    def __init__(self, lexed: Lexed, path: str, library: str):
        self.toks = lexed.tokens
        self.comments = lexed.comments
        self.lines = lexed.lines
        self.path = path
        self.library = library
        self.i = 0

    # ------------------------------------------------------------------ token helpers
    @property
    def tok(self) -> Token:
        return self.toks[self.i]

    def peek(self, k: int = 1) -> Token:
        return self.toks[min(self.i + k, len(self.toks) - 1)]

    def advance(self) -> Token:
        t = self.toks[self.i]
        self.i += 1
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
        out = []
        k = line - 1
        while k >= 1 and self.lines[k - 1].lstrip().startswith("--"):
            out.append(self.comments.get(k, ""))
            k -= 1
        return "\n".join(reversed(out))

    # ------------------------------------------------------------------ design file
    def design_file(self) -> ir.DesignFile:
        self.is_digital_file = self.is_digital()
        df = ir.DesignFile(self.path, self.library, digital=self.is_digital_file)
        uses: list[ir.UseClause] = []
        while not self.at("eof"):
            if self.accept_kw("library"):
                self.ident_list()
                self.expect_op(";")
            elif self.at_kw("use"):
                uses.extend(self.use_clause())
            elif self.at_kw("context"):
                raise self.unsupported("context declaration/reference")
            else:
                df.units.append(self.design_unit(uses))
                uses = []
        return df

    def use_clause(self) -> list[ir.UseClause]:
        out = []
        self.expect_kw("use")
        while True:
            t = self.tok
            parts = [self.ident("library name"), ]
            self.expect_op(".")
            parts.append(self.ident("package name"))
            if self.accept_op("."):
                parts.append("all" if self.accept_kw("all") else self.ident())
            else:
                parts.append("all")
            out.append(ir.UseClause(parts[0], parts[1], parts[2], t.loc))
            if not self.accept_op(","):
                break
        self.expect_op(";")
        return out

    def is_digital(self) -> bool:
        """Plain VHDL for GHDL: a file with a process, wait or type declaration and no AMS construct
        (terminal, quantity, nature, '=='). A structural bench of instances only stays an AMS file."""
        ams = {"terminal", "quantity", "nature", "subnature", "procedural"}
        digital = False
        for t in self.toks:
            if (t.kind == "kw" and t.text in ams) or t.is_("op", "=="):
                return False
            digital = digital or (t.kind == "kw" and t.text in ("process", "wait", "type"))
        return digital

    def skip_unit(self, kinds: tuple[str, ...], name: str) -> None:
        """Skip a digital unit's body up to `end <kinds...> [name];` or `end <name>;`."""
        while not self.at("eof"):
            if self.at_kw("end"):
                k = 1
                if all(self.peek(k + j).is_("kw", w) for j, w in enumerate(kinds)):
                    k += len(kinds)
                    if self.peek(k).is_("id", name):
                        k += 1
                    if self.peek(k).is_("op", ";"):
                        self.i += k + 1
                        return
                elif self.peek(1).is_("id", name) and self.peek(2).is_("op", ";"):
                    self.i += 3
                    return
            self.advance()
        raise self.error(f"missing 'end {' '.join(kinds)} {name};'")

    def design_unit(self, uses: list[ir.UseClause]) -> ir.DesignUnit:
        t = self.tok
        digital = self.is_digital_file
        if digital and self.at_kw("architecture", "package"):
            self.advance()
            if self.accept_kw("body"):
                name = self.ident()
                self.skip_unit(("package", "body"), name)
                return ir.PackageBody(name, [], uses, t.loc)
            name = self.ident()
            if t.text == "package":
                self.skip_unit(("package",), name)
                return ir.Package(name, [], uses, t.loc)
            self.expect_kw("of")
            entity = self.ident("entity name")
            self.skip_unit(("architecture",), name)
            return ir.DigitalArchitecture(name, entity, self.path, t.loc)
        if self.accept_kw("entity"):
            return self.entity(t, uses)
        if self.accept_kw("architecture"):
            return self.architecture(t, uses)
        if self.accept_kw("package"):
            if self.accept_kw("body"):
                name = self.ident()
                self.expect_kw("is")
                decls = self.declarations(("end",))
                self.end_of("package", "body", name=name)
                return ir.PackageBody(name, decls, uses, t.loc)
            name = self.ident()
            self.expect_kw("is")
            decls = self.declarations(("end",))
            self.end_of("package", name=name)
            return ir.Package(name, decls, uses, t.loc)
        if self.at_kw("configuration"):
            raise self.unsupported("configuration declaration")
        raise self.error(f"expected a design unit (entity, architecture, package), found {self.describe(t)}")

    def entity(self, t: Token, uses: list[ir.UseClause]) -> ir.Entity:
        name = self.ident("entity name")
        self.expect_kw("is")
        generics = self.generic_clause() if self.at_kw("generic") else []
        ports = self.port_clause() if self.at_kw("port") else []
        stmts: list[ir.Assertion] = []
        if self.is_digital_file and self.at_kw("begin"):
            self.skip_unit(("entity",), name)
            return ir.Entity(name, generics, ports, stmts, uses, self.header_before(t.loc.line), t.loc)
        if self.accept_kw("begin"):
            while not self.at_kw("end"):
                s = self.concurrent_statement()
                if not isinstance(s, ir.Assertion):
                    raise self.error("only assertions are allowed in an entity's statement part", t)
                stmts.append(s)
        self.end_of("entity", name=name)
        return ir.Entity(name, generics, ports, stmts, uses, self.header_before(t.loc.line), t.loc)

    def architecture(self, t: Token, uses: list[ir.UseClause]) -> ir.Architecture:
        name = self.ident("architecture name")
        self.expect_kw("of")
        entity = self.ident("entity name")
        self.expect_kw("is")
        decls = self.declarations(("begin",))
        self.expect_kw("begin")
        stmts = []
        while not self.at_kw("end"):
            stmts.append(self.concurrent_statement())
        self.end_of("architecture", name=name)
        return ir.Architecture(name, entity, decls, stmts, uses, t.loc)

    # ------------------------------------------------------------------ interface lists
    def generic_clause(self) -> list[ir.Generic]:
        self.expect_kw("generic")
        self.expect_op("(")
        out: list[ir.Generic] = []
        while True:
            t = self.tok
            self.accept_kw("constant")
            names = self.ident_list()
            self.expect_op(":")
            self.accept_kw("in")
            type_mark = self.type_mark()
            default = self.expression() if self.accept_op(":=") else None
            unit, comment = self.unit_comment(self.tok.loc.line if self.at_op(";") else t.loc.line, t.loc.line)
            for n in names:
                out.append(ir.Generic(n, type_mark, default, unit, comment, t.loc))
            if not self.accept_op(";"):
                break
        self.expect_op(")")
        self.expect_op(";")
        return out

    def port_clause(self) -> list[ir.Port]:
        self.expect_kw("port")
        self.expect_op("(")
        out: list[ir.Port] = []
        while True:
            t = self.tok
            if self.accept_kw("terminal"):
                names = self.ident_list()
                self.expect_op(":")
                nature = self.type_mark()
                out.extend(ir.TerminalPort(n, nature, t.loc) for n in names)
            elif self.accept_kw("quantity"):
                names = self.ident_list()
                self.expect_op(":")
                mode = self.port_mode("quantity")
                type_mark = self.type_mark()
                if self.at_op(":="):
                    raise self.unsupported("default value on a quantity port")
                unit, _ = self.unit_comment(t.loc.line)
                out.extend(ir.QuantityPort(n, mode, type_mark, unit, t.loc) for n in names)
            elif self.at_kw("signal") or self.tok.kind == "id":
                self.accept_kw("signal")
                names = self.ident_list()
                self.expect_op(":")
                mode = self.port_mode("signal")
                type_mark, width = self.signal_type()
                if self.at_op(":=") and self.is_digital_file:
                    self.advance()
                    self.expression()      # GHDL's business
                elif self.at_op(":="):
                    raise self.unsupported("default value on a signal port of an AMS model")
                out.extend(ir.SignalPort(n, mode, type_mark, width, t.loc) for n in names)
            else:
                raise self.error(f"expected 'terminal' or 'quantity' port, found {self.describe(self.tok)}")
            if not self.accept_op(";"):
                break
        self.expect_op(")")
        self.expect_op(";")
        return out

    def port_mode(self, kind: str) -> str:
        for mode in ("in", "out"):
            if self.accept_kw(mode):
                return mode
        if self.at_kw("inout", "buffer", "linkage"):
            raise self.unsupported(f"{kind} port mode '{self.tok.text}' (use in or out)")
        raise self.error(f"a {kind} port needs mode 'in' or 'out'")

    def signal_type(self) -> tuple[str, int | None]:
        """std_logic | std_logic_vector(N-1 downto 0) | integer | natural | boolean -> (type, width)."""
        t = self.tok
        name = self.type_mark() if not self.at("id", "std_logic_vector") else self.advance().text
        if name == "std_logic_vector":
            self.expect_op("(")
            hi = self.advance()
            self.expect_kw("downto")
            lo = self.advance()
            self.expect_op(")")
            if hi.kind != "num" or lo.kind != "num" or lo.text != "0":
                raise self.unsupported("std_logic_vector range other than (N-1 downto 0) with a literal N", t)
            return name, int(hi.text) + 1
        if name in ("integer", "natural"):
            return name, 32
        if name in ("std_logic", "boolean", "bit"):
            return name, None
        raise self.unsupported(f"signal type '{name}' (std_logic, std_logic_vector, integer, natural, boolean)", t)

    def type_mark(self) -> str:
        name = self.ident("type or nature name")
        while self.accept_op("."):
            name = self.ident("type or nature name")
        if self.at_op("(") or self.at_kw("range"):
            raise self.unsupported("constrained subtype indication")
        return name

    # ------------------------------------------------------------------ declarations
    def declarations(self, stop: tuple[str, ...]) -> list:
        out: list = []
        while not self.at_kw(*stop):
            out.extend(self.declaration())
        return out

    def declaration(self) -> list:
        t = self.tok
        if self.accept_kw("constant"):
            names = self.ident_list()
            self.expect_op(":")
            type_mark = self.type_mark()
            value = self.expression() if self.accept_op(":=") else None
            self.expect_op(";")
            return [ir.ConstantDecl(n, type_mark, value, t.loc) for n in names]
        if self.accept_kw("subtype"):
            name = self.ident()
            self.expect_kw("is")
            base = self.type_mark()
            tol = None
            if self.accept_kw("tolerance"):
                if not self.at("str"):
                    raise self.error("expected a tolerance string")
                tol = self.advance().text
            self.expect_op(";")
            unit, _ = self.unit_comment(t.loc.line)
            return [ir.SubtypeDecl(name, base, tol, unit, t.loc)]
        if self.accept_kw("nature"):
            name = self.ident()
            self.expect_kw("is")
            if self.at_kw("array", "record"):
                raise self.unsupported(f"{self.tok.text} nature")
            across = self.type_mark()
            self.expect_kw("across")
            through = self.type_mark()
            self.expect_kw("through")
            ref = self.ident("reference terminal name")
            self.expect_kw("reference")
            self.expect_op(";")
            return [ir.NatureDecl(name, across, through, ref, t.loc)]
        if self.accept_kw("subnature"):
            name = self.ident()
            self.expect_kw("is")
            base = self.type_mark()
            self.expect_op(";")
            return [ir.SubnatureDecl(name, base, t.loc)]
        if self.accept_kw("terminal"):
            names = self.ident_list()
            self.expect_op(":")
            nature = self.type_mark()
            self.expect_op(";")
            return [ir.TerminalDecl(n, nature, t.loc) for n in names]
        if self.accept_kw("quantity"):
            return self.quantity_declaration(t)
        if self.at_kw("function", "pure", "impure"):
            return [self.function()]
        if self.accept_kw("component"):
            name = self.ident()
            self.accept_kw("is")
            generics = self.generic_clause() if self.at_kw("generic") else []
            ports = self.port_clause() if self.at_kw("port") else []
            self.end_of("component", name=name)
            return [ir.ComponentDecl(name, generics, ports, t.loc)]
        if self.accept_kw("signal"):
            names = self.ident_list()
            self.expect_op(":")
            type_mark, width = self.signal_type()
            if self.accept_op(":="):
                self.expression()          # an initial value only matters to GHDL
            self.expect_op(";")
            return [ir.SignalDecl(n, type_mark, width, t.loc) for n in names]
        if self.at_kw("type", "alias", "attribute", "procedure", "shared", "file", "variable", "group",
                     "disconnect", "limit"):
            raise self.unsupported(f"{self.tok.text} declaration")
        raise self.error(f"expected a declaration, found {self.describe(t)}")

    def quantity_declaration(self, t: Token) -> list:
        names = self.ident_list()
        if self.at_kw("tolerance"):
            raise self.unsupported("tolerance aspect on a quantity")
        if self.accept_op(":"):
            type_mark = self.type_mark()
            if self.at_kw("tolerance", "spectrum", "noise"):
                raise self.unsupported(f"{self.tok.text} {'aspect' if self.tok.text == 'tolerance' else 'source quantity'}")
            init = self.expression() if self.accept_op(":=") else None
            self.expect_op(";")
            unit, _ = self.unit_comment(t.loc.line)
            return [ir.FreeQuantityDecl(n, type_mark, init, unit, t.loc) for n in names]
        across = through = None
        if self.accept_kw("across"):
            across = names
            if self.tok.kind == "id" and self.peek().is_("kw", "through"):
                through = self.ident_list()
                self.expect_kw("through")
        elif self.accept_kw("through"):
            through = names
        else:
            raise self.error(f"expected ':', 'across' or 'through' in quantity declaration, found "
                             f"{self.describe(self.tok)}")
        if (across and len(across) > 1) or (through and len(through) > 1):
            raise self.unsupported("several across or through quantities in one branch declaration", t)
        if self.at_kw("tolerance"):
            raise self.unsupported("tolerance aspect on a branch quantity")
        plus = self.ident("terminal name")
        minus = self.ident("terminal name") if self.accept_kw("to") else None
        self.expect_op(";")
        unit, _ = self.unit_comment(t.loc.line)
        return [ir.BranchQuantityDecl(across[0] if across else None, through[0] if through else None,
                                      plus, minus, None, None, t.loc)]

    def function(self) -> ir.FunctionDecl:
        t = self.tok
        if self.accept_kw("impure"):
            raise self.unsupported("impure function", t)
        self.accept_kw("pure")
        self.expect_kw("function")
        name = self.ident("function name")
        params: list[ir.Param] = []
        if self.accept_op("("):
            while True:
                pt = self.tok
                if self.at_kw("signal", "variable", "file", "quantity", "terminal"):
                    raise self.unsupported(f"{self.tok.text} function parameter")
                self.accept_kw("constant")
                names = self.ident_list()
                self.expect_op(":")
                self.accept_kw("in")
                type_mark = self.type_mark()
                if self.at_op(":="):
                    raise self.unsupported("default value on a function parameter")
                params.extend(ir.Param(n, type_mark, pt.loc) for n in names)
                if not self.accept_op(";"):
                    break
            self.expect_op(")")
        self.expect_kw("return")
        ret = self.type_mark()
        if self.accept_op(";"):
            return ir.FunctionDecl(name, params, ret, None, None, t.loc)
        self.expect_kw("is")
        decls: list = []
        while not self.at_kw("begin"):
            dt = self.tok
            if self.accept_kw("variable"):
                names = self.ident_list()
                self.expect_op(":")
                type_mark = self.type_mark()
                value = self.expression() if self.accept_op(":=") else None
                self.expect_op(";")
                decls.extend(ir.VariableDecl(n, type_mark, value, dt.loc) for n in names)
            elif self.at_kw("constant"):
                decls.extend(self.declaration())
            else:
                raise self.error(f"expected a variable or constant declaration, found {self.describe(dt)}")
        self.expect_kw("begin")
        body = self.sequence(("end",))
        self.end_of("function", name=name)
        return ir.FunctionDecl(name, params, ret, decls, body, t.loc)

    # ------------------------------------------------------------------ sequential statements
    def sequence(self, stop: tuple[str, ...]) -> list[ir.SeqStmt]:
        out = []
        while not self.at_kw(*stop):
            out.append(self.sequential_statement())
        return out

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
            branches = []
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
        if self.at_kw("while", "case", "loop", "wait", "exit", "next", "report", "assert"):
            raise self.unsupported(f"'{self.tok.text}' statement in a function body")
        if self.tok.kind == "id" and self.peek().is_("op", ":="):
            target = self.advance().text
            self.advance()
            value = self.expression()
            self.expect_op(";")
            return ir.VarAssign(target, value, t.loc)
        if self.tok.kind == "id" and self.peek().is_("op", "("):
            raise self.unsupported("assignment to a vector element or procedure call", t)
        raise self.error(f"expected a sequential statement, found {self.describe(t)}")

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
            if self.at_kw("generate"):
                raise self.unsupported("if-generate statement")
            self.expect_kw("use")
            branches = [(cond, self.simultaneous_part(("elsif", "else", "end")))]
            while self.accept_kw("elsif"):
                cond = self.expression()
                self.expect_kw("use")
                branches.append((cond, self.simultaneous_part(("elsif", "else", "end"))))
            if self.accept_kw("else"):
                branches.append((None, self.simultaneous_part(("end",))))
            self.end_of("use", name=label)
            return ir.SimultaneousIf(branches, label, t.loc)
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
        if self.at_kw("for"):
            raise self.unsupported("for-generate statement")
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
        if self.accept_kw("break"):
            on: list[ir.Expr] = []
            if self.at_kw("for") or self.tok.kind == "id":
                raise self.unsupported("break with a break list (re-initialisation)")
            if self.accept_kw("on"):
                on.append(self.name_expr())
                while self.accept_op(","):
                    on.append(self.name_expr())
            if self.at_kw("when"):
                raise self.unsupported("break ... when")
            self.expect_op(";")
            return ir.Break(on, t.loc)
        if self.accept_kw("null"):
            self.expect_op(";")
            return ir.SimultaneousNull(t.loc)
        lhs = self.simple_expression()
        if self.at_op("<="):
            return self.signal_assignment(lhs, t)
        if not self.accept_op("=="):
            raise self.error(f"expected '==' in simultaneous statement, found {self.describe(self.tok)}")
        rhs = self.simple_expression()
        if self.at_kw("tolerance"):
            raise self.unsupported("tolerance aspect on a simultaneous statement")
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
        form = "concurrent signal assignment other than s <= '1' when <condition> else '0' (digital logic belongs in a digital file run by GHDL)"
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
        out = []
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

    def association_list(self) -> list[ir.Assoc]:
        self.expect_op("(")
        out = []
        while True:
            t = self.tok
            formal = None
            if self.tok.kind == "id" and self.peek().is_("op", "=>"):
                formal = self.advance().text
                self.advance()
            if self.accept_kw("open"):
                out.append(ir.Assoc(formal, None, t.loc))
            else:
                out.append(ir.Assoc(formal, self.expression(), t.loc))
            if not self.accept_op(","):
                break
        self.expect_op(")")
        return out

    # ------------------------------------------------------------------ expressions
    def expression(self) -> ir.Expr:
        left = self.relation()
        op = None
        while self.at_kw(*_LOGIC):
            t = self.advance()
            if op is not None and t.text != op:
                raise self.error("mixing logical operators needs parentheses", t)
            op = t.text
            left = ir.Binary(t.text, left, self.relation(), t.loc)
        return left

    def relation(self) -> ir.Expr:
        left = self.simple_expression()
        if self.at_op(*_RELOPS):
            t = self.advance()
            left = ir.Binary(t.text, left, self.simple_expression(), t.loc)
        return left

    def simple_expression(self) -> ir.Expr:
        t = self.tok
        if self.at_op("-", "+"):
            self.advance()
            left: ir.Expr = ir.Unary(t.text, self.term(), t.loc)
        else:
            left = self.term()
        while self.at_op("+", "-", "&"):
            op = self.advance()
            left = ir.Binary(op.text, left, self.term(), op.loc)
        return left

    def term(self) -> ir.Expr:
        left = self.factor()
        while self.at_op("*", "/") or self.at_kw("mod", "rem"):
            op = self.advance()
            left = ir.Binary(op.text, left, self.factor(), op.loc)
        return left

    def factor(self) -> ir.Expr:
        t = self.tok
        if self.accept_kw("abs"):
            return ir.Unary("abs", self.primary(), t.loc)
        if self.accept_kw("not"):
            return ir.Unary("not", self.primary(), t.loc)
        left = self.primary()
        if self.at_op("**"):
            op = self.advance()
            return ir.Binary("**", left, self.primary(), op.loc)
        return left

    def primary(self) -> ir.Expr:
        t = self.tok
        if t.kind == "num":
            self.advance()
            return ir.Num(float(t.text), "." not in t.text, t.loc)
        if t.kind == "str":
            self.advance()
            return ir.Str(t.text, t.loc)
        if t.kind == "char":
            self.advance()
            return ir.Char(t.text, t.loc)
        if self.at_op("-", "+"):
            raise self.error("a sign inside an expression must be parenthesized, e.g. a * (-b)")
        if self.accept_op("("):
            first = self.expression()
            if self.at_op("=>"):
                raise self.unsupported("named aggregate")
            if self.accept_op(","):
                items = [first, self.expression()]
                while self.accept_op(","):
                    items.append(self.expression())
                self.expect_op(")")
                return ir.Aggregate(items, t.loc)
            self.expect_op(")")
            return first
        if t.kind == "id":
            return self.name_expr()
        if t.is_("kw", "null"):
            raise self.unsupported("null literal")
        raise self.error(f"expected an expression, found {self.describe(t)}")

    def name_expr(self) -> ir.Expr:
        t = self.tok
        name = self.ident()
        while self.at_op(".") and self.peek().kind in ("id", "kw"):
            self.advance()
            name += "." + (self.advance().text)
        if self.at_op("("):
            return ir.Call(name, self.association_list(), t.loc)
        if self.at_op("'"):
            tick = self.advance()
            if self.tok.kind not in ("id", "kw"):
                raise self.error("expected an attribute name after the tick", tick)
            attr = self.advance().text
            args = []
            if self.accept_op("("):
                args.append(self.expression())
                while self.accept_op(","):
                    args.append(self.expression())
                self.expect_op(")")
            return ir.Attr(name, attr, args, tick.loc)
        return ir.Name(name, t.loc)
