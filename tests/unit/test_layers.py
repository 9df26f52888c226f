"""The package's import graph follows the pipeline: no module imports from a later stage (frontend < elab <
backend < runner < report < identify < benches < study < commands < antipinch_commands < cli; report publishes what
the stages after it make: result files, pages, references). The shared modules (data, errors, paths, the result
types, the closed-form references) import no stage."""

from __future__ import annotations

import ast

from wrsim import paths

PACKAGE = paths.ROOT / "tools" / "wrsim"
STAGES = (
    "frontend",
    "elab",
    "backend",
    "runner",
    "report",
    "identify",
    "benches",
    "study",
    "commands",
    "antipinch_commands",
    "cli",
)
SHARED = ("data", "errors", "paths", "results", "closed_form")


def _rank(module: str) -> int | None:
    """The stage of a module (-1: shared; None: the package itself, which re-exports every stage)."""
    top = module.split(".")[1] if "." in module else None
    if top is None:
        return None
    if top in SHARED:
        return -1
    assert top in STAGES, f"{module} is in no stage of the pipeline"
    return STAGES.index(top)


def _imports() -> list[tuple[str, str, int]]:
    """(importing module, imported module, line) for every `from wrsim... import` in the package."""
    out = []
    for file in sorted(PACKAGE.rglob("*.py")):
        parts = file.relative_to(PACKAGE).with_suffix("").parts
        module = ".".join(("wrsim", *parts)).removesuffix(".__init__")
        for node in ast.walk(ast.parse(file.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "wrsim":
                names = [f"wrsim.{a.name}" for a in node.names] if node.module == "wrsim" else [node.module]
                out += [(module, name, node.lineno) for name in names]
    return out


def test_no_module_imports_from_a_later_stage():
    edges = _imports()
    assert len(edges) > 100
    upward = []
    for module, target, line in edges:
        here, there = _rank(module), _rank(target)
        if here is not None and there is not None and there > here:
            upward.append(f"{module} (line {line}) imports {target}")
    assert upward == []
