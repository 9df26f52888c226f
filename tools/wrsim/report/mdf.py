"""Bench waveforms as an ASAM MDF 4.10 file, for CANape, INCA and asammdf.

One channel group: the time axis is the master channel, every other signal a float64 channel with its name
and unit. The metadata dict is written to the file header comment (HD comment XML, `common_properties`), and
a file history entry names wrsim as the writing tool; `read_mdf` accepts only files that carry it.
asammdf is imported on first use, so importing this module stays cheap.
"""

from __future__ import annotations

import io
import re
import xml.etree.ElementTree as ET
from importlib import metadata as _dist
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from wrsim.data.atomic import write_bytes_atomic
from wrsim.errors import WrsimError

if TYPE_CHECKING:
    import asammdf

    from wrsim.results import Signal

__all__ = ["MDF_VERSION", "write_mdf", "read_mdf"]

MDF_VERSION = "4.10"
TOOL_ID = "wrsim"  # <tool_id> of the file history entry that marks a file wrsim wrote

_CHANNEL_TYPE_MASTER = 2  # MDF4 CN block cn_type of a master channel

# Characters a metadata value may hold: those an XML 1.0 document can carry, less the line breaks other than
# "\n" (asammdf re-indents the comment XML line by line, so "\r", NEL, LS and PS would not come back as they
# were). Keys are XML attributes and hold no tab or line break either.
_BAD_VALUE_CHAR = re.compile("[^\t\n\x20-\x84\x86-\u2027\u202a-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")
_BAD_KEY_CHAR = re.compile("[^\x20-\x84\x86-\u2027\u202a-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")


def write_mdf(path: Path, waveforms: list[Signal], metadata: dict[str, str]) -> None:
    """Write `waveforms` (``waveforms[0]`` is the time axis ``time`` in ``s``) and `metadata` to the MDF4
    file `path`. The file is built in memory and written atomically (a temporary file in the same directory,
    then os.replace), so `path` is either the complete old file or the complete new one.

    Each metadata entry is a ``<e name="key">`` element of the header comment's ``common_properties`` (a
    value with line breaks a ``<tree name="key">`` of its lines), so keys such as ``author``, ``project``
    or ``subject`` show up as the standard header fields; ``metadata["description"]`` is also the header
    comment text. WrsimError naming `path` if the waveforms or metadata cannot be stored or the file cannot
    be written.
    """
    path = Path(path)
    columns = _columns(path, waveforms)
    comment = _header_comment(path, metadata)

    import asammdf
    from asammdf.blocks.v4_blocks import FileHistory

    mdf = asammdf.MDF(version=MDF_VERSION)
    try:
        mdf.header.comment = comment
        history = FileHistory()
        history.comment = _history_comment()
        mdf.file_history.append(history)
        time = columns[0]
        if len(waveforms) > 1:
            mdf.append(
                [
                    asammdf.Signal(values, time, name=s.name, unit=s.unit)
                    for s, values in zip(waveforms[1:], columns[1:])
                ],
                common_timebase=True,
            )
        else:  # a channel group with the master channel alone
            import pandas as pd

            mdf.append(pd.DataFrame(index=pd.Index(time, name=waveforms[0].name)))
        data = _mdf_bytes(mdf)
    finally:
        mdf.close()
    write_bytes_atomic(path, data)


def read_mdf(path: Path) -> tuple[list[Signal], dict[str, str]]:
    """The waveforms (time axis first) and metadata of an MDF4 file written by `write_mdf`. WrsimError naming
    `path` if it cannot be read or is not such a file."""
    path = Path(path)
    import asammdf

    from wrsim.results import Signal

    try:
        mdf = asammdf.MDF(path)
    except Exception as exc:  # asammdf raises a variety of types for unreadable or foreign files
        raise WrsimError(f"{path}: cannot read MDF file: {_reason(exc)}") from exc
    with mdf:
        if not str(mdf.version).startswith("4."):
            raise WrsimError(f"{path}: MDF version {mdf.version}, not an MDF4 file written by wrsim")
        if not any(_tool_id(fh.comment) == TOOL_ID for fh in mdf.file_history):
            raise WrsimError(f"{path}: not an MDF file written by wrsim (no wrsim file history entry)")
        if not mdf.groups:  # asammdf writes no channel group for a time axis without samples
            return [Signal("time", "s", np.zeros(0))], _parse_header_comment(path, mdf.header.comment)
        if len(mdf.groups) != 1:
            raise WrsimError(f"{path}: {len(mdf.groups)} channel groups, a wrsim MDF file has exactly one")
        channels = mdf.groups[0].channels
        master = channels[0] if channels else None
        if master is None or master.channel_type != _CHANNEL_TYPE_MASTER:
            raise WrsimError(f"{path}: the first channel is not the master (time) channel")
        try:
            time = np.asarray(mdf.get_master(0), dtype=np.float64)
            waveforms = [Signal(master.name, master.unit, time)]
            # one select: a single pass over the compressed data, not one per channel
            selected = mdf.select([(None, 0, index) for index in range(1, len(channels))]) if channels[1:] else []
            for channel in selected:
                if channel.samples.dtype.kind != "f":
                    raise WrsimError(
                        f"{path}: channel {channel.name!r} holds {channel.samples.dtype} samples, not floating point"
                    )
                waveforms.append(Signal(channel.name, channel.unit, np.asarray(channel.samples, np.float64)))
            metadata = _parse_header_comment(path, mdf.header.comment)
        except WrsimError:
            raise
        except Exception as exc:  # a damaged data block, a foreign layout
            raise WrsimError(f"{path}: cannot read MDF file: {_reason(exc)}") from exc
    return waveforms, metadata


def _columns(path: Path, waveforms: list[Signal]) -> list[np.ndarray]:
    """The waveforms' values as 1-D float64 arrays of one length; WrsimError unless they are."""
    if not waveforms or (waveforms[0].name, waveforms[0].unit) != ("time", "s"):
        raise WrsimError(f"{path}: the first waveform must be the time axis time[s]")
    columns = []
    for s in waveforms:
        try:
            values = np.asarray(s.values, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise WrsimError(f"{path}: signal {s.name!r} is not numeric: {exc}") from exc
        if values.ndim != 1:
            raise WrsimError(f"{path}: signal {s.name!r} is {values.ndim}-dimensional, not a 1-D series")
        if len(values) != len(waveforms[0].values):
            raise WrsimError(
                f"{path}: signal {s.name!r} has {len(values)} values, the time axis {len(waveforms[0].values)}"
            )
        columns.append(values)
    return columns


def _header_comment(path: Path, metadata: dict[str, str]) -> str:
    """The HD comment XML holding `metadata`; WrsimError naming the entry if a key or value cannot be stored."""
    root = ET.Element("HDcomment")
    ET.SubElement(root, "TX").text = metadata.get("description", "")
    common = ET.SubElement(root, "common_properties")
    for key, value in metadata.items():
        if not isinstance(key, str) or not key or _BAD_KEY_CHAR.search(key):
            raise WrsimError(f"{path}: metadata key {key!r} must be a non-empty single-line string")
        if not isinstance(value, str):
            raise WrsimError(f"{path}: metadata {key!r} must be a string, got {type(value).__name__}")
        bad = _BAD_VALUE_CHAR.search(value)
        if bad:
            raise WrsimError(
                f"{path}: metadata {key!r} contains the character U+{ord(bad[0]):04X}, "
                "which an MDF4 header comment cannot hold"
            )
        if "\n" in value:
            tree = ET.SubElement(common, "tree", name=key)
            for number, line in enumerate(value.split("\n"), start=1):
                ET.SubElement(tree, "e", name=str(number)).text = line
        else:
            ET.SubElement(common, "e", name=key).text = value
    return ET.tostring(root, encoding="unicode")


def _parse_header_comment(path: Path, comment: str) -> dict[str, str]:
    """The metadata dict of an HD comment written by `_header_comment`."""
    try:
        root = _parse_xml(comment)
    except ET.ParseError as exc:
        raise WrsimError(f"{path}: the file header comment is not valid XML: {exc}") from exc
    metadata: dict[str, str] = {}
    for element in root.iterfind("common_properties/*"):
        name = element.get("name")
        if name is None:
            continue
        if element.tag == "e":
            metadata[name] = element.text or ""
        elif element.tag == "tree":
            metadata[name] = "\n".join(line.text or "" for line in element.iterfind("e"))
    return metadata


def _history_comment() -> str:
    """The FH comment XML naming wrsim (and its version) as the tool that wrote the file."""
    try:
        version = _dist.version("wrsim")
    except _dist.PackageNotFoundError:
        version = "unknown"
    root = ET.Element("FHcomment")
    ET.SubElement(root, "TX").text = "created"
    ET.SubElement(root, "tool_id").text = TOOL_ID
    ET.SubElement(root, "tool_vendor").text = "wrsim"
    ET.SubElement(root, "tool_version").text = version
    return ET.tostring(root, encoding="unicode")


def _tool_id(history_comment: str) -> str | None:
    """The <tool_id> of a file history comment, None if it has none."""
    try:
        root = _parse_xml(history_comment)
    except ET.ParseError:
        return None
    return root.findtext("tool_id")


def _parse_xml(text: str) -> ET.Element:
    """An MDF4 comment XML element, without the ASAM default namespace other tools may declare."""
    return ET.fromstring(re.sub(r"""\sxmlns=["'][^"']*["']""", "", text, count=1))


def _mdf_bytes(mdf: asammdf.MDF) -> bytes:
    """The MDF file `mdf` saved with transposed deflate compression."""
    from asammdf.blocks.v4_constants import CompressionAlgorithm

    buffer = io.BytesIO()  # transposed deflate: the best compression MDF 4.10 offers
    mdf.save(buffer, compression=CompressionAlgorithm.TRANSPOSED_DEFLATE, add_history_block=False)
    return buffer.getvalue()


def _reason(exc: BaseException) -> str:
    """A one-line account of `exc` for a message."""
    if isinstance(exc, OSError) and exc.strerror:
        return exc.strerror
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__
