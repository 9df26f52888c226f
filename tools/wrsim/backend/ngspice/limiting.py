"""Newton limiting of the compiled device (wrsim.backend.ngspice.osdi): the piecewise laws' edges of each unknown
and the C that limits an iterate cycling over them.

A piecewise law with a narrow middle region (a friction law's band, |omega| < omega_threshold with its steep
slope inside) makes Newton cycle: the linearisation on one side of the band lands on the other side and back, for
as many iterations as ngspice allows, and then the step is cut (the cable drum at a start from rest under load;
docs/performance.md, "Where the pinch bench's Newton iterations go"). SPICE's own devices limit such iterates (a
junction's voltage step); this is the same for any unknown that a condition of the equations compares with a
value independent of the unknowns."""

from __future__ import annotations

from wrsim.elab import symbolic as sy
from wrsim.elab.symbolic import S

__all__ = ["C_HELPERS", "edges"]

C_HELPERS = """\
/* Newton limiting over piecewise laws: where the iterates of an unknown cycle over a whole region of the conditions
   on it (both edges of a friction band: from `older` to `old` across the band one way, from `old` to *v back across
   it), *v is put just inside the first region it enters, 1e-3 of that region's width past its edge, and the device
   asks for another iteration. Only a cycle is limited, so a time point that converges is left as it was. */
static int wrsim_crossed(double a, double b, const double *edge, int d) {
    int n = 0;
    for (int i = 0; i < d; i++) n += edge[i] > fmin(a, b) && edge[i] < fmax(a, b);
    return n;
}
static uint32_t wrsim_limit(double *v, double old, double older, double *edge, int m) {
    if (isnan(old) || isnan(older) || isnan(*v) || (*v - old) * (old - older) >= 0.0) return 0;
    for (int i = 1; i < m; i++)
        for (int j = i; j > 0 && edge[j - 1] > edge[j]; j--) {
            double e = edge[j];
            edge[j] = edge[j - 1], edge[j - 1] = e;
        }
    int d = 0; /* distinct edges */
    for (int i = 0; i < m; i++) if (d == 0 || edge[i] > edge[d - 1]) edge[d++] = edge[i];
    if (wrsim_crossed(old, *v, edge, d) < 2 || wrsim_crossed(older, old, edge, d) < 2) return 0;
    if (*v > old) {
        int i = 0;
        while (edge[i] <= old) i++;
        *v = edge[i] + 1e-3 * (edge[i + 1] - edge[i]);
    } else {
        int i = d - 1;
        while (edge[i] >= old) i--;
        *v = edge[i] - 1e-3 * (edge[i] - edge[i - 1]);
    }
    return 1;
}
"""


def edges(expressions: list[S], index: dict[str, int]) -> dict[int, list[S]]:
    """For every unknown (its index in `index`) that a condition of `expressions` compares with a value independent
    of the unknowns and of time (a relation `q > e` or `e < q` of a node against a constant or a generic), those
    values: the edges of its piecewise laws."""
    out: dict[int, list[S]] = {}
    seen: set[int] = set()
    stack = list(expressions)
    while stack:
        s = stack.pop()
        if id(s) in seen:
            continue
        seen.add(id(s))
        if isinstance(s, sy.Op) and s.name in ("<", "<=", ">", ">=") and len(s.args) == 2:
            for q, e in (s.args, s.args[::-1]):
                node = q.name if isinstance(q, sy.Node) else q.plus if isinstance(q, sy.Diff) and q.minus == "0" else ""
                if node in index and not sy.nodes_of(e) and not any(isinstance(x, sy.Time) for x in sy.walk(e)):
                    out.setdefault(index[node], []).append(e)
        if isinstance(s, (sy.Op, sy.Fn)):
            stack += s.args
        elif isinstance(s, sy.Cond):
            stack += [s.test, s.then, s.other]
    return out
