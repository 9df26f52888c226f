"""Publishing a result folder so that a reader never sees a missing, partial or mixed result, whatever happens to
the writer (an exception, SIGKILL, a full disk, another wrsim run publishing the same bench at the same time).

`root/<name>` is a symbolic link to a version folder `root/.versions/<name>.<stamp>.<pid>.<token>`. A new result is
written into a fresh version folder and published by one atomic rename of a new link onto `root/<name>`; the
previous version is removed after the switch. A failed write removes its own version folder and leaves the link
alone. Leftovers of killed writers (unreferenced versions, temporary links, the hidden `.tmp` folders of older
wrsim versions) are removed by the next publish once their process is gone. Work folders of runs follow the same
naming (`unique_folder`), so concurrent runs never share one."""

from __future__ import annotations

import os
import re
import secrets
import shutil
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from wrsim.errors import WrsimError

__all__ = ["publish_directory", "unique_folder", "clean_stale", "VERSIONS"]

VERSIONS = ".versions"
_OWNER = re.compile(r"\.(\d+)\.[0-9a-f]{8}(\.(tmp|link|old))?$")  # ...<pid>.<token>[.tmp|.link|.old]


def _tag() -> str:
    return f"{time.strftime('%Y%m%d-%H%M%S')}.{os.getpid()}.{secrets.token_hex(4)}"


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _owner_gone(path: Path) -> bool:
    m = _OWNER.search(path.name)
    return m is not None and not _alive(int(m.group(1)))


def clean_stale(root: Path) -> None:
    """Remove what killed writers left in `root`: versions no link points at, temporary links, and the hidden
    `.tmp`/`.old` folders of older wrsim versions, each only once its process is gone."""
    store = root / VERSIONS
    live = {os.path.normpath(root / os.readlink(p)) for p in root.iterdir() if p.is_symlink()}
    candidates = [p for p in store.iterdir()] if store.is_dir() else []
    candidates += [p for p in root.iterdir() if p.name.startswith(".") and p.name != VERSIONS]
    for p in candidates:
        if os.path.normpath(p) in live or not _owner_gone(p):
            continue
        if p.is_symlink() or p.is_file():
            p.unlink(missing_ok=True)
        else:
            shutil.rmtree(p, ignore_errors=True)


@contextmanager
def publish_directory(root: Path, name: str) -> Iterator[Path]:
    """Yield an empty folder; when the block ends normally it becomes `root/name` in one atomic step, else it is
    removed and `root/name` keeps the previous result."""
    root = Path(root)
    try:
        (root / VERSIONS).mkdir(parents=True, exist_ok=True)
        clean_stale(root)
        version = root / VERSIONS / f"{name}.{_tag()}"
        version.mkdir()
    except OSError as e:
        raise WrsimError(f"cannot write results of bench {name} to {root}: {e}") from e
    try:
        yield version
        _switch(root, name, version)
    except BaseException:
        shutil.rmtree(version, ignore_errors=True)
        raise


def _switch(root: Path, name: str, version: Path) -> None:
    target = root / name
    link = root / f".{name}.{_tag()}.link"
    try:
        os.symlink(os.path.relpath(version, root), link)
        if target.is_dir() and not target.is_symlink():  # a result folder of an older wrsim: into the store
            os.rename(target, root / VERSIONS / f"{name}.{_tag()}.old")
        old = os.readlink(target) if target.is_symlink() else None
        os.replace(link, target)  # the one atomic step
    except OSError as e:
        link.unlink(missing_ok=True)
        raise WrsimError(f"cannot publish results of bench {name} in {root}: {e}") from e
    if old is not None and os.path.normpath(root / old) != os.path.normpath(version):
        shutil.rmtree(root / old, ignore_errors=True)


def unique_folder(parent: Path, keep: int = 3) -> Path:
    """A new folder `parent/<stamp>.<pid>.<token>` no other run uses; older ones beyond the newest `keep` are
    removed once their process is gone."""
    parent.mkdir(parents=True, exist_ok=True)
    folder = parent / _tag()
    folder.mkdir()
    runs = sorted((p for p in parent.iterdir() if p.is_dir() and _OWNER.search(p.name)), key=lambda p: p.name)
    for old in runs[:-keep] if keep else runs:
        if old != folder and _owner_gone(old):
            shutil.rmtree(old, ignore_errors=True)
    return folder
