"""A bench's parameter set as VHDL packages (`wrsim export`): the set a bench or a user's sets give, written by
backend.export, with the top-level generics of the bench's runs in the header."""

from __future__ import annotations

import shutil
from collections.abc import Sequence
from pathlib import Path

from wrsim import paths
from wrsim.benches import select_benches
from wrsim.benches.core import Run, bench_params, run_params
from wrsim.elab.library import Library, load_library
from wrsim.errors import WrsimError

__all__ = ["export_set"]


def export_set(
    user: str | Path | Sequence[str | Path] | None, bench: str | None, out: Path, lib: Library | None = None
) -> list:
    """Write the parameter set of `user`'s sets laid in order (over bench `bench`'s own set when a bench is given)
    as the VHDL packages wr_params and wr_digital_params into `out` (backend.export); with a bench whose runs use
    different sets, one folder per run under `out`. The header says which simulator top and top-level generics
    each run has. Returns the backend's ExportedFile list."""
    from wrsim.backend.export import export_params

    user = [user] if isinstance(user, (str, Path)) else list(user or ())
    if not user and bench is None:
        raise WrsimError("export: give --params SET, --bench BENCH or both")
    lib = lib or load_library(paths.LIBRARY)
    b = select_benches([bench])[0] if bench else None
    given = bench_params(b, user)
    assert given is not None
    command = "wrsim export" + "".join(f" --params {u}" for u in user) + (f" --bench {bench}" if bench else "")
    ambient = given.sections.get("ambient", {}).get("temperature")
    where = f" at {given.number_in('ambient', 'temperature', 'degC'):g} degC" if ambient else ""
    header = [
        f"parameter set {given.name}{where} as VHDL, written by `{command}`; do not edit.",
        "Lines marked `set:` carry the set's values, in the unit the generic declares; the others keep the "
        "library's defaults.",
    ]
    if b is None:
        pset = run_params(None, user)
        assert pset is not None
        return export_params(lib, pset, out, header)
    runs = [(run, run.parameters(given) or given) for run in b.runs]
    shared = all(run.params == runs[0][0].params for run, _ in runs)
    written = []
    for run, pset in runs[:1] if shared else runs:
        told = [r for r, _ in runs] if shared else [run]
        lines = [
            f"Bench {b.name}: simulate entity {b.entity} for {b.stop:g} s; top-level generics of the run"
            f"{'s' if len(told) > 1 else ''} (files: copied beside this one, paths relative to it):"
        ]
        lines += [f"  {r.label}: " + (_generics(r, out) or "the defaults") for r in told]
        written += export_params(lib, pset, out if shared else out / run.label, header + lines)
    return written


def _generics(run: Run, out: Path) -> str:
    """A run's top-level generics as the simulator takes them (`Run.resolved`, the files it makes put into
    `out`/files/<run>); a file a generic names is copied there too, and named relative to `out`."""
    from wrsim.backend.export import vhdl_literal

    files = out / "files" / run.label
    if any(callable(v) for v in run.generics.values()):
        files.mkdir(parents=True, exist_ok=True)
    shown = []
    for name, value in run.resolved(files).items():
        if isinstance(value, str) and Path(value).is_file():
            if Path(value).resolve().parent != files.resolve():
                files.mkdir(parents=True, exist_ok=True)
                value = str(shutil.copyfile(value, files / Path(value).name))
            value = str(Path(value).resolve().relative_to(out.resolve()))
        text = (
            f'"{value}"'
            if isinstance(value, str)
            else str(value)
            if isinstance(value, int)
            else vhdl_literal(float(value), "real")
        )
        shown.append(f"{name} => {text}")
    return ", ".join(shown)
