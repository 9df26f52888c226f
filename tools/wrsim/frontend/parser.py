"""Recursive-descent parser for the VHDL-AMS subset of docs/vhdl-ams-subset.md: tokens -> ir.DesignFile.

Constructs outside the subset are recognised far enough to be named: `unsupported construct: ...` with
file:line:col. A hand-written parser was chosen over a grammar library because VHDL's ambiguities (calls vs
indexing, attribute ticks vs character literals, labels) need token look-ahead that is easier to keep
precise by hand, and because every message must point at the offending token."""
from __future__ import annotations

from pathlib import Path

from wrsim.errors import WrsimError
from wrsim.frontend import ast as ir
from wrsim.frontend.lexer import Token, tokenize
from wrsim.frontend.statements import StatementParser

__all__ = ["parse_text", "parse_file", "read_source", "MAX_WIDTH"]

AMS_RESERVED = {"across", "break", "limit", "nature", "noise", "procedural", "quantity", "reference", "spectrum",
                "subnature", "terminal", "through", "tolerance"}     # the words 1076.1 adds to VHDL
MAX_WIDTH = 256        # bits of a std_logic_vector port or signal (d_cosim carries one node per bit)


def parse_file(path: str | Path, library: str = "work") -> ir.DesignFile:
    """Parse one .vhd file into design units of `library`."""
    return parse_text(read_source(path), str(path), library)


def read_source(path: str | Path) -> str:
    """The text of a VHDL-AMS source file; WrsimError naming the file when it cannot be read as UTF-8."""
    try:
        return Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise WrsimError(f"{path}: cannot read VHDL-AMS source: {e}") from None


def parse_text(text: str, path: str = "<string>", library: str = "work") -> ir.DesignFile:
    """Parse VHDL-AMS source text."""
    return _Parser(tokenize(text, path), path, library).design_file()


class _Parser(StatementParser):
    """Design files: use clauses, entities, architectures, packages, and their declarations."""

    # ------------------------------------------------------------------ design file
    def design_file(self) -> ir.DesignFile:
        self.is_digital_file = self.is_digital()
        if self.is_digital_file:                # GHDL reads its bodies, a 1076.1 tool reads them too
            word = next((t for t in self.toks if t.kind == "kw" and t.text in AMS_RESERVED), None)
            if word is not None:
                raise self.error(f"'{word.text}' is a reserved word of VHDL-AMS (IEEE 1076.1): a digital unit "
                                 f"analysed next to the AMS models cannot use it as a name", word)
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

    def signal_type(self, held: bool = False) -> tuple[str, int | None]:
        """std_logic | std_logic_vector(N-1 downto 0) | integer | natural | boolean -> (type, width); `held` (a
        signal declared in an architecture): also real, bit, std_ulogic."""
        t = self.tok
        name = self.type_mark() if not self.at("id", "std_logic_vector") else self.advance().text
        if name == "std_logic_vector":
            self.expect_op("(")
            hi = self.advance()
            self.expect_kw("downto")
            lo = self.advance()
            self.expect_op(")")
            if hi.kind != "num" or lo.kind != "num" or lo.text != "0" or not hi.text.isdigit():
                raise self.unsupported("std_logic_vector range other than (N-1 downto 0) with a literal N", t)
            if int(hi.text) >= MAX_WIDTH:
                raise self.error(f"std_logic_vector of {int(hi.text) + 1} bits: at most {MAX_WIDTH} are supported", hi)
            return name, int(hi.text) + 1
        if name in ("integer", "natural"):
            return name, 32
        if name in ("std_logic", "boolean", "bit"):
            return name, None
        if held and name in ("real", "std_ulogic"):
            return name, None
        raise self.unsupported(f"signal type '{name}' (std_logic, std_logic_vector, integer, natural, boolean)", t)

    def type_mark(self) -> str:
        name = self.ident("type or nature name")
        while self.accept_op("."):
            name = self.ident("type or nature name")
        if self.at_op("(") or self.at_kw("range"):
            raise self.unsupported("constrained subtype indication")
        return name

    def subtype_indication(self) -> tuple[str, ir.Bounds | None]:
        """A type or nature mark with an optional index constraint `(a to b)` / `(a downto b)`."""
        t = self.tok
        name = self.ident("type or nature name")
        while self.accept_op("."):
            name = self.ident("type or nature name")
        if self.at_kw("range"):
            raise self.unsupported("range constraint")
        if not self.accept_op("("):
            return name, None
        left = self.simple_expression()
        downto = self.accept_kw("downto")
        if not downto and not self.accept_kw("to"):
            raise self.unsupported("index constraint other than (a to b) or (a downto b)", t)
        right = self.simple_expression()
        self.expect_op(")")
        return name, ir.Bounds(left, right, downto)

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
            type_mark, bounds = self.subtype_indication()
            value = self.expression() if self.accept_op(":=") else None
            self.expect_op(";")
            return [ir.ConstantDecl(n, type_mark, value, t.loc, bounds) for n in names]
        if self.accept_kw("subtype"):
            name = self.ident()
            self.expect_kw("is")
            base, bounds = self.subtype_indication()
            if self.at_op("'") and (self.peek().is_("kw", "across") or self.peek().is_("kw", "through")):
                self.advance()               # n_vector'across: the array of the element nature's across type
                self.advance()
                base = "real_vector"
            tol = None
            if self.accept_kw("tolerance"):
                if not self.at("str"):
                    raise self.error("expected a tolerance string")
                tol = self.advance().text
            self.expect_op(";")
            unit, _ = self.unit_comment(t.loc.line)
            return [ir.SubtypeDecl(name, base, tol, unit, t.loc, bounds)]
        if self.accept_kw("nature"):
            name = self.ident()
            self.expect_kw("is")
            if self.accept_kw("array"):      # nature n is array (natural range <>) of element;
                self.skip_to("of")
                element = self.type_mark()
                self.expect_op(";")
                return [ir.ArrayNatureDecl(name, element, t.loc)]
            if self.at_kw("record"):
                raise self.unsupported("record nature")
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
            nature, bounds = self.subtype_indication()
            self.expect_op(";")
            return [ir.TerminalDecl(n, nature, t.loc, bounds) for n in names]
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
            type_mark, width = self.signal_type(held=True)
            value = self.expression() if self.accept_op(":=") else None
            self.expect_op(";")
            return [ir.SignalDecl(n, type_mark, width, t.loc, value) for n in names]
        if self.accept_kw("alias"):
            name = self.ident("alias name")
            if self.accept_op(":"):
                self.type_mark()
            self.expect_kw("is")
            target = self.type_mark()
            if self.at_op("'") and self.peek().is_("kw", "reference"):
                self.advance()
                target += "'" + self.advance().text
            if self.at_op("["):
                raise self.unsupported("alias of a subprogram (signature)")
            self.expect_op(";")
            return [ir.AliasDecl(name, target, t.loc)]
        if self.accept_kw("attribute"):
            attr = self.ident("attribute name")
            if self.accept_op(":"):          # a declaration: n'attr is read from its specifications
                self.skip_to(";")
                return []
            self.expect_kw("of")
            names = ["all"] if self.accept_kw("all") else ["others"] if self.accept_kw("others") else \
                self.ident_list()
            self.expect_op(":")
            self.advance()                   # the entity class (quantity, subtype, label, ...)
            self.expect_kw("is")
            value = self.expression()
            self.expect_op(";")
            return [ir.AttributeSpec(attr, names, value, t.loc)]
        if self.accept_kw("limit"):
            self.skip_to("with")
            step = self.expression()
            self.expect_op(";")
            return [ir.LimitSpec(step, t.loc)]
        if self.accept_kw("for"):
            return [self.configuration_spec(t)]
        if self.at_kw("type", "procedure", "shared", "file", "variable", "group", "disconnect"):
            raise self.unsupported(f"{self.tok.text} declaration")
        raise self.error(f"expected a declaration, found {self.describe(t)}")

    def skip_to(self, stop: str) -> None:
        """Skip tokens up to and including the operator or reserved word `stop`."""
        while not self.at("eof"):
            if self.advance().text == stop:
                return
        raise self.error(f"expected '{stop}'")

    def quantity_declaration(self, t: Token) -> list:
        names = self.ident_list()
        self.tolerance_aspect()
        if self.accept_op(":="):     # a branch quantity's initial value: only a starting guess (1076.1)
            self.expression()
        if self.accept_op(":"):
            type_mark, bounds = self.subtype_indication()
            self.tolerance_aspect()
            if self.at_kw("spectrum", "noise"):
                source = self.advance().text
                self.expression()
                if source == "spectrum":
                    self.expect_op(",")
                    self.expression()
                self.expect_op(";")
                return [ir.FreeQuantityDecl(n, type_mark, None, None, t.loc, source=source) for n in names]
            init = self.expression() if self.accept_op(":=") else None
            self.expect_op(";")
            unit, _ = self.unit_comment(t.loc.line)
            return [ir.FreeQuantityDecl(n, type_mark, init, unit, t.loc, bounds=bounds) for n in names]
        across = through = None
        if self.accept_kw("across"):
            across = names
            k = 1                            # `across i1, i2 [tolerance ...] [:= ...] through`: through names follow
            while self.peek(k).is_("op", ",") and self.peek(k + 1).kind == "id":
                k += 2
            after = self.peek(k)
            if self.tok.kind == "id" and (after.is_("kw", "through") or after.is_("kw", "tolerance")
                                          or after.is_("op", ":=")):
                through = self.ident_list()
                self.tolerance_aspect()
                if self.accept_op(":="):
                    self.expression()
                self.expect_kw("through")
        elif self.accept_kw("through"):
            through = names
        else:
            raise self.error(f"expected ':', 'across' or 'through' in quantity declaration, found "
                             f"{self.describe(self.tok)}")
        plus = self.terminal_name()
        minus = self.terminal_name() if self.accept_kw("to") else None
        self.expect_op(";")
        # several across quantities are names of one voltage; several through quantities are parallel branches
        a: list[str | None] = [*across] if across else [None]
        th: list[str | None] = [*through] if through else [None]
        return [ir.BranchQuantityDecl(a[k] if k < len(a) else None, th[k] if k < len(th) else None, plus, minus,
                                      None, None, t.loc) for k in range(max(len(a), len(th)))]

    def terminal_name(self) -> str | ir.Expr:
        """A terminal, t(k) (an element of a vector terminal), or N'reference (the reference terminal of N)."""
        t = self.tok
        name = self.ident("terminal name")
        if self.accept_op("("):
            index = self.simple_expression()
            self.expect_op(")")
            return ir.Call(name, [ir.Assoc(None, index, index.loc)], t.loc)
        if self.at_op("'") and self.peek().is_("kw", "reference"):
            self.advance()
            name += "'" + self.advance().text
        return name

    def configuration_spec(self, t: Token) -> ir.ConfigSpec:
        """After `for`: `labels | all | others : component use entity lib.e[(a)];`"""
        labels = ["all"] if self.accept_kw("all") else ["others"] if self.accept_kw("others") else self.ident_list()
        self.expect_op(":")
        component = self.ident("component name")
        self.expect_kw("use")
        if not self.accept_kw("entity"):
            raise self.unsupported("configuration specification other than 'use entity'")
        entity = self.ident("entity name")
        while self.accept_op("."):
            entity = self.ident("entity name")
        arch = None
        if self.accept_op("("):
            arch = self.ident("architecture name")
            self.expect_op(")")
        if self.at_kw("generic", "port"):
            raise self.unsupported("generic or port map in a configuration specification")
        self.expect_op(";")
        return ir.ConfigSpec(labels, component, entity, arch, t.loc)

    def local_declarations(self) -> list:
        """The variable and constant declarations of a function or process, up to `begin`."""
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
        return decls

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
        decls = self.local_declarations()
        self.expect_kw("begin")
        body = self.sequence(("end",))
        self.end_of("function", name=name)
        return ir.FunctionDecl(name, params, ret, decls, body, t.loc)
