"""The pairing pass: the 1076.1 equation count of an architecture, and the structural pairing of each
equation with the unknown whose node carries it (maximum bipartite matching)."""

from __future__ import annotations

from wrsim.elab.design import ArchModel
from wrsim.errors import SourceError

__all__ = ["pair_model", "pair_equations"]


def pair_model(m: ArchModel) -> None:
    """Raise SourceError unless `m` (an ArchModel) is square and structurally solvable; pairs equations."""
    unknowns = list(m.unknowns)
    where = f"architecture {m.arch.name} of {m.entity.name}"
    if len(m.equations) != len(unknowns):
        listing = ", ".join(unknowns) or "none"
        raise SourceError(
            m.arch.loc,
            f"{where}: {len(m.equations)} simultaneous statement(s) for "
            f"{len(unknowns)} unknown(s) ({listing}); 1076.1 requires one equation per "
            f"through quantity, free quantity and out quantity port",
        )
    pairing = pair_equations([eq.unknowns for eq in m.equations], unknowns)
    if isinstance(pairing, tuple):
        eqs, left = pairing
        lines = "; ".join(f"{m.equations[k].loc}" for k in eqs)
        raise SourceError(
            m.arch.loc,
            f"{where} is structurally singular: the equations at {lines} compete for "
            f"the same unknowns, and {', '.join(left)} is determined by none",
        )
    for eq, name in zip(m.equations, pairing):
        eq.paired = name


def pair_equations(involved: list[set[str]], unknowns: list[str]) -> list[str] | tuple[list[int], list[str]]:
    """Maximum bipartite matching (augmenting paths). Returns the unknown paired with each equation, or
    (equations in the deficient set, unknowns left unpaired) when no perfect matching exists."""
    owner: dict[str, int] = {}

    def augment(k: int, seen: set[str]) -> bool:
        for u in sorted(involved[k]):
            if u in seen:
                continue
            seen.add(u)
            if u not in owner or augment(owner[u], seen):
                owner[u] = k
                return True
        return False

    deficient: list[int] = []
    for k in range(len(involved)):
        seen: set[str] = set()
        if not augment(k, seen) and not deficient:
            deficient = sorted({k} | {owner[u] for u in seen if u in owner})
    if deficient:
        return deficient, [u for u in unknowns if u not in owner]
    by_eq = {k: u for u, k in owner.items()}
    return [by_eq[k] for k in range(len(involved))]
