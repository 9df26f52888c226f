"""Declarations of the subset: interface lists (generics, ports), types, subtypes and natures, objects (constants,
signals, terminals, free and branch quantities), subprograms (pure functions and the declarations of their bodies),
and the other declarative items (components, aliases, attributes, limit and configuration specifications). Each
parse method's docstring starts with the rule it reads, in the notation of IEEE 1076 and 1076.1."""

from __future__ import annotations

from wrsim.frontend import ast
from wrsim.frontend.concurrent import ConcurrentParser
from wrsim.frontend.lexer import Token

__all__ = ["DeclarationParser", "MAX_WIDTH"]

MAX_WIDTH = 256  # bits of a std_logic_vector port or signal (d_cosim carries one node per bit)


class DeclarationParser(ConcurrentParser):
    """Declarations, on top of the statements (a function's body is a sequence of statements)."""

    # ------------------------------------------------------------------ interface lists
    def generic_clause(self) -> list[ast.Generic]:
        """generic_clause ::= generic ( interface_constant_declaration { ; interface_constant_declaration } ) ;
        interface_constant_declaration ::= [ constant ] identifier_list : [ in ] type_mark [ := expression ]"""
        self.expect_kw("generic")
        self.expect_op("(")
        out: list[ast.Generic] = []
        while True:
            t = self.tok
            self.accept_kw("constant")
            names = self.ident_list()
            self.expect_op(":")
            self.accept_kw("in")
            type_mark, bounds = self.subtype_indication()
            default = self.expression() if self.accept_op(":=") else None
            unit, comment = self.unit_comment(self.tok.loc.line if self.at_op(";") else t.loc.line, t.loc.line)
            for n in names:
                out.append(ast.Generic(n, type_mark, default, unit, comment, t.loc, bounds))
            if not self.accept_op(";"):
                break
        self.expect_op(")")
        self.expect_op(";")
        return out

    def port_clause(self) -> list[ast.Port]:
        """port_clause ::= port ( interface_declaration { ; interface_declaration } ) ;
        interface_declaration ::= terminal identifier_list : nature_mark
                                | quantity identifier_list : ( in | out ) type_mark
                                | [ signal ] identifier_list : ( in | out ) signal_type [ := expression ]"""
        self.expect_kw("port")
        self.expect_op("(")
        out: list[ast.Port] = []
        while True:
            t = self.tok
            if self.accept_kw("terminal"):
                names = self.ident_list()
                self.expect_op(":")
                nature = self.type_mark()
                out.extend(ast.TerminalPort(n, nature, t.loc) for n in names)
            elif self.accept_kw("quantity"):
                names = self.ident_list()
                self.expect_op(":")
                mode = self.port_mode("quantity")
                type_mark = self.type_mark()
                if self.at_op(":="):
                    raise self.unsupported("default value on a quantity port")
                unit, _ = self.unit_comment(t.loc.line)
                out.extend(ast.QuantityPort(n, mode, type_mark, unit, t.loc) for n in names)
            elif self.at_kw("signal") or self.tok.kind == "id":
                self.accept_kw("signal")
                names = self.ident_list()
                self.expect_op(":")
                mode = self.port_mode("signal")
                type_mark, width = self.signal_type()
                if self.at_op(":=") and self.is_digital_file:
                    self.advance()
                    self.expression()  # GHDL's business
                elif self.at_op(":="):
                    raise self.unsupported("default value on a signal port of an AMS model")
                out.extend(ast.SignalPort(n, mode, type_mark, width, t.loc) for n in names)
            else:
                raise self.error(f"expected 'terminal' or 'quantity' port, found {self.describe(self.tok)}")
            if not self.accept_op(";"):
                break
        self.expect_op(")")
        self.expect_op(";")
        return out

    def port_mode(self, kind: str) -> str:
        """mode ::= in | out"""
        for mode in ("in", "out"):
            if self.accept_kw(mode):
                return mode
        if self.at_kw("inout", "buffer", "linkage"):
            raise self.unsupported(f"{kind} port mode '{self.tok.text}' (use in or out)")
        raise self.error(f"a {kind} port needs mode 'in' or 'out'")

    # ------------------------------------------------------------------ types, subtypes and natures
    def signal_type(self, held: bool = False) -> tuple[str, int | None]:
        """signal_type ::= std_logic | std_logic_vector ( integer_literal downto 0 ) | integer | natural | boolean
        | bit, and with `held` (a signal declared in an architecture) also std_ulogic and any other type mark (real,
        a real subtype such as resistance: the elaboration resolves it) -> (type, width)"""
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
        if held:
            return name, None
        if name == "std_ulogic":  # a port: the unresolved std_logic; one driver either way
            return "std_logic", None
        raise self.unsupported(
            f"signal type '{name}' (std_logic, std_ulogic, std_logic_vector, integer, natural, boolean)", t
        )

    def type_mark(self) -> str:
        """type_mark ::= identifier { . identifier } (no constraint)"""
        name = self.ident("type or nature name")
        while self.accept_op("."):
            name = self.ident("type or nature name")
        if self.at_op("(") or self.at_kw("range"):
            raise self.unsupported("constrained subtype indication")
        return name

    def subtype_indication(self) -> tuple[str, ast.Bounds | None]:
        """subtype_indication ::= type_mark [ ( simple_expression ( to | downto ) simple_expression ) ]"""
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
        return name, ast.Bounds(left, right, downto)

    def subtype_declaration(self, t: Token) -> list:
        """After `subtype`: subtype_declaration ::= subtype identifier is subtype_indication [ ' ( across |
        through ) ] [ tolerance string_literal ] ;"""
        name = self.ident()
        self.expect_kw("is")
        base, bounds = self.subtype_indication()
        if self.at_op("'") and (self.peek().is_("kw", "across") or self.peek().is_("kw", "through")):
            self.advance()  # n_vector'across: the array of the element nature's across type
            self.advance()
            base = "real_vector"
        tol = None
        if self.accept_kw("tolerance"):
            if not self.at("str"):
                raise self.error("expected a tolerance string")
            tol = self.advance().text
        self.expect_op(";")
        unit, _ = self.unit_comment(t.loc.line)
        return [ast.SubtypeDecl(name, base, tol, unit, t.loc, bounds)]

    def nature_declaration(self, t: Token) -> list:
        """After `nature`: nature_declaration ::= nature identifier is ( type_mark across type_mark through
        identifier reference | array ( index_subtype_definition ) of nature_mark ) ;"""
        name = self.ident()
        self.expect_kw("is")
        if self.accept_kw("array"):  # nature n is array (natural range <>) of element;
            self.skip_to("of")
            element = self.type_mark()
            self.expect_op(";")
            return [ast.ArrayNatureDecl(name, element, t.loc)]
        if self.at_kw("record"):
            raise self.unsupported("record nature")
        across = self.type_mark()
        self.expect_kw("across")
        through = self.type_mark()
        self.expect_kw("through")
        ref = self.ident("reference terminal name")
        self.expect_kw("reference")
        self.expect_op(";")
        return [ast.NatureDecl(name, across, through, ref, t.loc)]

    def subnature_declaration(self, t: Token) -> list:
        """After `subnature`: subnature_declaration ::= subnature identifier is nature_mark ;"""
        name = self.ident()
        self.expect_kw("is")
        base = self.type_mark()
        self.expect_op(";")
        return [ast.SubnatureDecl(name, base, t.loc)]

    # ------------------------------------------------------------------ objects
    def declarations(self, stop: tuple[str, ...]) -> list:
        """block_declarative_part ::= { block_declarative_item } (up to one of the reserved words `stop`)"""
        out: list = []
        while not self.at_kw(*stop):
            out.extend(self.declaration())
        return out

    def declaration(self) -> list:
        """block_declarative_item ::= constant_declaration | subtype_declaration | nature_declaration
        | subnature_declaration | terminal_declaration | quantity_declaration | function_declaration
        | function_body | component_declaration | signal_declaration | alias_declaration
        | attribute_declaration | attribute_specification | step_limit_specification
        | configuration_specification"""
        t = self.tok
        if self.accept_kw("constant"):
            return self.constant_declaration(t)
        if self.accept_kw("subtype"):
            return self.subtype_declaration(t)
        if self.accept_kw("nature"):
            return self.nature_declaration(t)
        if self.accept_kw("subnature"):
            return self.subnature_declaration(t)
        if self.accept_kw("terminal"):
            return self.terminal_declaration(t)
        if self.accept_kw("quantity"):
            return self.quantity_declaration(t)
        if self.at_kw("function", "pure", "impure"):
            return [self.function()]
        if self.accept_kw("component"):
            return [self.component_declaration(t)]
        if self.accept_kw("signal"):
            return self.signal_declaration(t)
        if self.accept_kw("alias"):
            return [self.alias_declaration(t)]
        if self.accept_kw("attribute"):
            return self.attribute(t)
        if self.accept_kw("limit"):
            return [self.step_limit_specification(t)]
        if self.accept_kw("for"):
            return [self.configuration_spec(t)]
        if self.at_kw("type", "procedure", "shared", "file", "variable", "group", "disconnect"):
            raise self.unsupported(f"{self.tok.text} declaration")
        raise self.error(f"expected a declaration, found {self.describe(t)}")

    def constant_declaration(self, t: Token) -> list:
        """After `constant`: constant_declaration ::= constant identifier_list : subtype_indication
        [ := expression ] ;"""
        names = self.ident_list()
        self.expect_op(":")
        type_mark, bounds = self.subtype_indication()
        value = self.expression() if self.accept_op(":=") else None
        self.expect_op(";")
        return [ast.ConstantDecl(n, type_mark, value, t.loc, bounds) for n in names]

    def signal_declaration(self, t: Token) -> list:
        """After `signal`: signal_declaration ::= signal identifier_list : signal_type [ := expression ] ;"""
        names = self.ident_list()
        self.expect_op(":")
        type_mark, width = self.signal_type(held=True)
        value = self.expression() if self.accept_op(":=") else None
        self.expect_op(";")
        return [ast.SignalDecl(n, type_mark, width, t.loc, value) for n in names]

    def terminal_declaration(self, t: Token) -> list:
        """After `terminal`: terminal_declaration ::= terminal identifier_list : subnature_indication ;"""
        names = self.ident_list()
        self.expect_op(":")
        nature, bounds = self.subtype_indication()
        self.expect_op(";")
        return [ast.TerminalDecl(n, nature, t.loc, bounds) for n in names]

    def quantity_declaration(self, t: Token) -> list:
        """After `quantity`: quantity_declaration ::= free_quantity_declaration | branch_quantity_declaration
            | source_quantity_declaration
        free_quantity_declaration ::= quantity identifier_list : subtype_indication [ := expression ] ;
        branch_quantity_declaration ::= quantity [ across_aspect ] [ through_aspect ] terminal_aspect ;
        across_aspect ::= identifier_list [ tolerance_aspect ] [ := expression ] across
        through_aspect ::= identifier_list [ tolerance_aspect ] [ := expression ] through
        terminal_aspect ::= terminal_name [ to terminal_name ]
        source_quantity_declaration ::= quantity identifier_list : subtype_indication ( spectrum expression ,
            expression | noise expression ) ;"""
        names = self.ident_list()
        self.tolerance_aspect()
        if self.accept_op(":="):  # a branch quantity's initial value: only a starting guess (1076.1)
            self.expression()
        if self.accept_op(":"):
            type_mark, bounds = self.subtype_indication()
            self.tolerance_aspect()
            if self.at_kw("spectrum", "noise"):
                source = self.advance().text
                spectrum = [self.expression()]
                if source == "spectrum":
                    self.expect_op(",")
                    spectrum.append(self.expression())
                self.expect_op(";")
                unit, _ = self.unit_comment(t.loc.line)
                return [
                    ast.FreeQuantityDecl(n, type_mark, None, unit, t.loc, source=source, spectrum=tuple(spectrum))
                    for n in names
                ]
            init = self.expression() if self.accept_op(":=") else None
            self.expect_op(";")
            unit, _ = self.unit_comment(t.loc.line)
            return [ast.FreeQuantityDecl(n, type_mark, init, unit, t.loc, bounds=bounds) for n in names]
        across = through = None
        if self.accept_kw("across"):
            across = names
            k = 1  # `across i1, i2 [tolerance ...] [:= ...] through`: through names follow
            while self.peek(k).is_("op", ",") and self.peek(k + 1).kind == "id":
                k += 2
            after = self.peek(k)
            if self.tok.kind == "id" and (
                after.is_("kw", "through") or after.is_("kw", "tolerance") or after.is_("op", ":=")
            ):
                through = self.ident_list()
                self.tolerance_aspect()
                if self.accept_op(":="):
                    self.expression()
                self.expect_kw("through")
        elif self.accept_kw("through"):
            through = names
        else:
            raise self.error(
                f"expected ':', 'across' or 'through' in quantity declaration, found {self.describe(self.tok)}"
            )
        plus = self.terminal_name()
        minus = self.terminal_name() if self.accept_kw("to") else None
        self.expect_op(";")
        # several across quantities are names of one voltage; several through quantities are parallel branches
        a: list[str | None] = [*across] if across else [None]
        th: list[str | None] = [*through] if through else [None]
        return [
            ast.BranchQuantityDecl(
                a[k] if k < len(a) else None, th[k] if k < len(th) else None, plus, minus, None, None, t.loc
            )
            for k in range(max(len(a), len(th)))
        ]

    def terminal_name(self) -> str | ast.Expr:
        """terminal_name ::= identifier [ ( simple_expression ) ] | identifier ' reference

        A terminal, t(k) (an element of a vector terminal), or N'reference (the reference terminal of N)."""
        t = self.tok
        name = self.ident("terminal name")
        if self.accept_op("("):
            index = self.simple_expression()
            self.expect_op(")")
            return ast.Call(name, [ast.Assoc(None, index, index.loc)], t.loc)
        if self.at_op("'") and self.peek().is_("kw", "reference"):
            self.advance()
            name += "'" + self.advance().text
        return name

    # ------------------------------------------------------------------ subprograms
    def function(self) -> ast.FunctionDecl:
        """function_declaration ::= function_specification ;
        function_body ::= function_specification is subprogram_declarative_part begin sequence_of_statements
            end [ function ] [ designator ] ;
        function_specification ::= [ pure ] function designator [ ( interface_constant_declaration
            { ; interface_constant_declaration } ) ] return type_mark"""
        t = self.tok
        if self.accept_kw("impure"):
            raise self.unsupported("impure function", t)
        self.accept_kw("pure")
        self.expect_kw("function")
        name = self.ident("function name")
        params: list[ast.Param] = []
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
                params.extend(ast.Param(n, type_mark, pt.loc) for n in names)
                if not self.accept_op(";"):
                    break
            self.expect_op(")")
        self.expect_kw("return")
        ret = self.type_mark()
        if self.accept_op(";"):
            return ast.FunctionDecl(name, params, ret, None, None, t.loc)
        self.expect_kw("is")
        decls = self.local_declarations()
        self.expect_kw("begin")
        body = self.sequence(("end",))
        self.end_of("function", name=name)
        return ast.FunctionDecl(name, params, ret, decls, body, t.loc)

    def local_declarations(self) -> list:
        """subprogram_declarative_part ::= { variable_declaration | constant_declaration } (up to `begin`)
        variable_declaration ::= variable identifier_list : type_mark [ := expression ] ;

        The declarations of a function, process or procedural."""
        decls: list = []
        while not self.at_kw("begin"):
            dt = self.tok
            if self.accept_kw("variable"):
                names = self.ident_list()
                self.expect_op(":")
                type_mark = self.type_mark()
                value = self.expression() if self.accept_op(":=") else None
                self.expect_op(";")
                decls.extend(ast.VariableDecl(n, type_mark, value, dt.loc) for n in names)
            elif self.at_kw("constant"):
                decls.extend(self.declaration())
            else:
                raise self.error(f"expected a variable or constant declaration, found {self.describe(dt)}")
        return decls

    # ------------------------------------------------------------------ other declarative items
    def component_declaration(self, t: Token) -> ast.ComponentDecl:
        """After `component`: component_declaration ::= component identifier [ is ] [ generic_clause ]
        [ port_clause ] end component [ identifier ] ;"""
        name = self.ident()
        self.accept_kw("is")
        generics = self.generic_clause() if self.at_kw("generic") else []
        ports = self.port_clause() if self.at_kw("port") else []
        self.end_of("component", name=name)
        return ast.ComponentDecl(name, generics, ports, t.loc)

    def alias_declaration(self, t: Token) -> ast.AliasDecl:
        """After `alias`: alias_declaration ::= alias identifier [ : type_mark ] is name [ ' reference ] ;"""
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
        return ast.AliasDecl(name, target, t.loc)

    def attribute(self, t: Token) -> list:
        """After `attribute`: attribute_declaration ::= attribute identifier : type_mark ;
        attribute_specification ::= attribute identifier of ( identifier_list | all | others ) : entity_class
            is expression ;"""
        attr = self.ident("attribute name")
        if self.accept_op(":"):  # a declaration: n'attr is read from its specifications
            self.skip_to(";")
            return []
        self.expect_kw("of")
        names = ["all"] if self.accept_kw("all") else ["others"] if self.accept_kw("others") else self.ident_list()
        self.expect_op(":")
        self.advance()  # the entity class (quantity, subtype, label, ...)
        self.expect_kw("is")
        value = self.expression()
        self.expect_op(";")
        return [ast.AttributeSpec(attr, names, value, t.loc)]

    def step_limit_specification(self, t: Token) -> ast.LimitSpec:
        """After `limit`: step_limit_specification ::= limit quantity_specification with real_expression ;"""
        self.skip_to("with")
        step = self.expression()
        self.expect_op(";")
        return ast.LimitSpec(step, t.loc)

    def configuration_spec(self, t: Token) -> ast.ConfigSpec:
        """After `for`: configuration_specification ::= for ( identifier_list | all | others ) : component_name
        use entity entity_name [ ( architecture_identifier ) ] ;"""
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
        return ast.ConfigSpec(labels, component, entity, arch, t.loc)

    def skip_to(self, stop: str) -> None:
        """Skip tokens up to and including the operator or reserved word `stop`."""
        while not self.at("eof"):
            if self.advance().text == stop:
                return
        raise self.error(f"expected '{stop}'")
