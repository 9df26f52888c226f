"""Recursive-descent parser for the VHDL-AMS subset of docs/vhdl-ams-subset.md: tokens -> ast.DesignFile.

The grammar is read in layers, each a module: the token cursor (`cursor`), expressions (`expressions`), sequential
statements (`statements`), concurrent statements (`concurrent`), declarations (`declarations`), and here design
files and design units. Each parse method's docstring starts with the rule it reads, in the notation of IEEE 1076
and 1076.1 (`::=`, `[ ]` optional, `{ }` repeated, `|` alternatives; reserved words in lower case).

Constructs outside the subset are recognised far enough to be named: `unsupported construct: ...` with
file:line:col. A hand-written parser was chosen over a grammar library because VHDL's ambiguities (calls vs
indexing, attribute ticks vs character literals, labels) need token look-ahead that is easier to keep
precise by hand, and because every message must point at the offending token."""

from __future__ import annotations

from pathlib import Path

from wrsim.errors import WrsimError
from wrsim.frontend import ast
from wrsim.frontend.declarations import DeclarationParser
from wrsim.frontend.lexer import Token, tokenize

__all__ = ["parse_text", "parse_file", "read_source"]

AMS_RESERVED = {
    "across",
    "break",
    "limit",
    "nature",
    "noise",
    "procedural",
    "quantity",
    "reference",
    "spectrum",
    "subnature",
    "terminal",
    "through",
    "tolerance",
}  # the words 1076.1 adds to VHDL


def parse_file(path: str | Path, library: str = "work") -> ast.DesignFile:
    """Parse one .vhd file into design units of `library`."""
    return parse_text(read_source(path), str(path), library)


def read_source(path: str | Path) -> str:
    """The text of a VHDL-AMS source file; WrsimError naming the file when it cannot be read as UTF-8."""
    try:
        return Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise WrsimError(f"{path}: cannot read VHDL-AMS source: {e}") from None


def parse_text(text: str, path: str = "<string>", library: str = "work") -> ast.DesignFile:
    """Parse VHDL-AMS source text."""
    return _Parser(tokenize(text, path), path, library).design_file()


class _Parser(DeclarationParser):
    """Design files: context clauses and design units (entities, architectures, packages)."""

    def design_file(self) -> ast.DesignFile:
        """design_file ::= { context_item } design_unit { { context_item } design_unit }
        context_item ::= library_clause | use_clause"""
        self.is_digital_file = self.is_digital()
        if self.is_digital_file:  # GHDL reads its bodies, a 1076.1 tool reads them too
            word = next((t for t in self.toks if t.kind == "kw" and t.text in AMS_RESERVED), None)
            if word is not None:
                raise self.error(
                    f"'{word.text}' is a reserved word of VHDL-AMS (IEEE 1076.1): a digital unit "
                    f"analysed next to the AMS models cannot use it as a name",
                    word,
                )
        df = ast.DesignFile(self.path, self.library, digital=self.is_digital_file)
        uses: list[ast.UseClause] = []
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

    def use_clause(self) -> list[ast.UseClause]:
        """use_clause ::= use library_name . package_name [ . ( identifier | all ) ] { , ... } ;"""
        out = []
        self.expect_kw("use")
        while True:
            t = self.tok
            parts = [
                self.ident("library name"),
            ]
            self.expect_op(".")
            parts.append(self.ident("package name"))
            if self.accept_op("."):
                parts.append("all" if self.accept_kw("all") else self.ident())
            else:
                parts.append("all")
            out.append(ast.UseClause(parts[0], parts[1], parts[2], t.loc))
            if not self.accept_op(","):
                break
        self.expect_op(";")
        return out

    def design_unit(self, uses: list[ast.UseClause]) -> ast.DesignUnit:
        """design_unit ::= entity_declaration | architecture_body | package_declaration | package_body
        package_declaration ::= package identifier is package_declarative_part end [ package ] [ identifier ] ;
        package_body ::= package body identifier is package_body_declarative_part end [ package body ]
            [ identifier ] ;

        A digital file's architectures and packages are skipped (GHDL analyses them)."""
        t = self.tok
        digital = self.is_digital_file
        if digital and self.at_kw("architecture", "package"):
            self.advance()
            if self.accept_kw("body"):
                name = self.ident()
                self.skip_unit(("package", "body"), name)
                return ast.PackageBody(name, [], uses, t.loc)
            name = self.ident()
            if t.text == "package":
                self.skip_unit(("package",), name)
                return ast.Package(name, [], uses, t.loc)
            self.expect_kw("of")
            entity = self.ident("entity name")
            self.skip_unit(("architecture",), name)
            return ast.DigitalArchitecture(name, entity, self.path, t.loc)
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
                return ast.PackageBody(name, decls, uses, t.loc)
            name = self.ident()
            self.expect_kw("is")
            decls = self.declarations(("end",))
            self.end_of("package", name=name)
            return ast.Package(name, decls, uses, t.loc)
        if self.at_kw("configuration"):
            raise self.unsupported("configuration declaration")
        raise self.error(f"expected a design unit (entity, architecture, package), found {self.describe(t)}")

    def entity(self, t: Token, uses: list[ast.UseClause]) -> ast.Entity:
        """After `entity`: entity_declaration ::= entity identifier is [ generic_clause ] [ port_clause ]
        { attribute_declaration | attribute_specification } [ begin { concurrent_assertion_statement } ]
        end [ entity ] [ identifier ] ;"""
        name = self.ident("entity name")
        self.expect_kw("is")
        generics = self.generic_clause() if self.at_kw("generic") else []
        ports = self.port_clause() if self.at_kw("port") else []
        attributes: list[ast.AttributeSpec] = []
        while self.at_kw("attribute"):
            attributes += self.attribute(self.advance())
        stmts: list[ast.Assertion] = []
        if self.is_digital_file and self.at_kw("begin"):
            self.skip_unit(("entity",), name)
            return ast.Entity(name, generics, ports, stmts, uses, self.header_before(t.loc.line), t.loc, attributes)
        if self.accept_kw("begin"):
            while not self.at_kw("end"):
                s = self.concurrent_statement()
                if not isinstance(s, ast.Assertion):
                    raise self.error("only assertions are allowed in an entity's statement part", t)
                stmts.append(s)
        self.end_of("entity", name=name)
        return ast.Entity(name, generics, ports, stmts, uses, self.header_before(t.loc.line), t.loc, attributes)

    def architecture(self, t: Token, uses: list[ast.UseClause]) -> ast.Architecture:
        """After `architecture`: architecture_body ::= architecture identifier of entity_name is
        architecture_declarative_part begin { concurrent_statement } end [ architecture ] [ identifier ] ;"""
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
        return ast.Architecture(name, entity, decls, stmts, uses, t.loc)

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
