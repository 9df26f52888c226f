"""Safe file access. Atomic writes: a file is replaced as a whole or not at all (temporary file in the same folder,
fsync, rename), so a reader never sees it half-written and a failed write keeps the previous content. Bounded
reads of input text files: regular files only (a FIFO would block, /dev/zero never end), at most INPUT_LIMIT; the
files a design reads line by line (VHDL textio) also with lines of at most LINE_LIMIT characters."""

from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path

from wrsim.errors import WrsimError

__all__ = [
    "write_text_atomic",
    "write_bytes_atomic",
    "read_bytes",
    "read_text",
    "check_lines",
    "INPUT_LIMIT",
    "LINE_LIMIT",
]

INPUT_LIMIT = 64 << 20  # [bytes] the largest input text file (parameter sets, measurement tables, CAN logs)
LINE_LIMIT = 4096  # [characters] the longest line of a file a design reads with textio (GHDL's readline and
# read copy the rest of a line per call: a 10 MB switch-sequence line kept the digital unit busy for minutes)


def read_bytes(path: Path, limit: int = INPUT_LIMIT) -> bytes:
    """The content of the input file `path`; one WrsimError naming it when it cannot be read, is not a regular
    file or is larger than `limit` bytes."""
    try:
        if not stat.S_ISREG(path.stat().st_mode):  # before opening: opening a FIFO blocks
            raise WrsimError(f"{path}: not a regular file")
        with path.open("rb") as f:
            data = f.read(limit + 1)
    except OSError as exc:
        raise WrsimError(f"{path}: cannot read: {exc.strerror or exc}") from exc
    if len(data) > limit:
        raise WrsimError(f"{path}: larger than {limit >> 20} MB, the limit for an input file of this kind")
    return data


def read_text(path: Path, encoding: str = "utf-8-sig", limit: int = INPUT_LIMIT) -> str:
    """The text of the input file `path`; one WrsimError naming it when read_bytes refuses it or it is not text in
    `encoding`."""
    data = read_bytes(path, limit)
    try:
        return data.decode(encoding)
    except UnicodeDecodeError as exc:
        raise WrsimError(f"{path}: not a {encoding.removesuffix('-sig').upper()} text file ({exc.reason})") from exc


def check_lines(path: Path, limit: int = LINE_LIMIT) -> None:
    """One WrsimError naming `path` (and the line) when it is not an input text file read_text accepts or has a
    line longer than `limit` characters."""
    for number, line in enumerate(read_text(path).splitlines(), start=1):
        if len(line) > limit:
            raise WrsimError(f"{path}:{number}: a line of {len(line)} characters, more than the {limit} allowed")


def _file_mode(path: Path) -> int:
    """Mode for a rewritten file: the old file's, else what open() would give (0o666 & ~umask)."""
    if path.exists():
        return path.stat().st_mode & 0o777
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def write_bytes_atomic(path: str | Path, data: bytes) -> None:
    """Write `data` to `path` through a temporary file in the same directory and os.replace, so a reader
    sees the old file or the new one, never a half-written one."""
    path = Path(path)
    tmp_name = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(
            "wb", dir=path.parent, delete=False, prefix=f".{path.name}.", suffix=".tmp"
        ) as tmp:
            tmp_name = tmp.name
            tmp.write(data)
        os.chmod(tmp_name, _file_mode(path))
        os.replace(tmp_name, path)
    except OSError as exc:
        if tmp_name is not None and os.path.exists(tmp_name):
            os.unlink(tmp_name)
        raise WrsimError(f"{path}: cannot write: {exc.strerror or exc}") from exc


def write_text_atomic(path: str | Path, text: str) -> None:
    """Write `text` (UTF-8) atomically, as write_bytes_atomic."""
    write_bytes_atomic(path, text.encode("utf-8"))
