"""CAN side of the window-regulator simulation: switch commands in, ECU status out.

The message layout is ``params/can/window_regulator.dbc`` (comments in the file say what each signal
means): ``WR_SwitchCommand`` (ID 0x1A0, 2 bytes, door switch/body controller -> ECU) carries the
instruction of thesis 4.3.3.2 (0 stop, 1 up, 2 down), a voltage offset, a sequence-end flag and an alive
counter; ``WR_Status`` (ID 0x1A1, 8 bytes, every 10 ms, ECU -> bus) carries glass position, motor state,
pinch event, pinch force and supply voltage.

Switch commands come from a CAN log (``.asc`` or ``.blf``) or from a python-can virtual bus
(``virtual:<channel>``, in the same Python process). The command message is the switch *state*: it is
sent cyclically (100 ms) and on every change, so :func:`read_commands` returns the changes only -- a frame
repeating the previous command and offset is a repetition, not a new unit. On a virtual bus the reader
stops at the frame with ``SequenceEnd = 1``; the sender stamps simulated time on its frames (open its bus
with ``preserve_timestamps=True``). :func:`write_sequence` turns the commands into the switch-sequence
text file of the VHDL switch model (format in docs/switch-sequence.md).

Simulated waveforms become ``WR_Status`` frames with :func:`status_frames` and a log with
:func:`write_log`; :func:`decode_log` decodes a log with the DBC. Every bad input raises WrsimError
naming the file and line (ASC), the frame index and time, or the DBC item.
"""

from __future__ import annotations

import io
import math
import re
import struct
import warnings
import zlib
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TextIO, cast

import can
import cantools
import numpy as np
from can.io.asc import ASC_MESSAGE_REGEX
from can.io.blf import (
    LOG_CONTAINER,
    LOG_CONTAINER_STRUCT,
    OBJ_HEADER_BASE_STRUCT,
    ZLIB_DEFLATE,
    BLFParseError,
)
from cantools.database import Database

from wrsim import paths
from wrsim.data.atomic import read_bytes, read_text, write_bytes_atomic, write_text_atomic
from wrsim.data.units import convert
from wrsim.errors import Loc, SourceError, WrsimError

__all__ = [
    "DBC_PATH",
    "REPLAY_LOG",
    "COMMAND_MESSAGE",
    "STATUS_MESSAGE",
    "REPLAY_SEQUENCE",
    "Command",
    "ClippedWarning",
    "load_dbc",
    "read_commands",
    "command_frames",
    "write_sequence",
    "status_frames",
    "write_log",
    "decode_log",
    "make_replay_log",
]

DBC_PATH = paths.CAN / "window_regulator.dbc"
DBC_LIMIT = 4 << 20  # [bytes] the largest DBC read: a whole vehicle's; cantools takes about 1.2 s and 100 MB a MB
REPLAY_LOG = paths.CAN / "replay_up_down.asc"
COMMAND_MESSAGE = "WR_SwitchCommand"
STATUS_MESSAGE = "WR_Status"

_COMMANDS = {0: "stop", 1: "up", 2: "down"}  # thesis 4.3.3.2
# Signals the code relies on, with the unit of the Python side (None: a coded value without unit).
_LAYOUT = {
    COMMAND_MESSAGE: {"SwitchCommand": None, "SequenceEnd": None, "CommandCounter": None, "VoltageOffset": "V"},
    STATUS_MESSAGE: {
        "WindowPosition": "m",
        "PinchForce": "N",
        "SupplyVoltage": "V",
        "MotorState": None,
        "PinchEvent": None,
        "StatusCounter": None,
    },
}
_COUNTER_MODULO = 16  # 4-bit alive counters
# python-can's own test for "this is a Unix wall-clock time, not a relative one" (1990-01-01).
_WALL_CLOCK = 631152000.0
_VIRTUAL = "virtual:"


@dataclass(frozen=True)
class Command:
    """One time-based switch unit: from `time` [s] on, `command` (0 stop, 1 up, 2 down) with the supply
    raised by `voltage_offset` [V]."""

    time: float
    command: int
    voltage_offset: float = 0.0


#: The committed replay (params/can/replay_up_down.asc): a full up/down cycle of a window whose stroke
#: takes 3.5-4.5 s (thesis 5.3.1): up for 4.9 s, pause, down for 4.5 s, stop.
REPLAY_SEQUENCE = (Command(0.0, 0), Command(0.1, 1), Command(5.0, 0), Command(5.5, 2), Command(10.0, 0))


class ClippedWarning(UserWarning):
    """Samples of a status signal lay outside the DBC range and were clipped to it."""

    def __init__(self, signal: str, count: int, lo: float, hi: float, unit: str):
        super().__init__(
            f"{STATUS_MESSAGE}.{signal}: {count} sample(s) outside the DBC range [{lo:g}, {hi:g}] {unit} clipped"
        )
        self.signal, self.count = signal, count


# ---------------------------------------------------------------------------------------------- DBC


def load_dbc(path: str | Path | None = None) -> Database:
    """Load the message layout (default: the repo's DBC) and check it has the messages, signals and
    units this module uses."""
    path = Path(DBC_PATH if path is None else path)
    text = read_text(path, encoding="cp1252", limit=DBC_LIMIT)  # cantools' encoding of DBC files
    try:
        db = cantools.database.load_string(text, database_format="dbc")
    except (cantools.database.Error, ValueError, KeyError, IndexError, TypeError, AttributeError) as exc:
        # cantools: 'DBC: "<parser message>"'; other exceptions of its parser: their first line
        detail = (str(exc).removeprefix("DBC: ").strip('"').splitlines() or [type(exc).__name__])[0]
        m = re.match(r'Invalid syntax at line (\d+), column (\d+): "(.*)', detail, re.S)
        if m:  # the parser quotes the line and marks the column with >>!<<
            raise SourceError(Loc(str(path), int(m[1]), int(m[2])), f"DBC syntax error: {m[3].strip()}") from exc
        raise WrsimError(f"{path}: not a valid DBC file: {detail}") from exc
    if not isinstance(db, Database):
        raise WrsimError(f"{path}: a diagnostics database, not a CAN DBC")
    _check_layout(db, str(path))
    return db


def _check_layout(db: Database, where: str) -> None:
    for name, signals in _LAYOUT.items():
        try:
            message = db.get_message_by_name(name)
        except KeyError:
            raise WrsimError(f"{where}: no message '{name}' in the DBC") from None
        if not message.cycle_time:
            raise WrsimError(f"{where}: message '{name}' needs a GenMsgCycleTime attribute")
        for signal, unit in signals.items():
            try:
                dbc_unit = message.get_signal_by_name(signal).unit or ""
            except KeyError:
                raise WrsimError(f"{where}: message '{name}' has no signal '{signal}'") from None
            if unit is None and dbc_unit:
                raise WrsimError(
                    f"{where}: signal {name}.{signal} is a coded value; its unit must be empty, not '{dbc_unit}'"
                )
            if unit is not None:
                try:
                    convert(1.0, unit, dbc_unit or "1")
                except WrsimError as exc:
                    raise WrsimError(f"{where}: signal {name}.{signal}: {exc}") from exc


def _db(db: Database | None) -> Database:
    if db is None:
        return load_dbc()
    _check_layout(db, "DBC")
    return db


# ------------------------------------------------------------------------------------ reading frames


@dataclass(frozen=True)
class _Frame:
    where: str  # "file:line: frame i", "file: frame i" or "virtual:ch: frame i"
    msg: can.Message


class _Lines:
    """Lines handed to ASCReader one by one, remembering the number of the line it is on."""

    def __init__(self, lines: list[str]):
        self._lines = iter(lines)
        self.number = 0

    def __iter__(self) -> _Lines:
        return self

    def __next__(self) -> str:
        line = next(self._lines)
        self.number += 1
        return line

    def close(self) -> None:
        """ASCReader closes its file when done; there is nothing to close."""


_ASC_HEADER = re.compile(
    r"(date\s|base\s|(no\s+)?internal\s+events\s+logged|begin\s+triggerblock"
    r"|end\s+triggerblock|//)",
    re.I,
)
_ASC_TIMESTAMPED = re.compile(r"\d+\.\d+\s+(\S+)\s*(\S*)")


def _asc_frame_lines(path: Path, lines: list[str]) -> set[int]:
    """Classify every line of an ASC file; return the numbers of the CAN frame lines. Lines stamped with
    a time whose second field is not a channel number are non-CAN events (start of measurement, system
    variables, J1939, ...) and are ignored; anything else is an error."""
    frames = set()
    for number, raw in enumerate(lines, start=1):
        line = raw.strip()
        if not line or _ASC_HEADER.match(line):
            continue
        m = _ASC_TIMESTAMPED.match(line)
        if m is None:
            raise SourceError(
                Loc(str(path), number, 1), f"not an ASC line (header, comment, event or CAN frame): '{line}'"
            )
        if ASC_MESSAGE_REGEX.match(line):  # exactly the lines python-can parses as frames
            frames.add(number)
        elif m[1].isdigit() and not m[2].endswith(":"):
            raise SourceError(
                Loc(str(path), number, 1),
                f"channel {m[1]}: neither a CAN frame '<id> Rx|Tx d <dlc> <bytes>' nor an event: '{line}'",
            )
    return frames


def _asc_frames(path: Path) -> Iterator[_Frame]:
    lines = read_text(path, "latin-1").splitlines()
    expected = _asc_frame_lines(path, lines)
    source = _Lines(lines)
    seen = set()
    try:
        for index, msg in enumerate(can.ASCReader(cast(TextIO, source))):  # a line iterator is enough
            seen.add(source.number)
            yield _Frame(f"{path}:{source.number}: frame {index}", msg)
    except (ValueError, IndexError) as exc:
        raise SourceError(
            Loc(str(path), source.number, 1), f"malformed CAN frame ({exc}): '{lines[source.number - 1].strip()}'"
        ) from exc
    if expected - seen:
        number = min(expected - seen)
        raise SourceError(
            Loc(str(path), number, 1),
            "CAN frame not read: python-can ends the header at the first line after "
            "the 'date'/'base' lines and drops that line; put 'internal events logged' "
            "(or 'Begin Triggerblock') before the first frame",
        )


BLF_LIMIT = 64 << 20  # [bytes] the largest BLF file read (a switch-command log is kilobytes)


def _blf_objects(path: Path) -> None:
    """Check the object chain of a BLF file before python-can reads it: its reader loops for ever on an object of
    length 0 (the next object starts where this one did). Every object, in the file and inside each log
    container, must hold at least its own header; the file at most BLF_LIMIT bytes."""
    base, container = OBJ_HEADER_BASE_STRUCT.size, LOG_CONTAINER_STRUCT.size
    data = read_bytes(path, BLF_LIMIT)
    pos = struct.unpack_from("<4sL", data)[1] if len(data) >= 8 else len(data)
    inner = bytearray()
    while pos + base <= len(data):
        signature, _, _, size, kind = OBJ_HEADER_BASE_STRUCT.unpack_from(data, pos)
        if pos + size > len(data):
            break  # a truncated file: python-can's reader names it
        if signature != b"LOBJ" or size < base:
            raise WrsimError(f"{path}: malformed BLF file: the object at byte {pos} has length {size}")
        if kind == LOG_CONTAINER and size >= base + container:
            method, _ = LOG_CONTAINER_STRUCT.unpack_from(data, pos + base)
            payload = data[pos + base + container : pos + size]
            try:
                inner += zlib.decompressobj().decompress(payload, BLF_LIMIT) if method == ZLIB_DEFLATE else payload
            except zlib.error as exc:
                raise WrsimError(f"{path}: malformed BLF file: the container at byte {pos}: {exc}") from exc
            if len(inner) > BLF_LIMIT:
                raise WrsimError(f"{path}: BLF file over {BLF_LIMIT >> 20} MB unpacked")
        pos += size + size % 4
    at = 0
    while at + base <= len(inner):
        found = inner.find(b"LOBJ", at, at + 8 + 4)  # objects are padded to 4 bytes (python-can looks 8 ahead)
        if found < 0:
            return  # python-can says what is wrong there
        size = OBJ_HEADER_BASE_STRUCT.unpack_from(inner, found)[3]
        if size < base:
            raise WrsimError(f"{path}: malformed BLF file: an object of length {size} in the log data")
        at = found + size


def _blf_frames(path: Path) -> Iterator[_Frame]:
    index = -1
    try:
        _blf_objects(path)
        with can.BLFReader(path) as reader:
            if path.stat().st_size < reader.file_size:
                raise WrsimError(
                    f"{path}: truncated BLF file: {path.stat().st_size} bytes, the header declares {reader.file_size}"
                )
            for index, msg in enumerate(reader):
                yield _Frame(f"{path}: frame {index}", msg)
    except OSError as exc:
        raise WrsimError(f"{path}: cannot read: {exc.strerror or exc}") from exc
    except (BLFParseError, struct.error, zlib.error) as exc:
        after = f" after frame {index}" if index >= 0 else ""
        raise WrsimError(f"{path}: malformed BLF file{after}: {exc or type(exc).__name__}") from exc


def _log_frames(path: Path) -> Iterator[_Frame]:
    """Every frame of a CAN log, checked for a consistent DLC; error and remote frames skipped."""
    kinds = {".asc": _asc_frames, ".blf": _blf_frames}
    if path.suffix.lower() not in kinds:
        raise WrsimError(
            f"{path}: unsupported CAN log type '{path.suffix}': use .asc or .blf "
            f"(or {_VIRTUAL}<channel> for a virtual bus)"
        )
    for frame in kinds[path.suffix.lower()](path):
        if frame.msg.is_error_frame or frame.msg.is_remote_frame:
            continue
        if len(frame.msg.data) != frame.msg.dlc:
            raise WrsimError(f"{frame.where}: DLC {frame.msg.dlc} but {len(frame.msg.data)} data byte(s)")
        yield frame


def _bus_frames(bus: can.BusABC, name: str, timeout: float) -> Iterator[_Frame]:
    index = 0
    while True:
        msg = bus.recv(timeout)
        if msg is None:
            raise WrsimError(
                f"{name}: no frame for {timeout:g} s after {index} frame(s); the last "
                f"{COMMAND_MESSAGE} frame of a sequence must set SequenceEnd = 1"
            )
        if not (msg.is_error_frame or msg.is_remote_frame):
            yield _Frame(f"{name}: frame {index}", msg)
        index += 1


def _is(msg: can.Message, definition: cantools.database.Message) -> bool:
    return msg.arbitration_id == definition.frame_id and msg.is_extended_id == definition.is_extended_frame


def _decode(frame: _Frame, definition: cantools.database.Message) -> dict[str, int | float]:
    try:
        values = definition.decode(bytes(frame.msg.data), decode_choices=False)
    except cantools.database.DecodeError as exc:
        raise WrsimError(f"{frame.where}: cannot decode {definition.name}: {exc}") from exc
    if not isinstance(values, dict):
        raise WrsimError(f"{frame.where}: {definition.name} is multiplexed; wrsim reads plain frames only")
    return {k: v for k, v in values.items() if isinstance(v, (int, float))}


def _bounds(signal: cantools.database.Signal) -> tuple[float, float]:
    """A signal's DBC range (_check_layout has made sure the DBC gives one)."""
    if signal.minimum is None or signal.maximum is None:
        raise WrsimError(f"DBC signal {signal.name} has no [minimum|maximum] range")
    return signal.minimum, signal.maximum


def _period(definition: cantools.database.Message) -> float:
    """A message's cycle time in s (GenMsgCycleTime)."""
    if definition.cycle_time is None:
        raise WrsimError(f"DBC message {definition.name} has no cycle time (GenMsgCycleTime)")
    return definition.cycle_time / 1000.0


# ---------------------------------------------------------------------------------- switch commands


def _check_unit(where: str, time: float, command: int | float, previous: float | None) -> None:
    """One rule for every switch unit: a finite time >= 0 that rises strictly, a known command."""
    if not math.isfinite(time) or time < 0.0:
        raise WrsimError(f"{where}: time {time:.9g} s must be finite and >= 0")
    if previous is not None and time <= previous:
        raise WrsimError(
            f"{where}: time {time:.9g} s does not increase (previous: {previous:.9g} s); "
            f"switch command times must rise strictly"
        )
    if not isinstance(command, (int, np.integer)) or command not in _COMMANDS:
        raise WrsimError(f"{where} (t = {time:.9g} s): unknown switch command {command!r} (0 stop, 1 up, 2 down)")


def _commands(frames: Iterable[_Frame], db: Database, stop_at_end: bool, name: str) -> list[Command]:
    definition = db.get_message_by_name(COMMAND_MESSAGE)
    offset = definition.get_signal_by_name("VoltageOffset")
    out: list[Command] = []
    previous: float | None = None
    end: str | None = None
    for frame in frames:
        if not _is(frame.msg, definition):
            continue
        t = frame.msg.timestamp
        if end is not None:
            raise WrsimError(
                f"{frame.where} (t = {t:.9g} s): {COMMAND_MESSAGE} after the end-of-sequence frame ({end})"
            )
        if stop_at_end and t >= _WALL_CLOCK:
            raise WrsimError(
                f"{frame.where}: timestamp {t:.9g} s is wall-clock time; the sender must "
                f"stamp simulated time and open its bus with preserve_timestamps=True"
            )
        values = _decode(frame, definition)
        _check_unit(frame.where, t, values["SwitchCommand"], previous)
        low, high = _bounds(offset)
        if not low <= values["VoltageOffset"] <= high:
            raise WrsimError(
                f"{frame.where} (t = {t:.9g} s): voltage offset {values['VoltageOffset']:g} "
                f"{offset.unit} outside the DBC range [{low:g}, {high:g}] {offset.unit}"
            )
        command = Command(t, int(values["SwitchCommand"]), convert(values["VoltageOffset"], offset.unit or "1", "V"))
        if not out or (command.command, command.voltage_offset) != (out[-1].command, out[-1].voltage_offset):
            out.append(command)
        previous = t
        if values["SequenceEnd"]:
            if stop_at_end:
                break
            end = frame.where
    if not out:
        raise WrsimError(f"{name}: no {COMMAND_MESSAGE} frame (ID 0x{definition.frame_id:X})")
    return out


def read_commands(source: str | Path, db: Database | None = None, *, timeout: float = 2.0) -> list[Command]:
    """The switch commands in a CAN log (`.asc`/`.blf`) or on a virtual bus (`"virtual:<channel>"`).

    Only ``WR_SwitchCommand`` frames count (on any channel); other frames are ignored. Frame times must
    rise strictly, commands be 0/1/2 and offsets lie in the DBC range. Consecutive frames with the same
    command and offset are one unit (the message is repeated cyclically). In a log, no command frame
    may follow one with ``SequenceEnd = 1``. A virtual bus is read until the frame with
    ``SequenceEnd = 1``; more than `timeout` seconds without a frame is an error (so is a wall-clock
    timestamp: the sender must stamp simulated time and open its bus with
    ``preserve_timestamps=True``).
    """
    db = _db(db)
    if isinstance(source, str) and source.startswith(_VIRTUAL):
        channel = source[len(_VIRTUAL) :]
        if not channel:
            raise WrsimError(f"'{source}': name the virtual channel, e.g. {_VIRTUAL}switch")
        with can.Bus(interface="virtual", channel=channel) as bus:
            return _commands(_bus_frames(bus, source, timeout), db, True, source)
    path = Path(source)
    return _commands(_log_frames(path), db, False, str(path))


def command_frames(commands: Sequence[Command], db: Database | None = None) -> list[can.Message]:
    """The ``WR_SwitchCommand`` frames a switch sends for `commands`: one at each unit, then every DBC
    cycle time (100 ms) until the next unit; the last unit's frame carries ``SequenceEnd = 1``."""
    db = _db(db)
    definition = db.get_message_by_name(COMMAND_MESSAGE)
    if not commands:
        raise WrsimError("command_frames: empty switch sequence")
    for i, c in enumerate(commands):
        _check_unit(f"command_frames: unit {i}", c.time, c.command, commands[i - 1].time if i else None)
    period = _period(definition)
    unit = definition.get_signal_by_name("VoltageOffset").unit or "1"
    frames: list[can.Message] = []
    for k, c in enumerate(commands):
        last = k == len(commands) - 1
        repeats = 1 if last else math.ceil((commands[k + 1].time - c.time) / period - 1e-6)
        for n in range(repeats):
            values = {
                "SwitchCommand": c.command,
                "SequenceEnd": int(last),
                "CommandCounter": len(frames) % _COUNTER_MODULO,
                "VoltageOffset": convert(c.voltage_offset, "V", unit),
            }
            frames.append(_message(definition, values, round(c.time + n * period, 9), f"command_frames: unit {k}"))
    return frames


def _format_time(t: float) -> str:
    """Seconds with up to 9 decimals and always a decimal point (a VHDL real literal)."""
    text = f"{t:.9f}".rstrip("0")
    return text + "0" if text.endswith(".") else text


def write_sequence(commands: Sequence[Command], path: str | Path, *, strict: bool = False) -> None:
    """Write the switch-sequence file of the VHDL switch model: one ``T <time s> <command>`` line per
    time-based unit (docs/switch-sequence.md); times are written to 1 ns and must rise strictly.

    A time-based unit has no voltage field (thesis 4.3.3.2), so a non-zero voltage offset is written as
    a comment and not applied; with `strict` it is an error instead.
    """
    if not commands:
        raise WrsimError(f"{path}: empty switch sequence")
    out = ["# switch sequence (thesis 4.3.3.2): T <time s> <command: 0 stop, 1 up, 2 down>"]
    previous = None
    for i, c in enumerate(commands):
        time = _format_time(c.time)
        _check_unit(f"{path}: unit {i}", float(time), c.command, previous)
        previous = float(time)
        out.append(f"T {time} {c.command}")
        if c.voltage_offset:
            note = (
                f"voltage offset {c.voltage_offset:+g} V from {time} s not applied: a time-based "
                f"unit has no voltage field"
            )
            if strict:
                raise WrsimError(f"{path}: unit {i}: {note}")
            out.append(f"# {note}")
    write_text_atomic(path, "\n".join(out) + "\n")


# ------------------------------------------------------------------------------------- status frames


def _message(definition: cantools.database.Message, values: dict[str, float], t: float, where: str) -> can.Message:
    try:
        data = definition.encode(values, strict=True)
    except (cantools.database.EncodeError, ValueError) as exc:
        raise WrsimError(f"{where} (t = {t:.9g} s): cannot encode {definition.name}: {exc}") from exc
    return can.Message(
        timestamp=t,
        arbitration_id=definition.frame_id,
        is_extended_id=definition.is_extended_frame,
        data=data,
        is_rx=False,
        channel=0,
    )


def _coded(name: str, values: np.ndarray, t: np.ndarray, allowed: dict[int, str]) -> np.ndarray:
    coded = np.rint(values).astype(int)
    bad = np.flatnonzero(~np.isin(coded, list(allowed)))
    if bad.size:
        k = bad[0]
        meaning = ", ".join(f"{v} {m}" for v, m in allowed.items())
        raise WrsimError(f"{name}: value {values[k]:g} at t = {t[k]:.9g} s is not one of {meaning}")
    return coded


def status_frames(
    time: np.ndarray,
    position: np.ndarray,
    motor_state: np.ndarray,
    pinch: np.ndarray,
    force: np.ndarray,
    supply: np.ndarray,
    period: float | None = None,
    db: Database | None = None,
) -> list[can.Message]:
    """``WR_Status`` frames sampled from simulated waveforms on one time grid.

    `time` [s] rises strictly; `position` glass position [m], `motor_state` 0 stop/1 up/2 down,
    `pinch` 0/1, `force` pinch force [N], `supply` supply voltage [V]. Samples every `period` seconds
    (default: the DBC cycle time, 10 ms) from ``time[0]``: continuous signals interpolated linearly,
    motor state and pinch flag held from the last time point. Values outside a DBC range are clipped to
    it and reported with one :class:`ClippedWarning` per signal.
    """
    db = _db(db)
    definition = db.get_message_by_name(STATUS_MESSAGE)
    period = _period(definition) if period is None else period
    if not (math.isfinite(period) and period > 0.0):
        raise WrsimError(f"status_frames: period {period:g} s must be > 0")
    arrays = {
        "time": time,
        "position": position,
        "motor_state": motor_state,
        "pinch": pinch,
        "force": force,
        "supply": supply,
    }
    arrays = {k: np.asarray(v, dtype=float) for k, v in arrays.items()}
    t = arrays["time"]
    for key, values in arrays.items():
        if values.ndim != 1 or values.shape != t.shape or not values.size:
            raise WrsimError(
                f"status_frames: '{key}' has shape {values.shape}; every waveform must "
                f"be 1-D, non-empty and as long as 'time' {t.shape}"
            )
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise WrsimError(f"status_frames: '{key}' is not finite at sample {bad[0]}")
    falls = np.flatnonzero(np.diff(t) <= 0)
    if falls.size:
        k = falls[0] + 1
        raise WrsimError(f"status_frames: 'time' does not rise at sample {k} ({t[k]:.9g} s after {t[k - 1]:.9g} s)")
    grid = t[0] + period * np.arange(int(math.floor((t[-1] - t[0]) / period + 1e-9)) + 1)
    held = np.searchsorted(t, grid + 1e-9, side="right") - 1
    signals = {
        "WindowPosition": ("m", np.interp(grid, t, arrays["position"])),
        "PinchForce": ("N", np.interp(grid, t, arrays["force"])),
        "SupplyVoltage": ("V", np.interp(grid, t, arrays["supply"])),
    }
    columns = {}
    for name, (unit, values) in signals.items():
        signal = definition.get_signal_by_name(name)
        values = convert(values, unit, signal.unit or "1")
        low, high = _bounds(signal)
        outside = int(np.count_nonzero((values < low) | (values > high)))
        if outside:
            warnings.warn(ClippedWarning(name, outside, low, high, signal.unit or ""), stacklevel=2)
        columns[name] = np.clip(values, low, high)
    columns["MotorState"] = _coded("motor_state", arrays["motor_state"][held], grid, _COMMANDS)
    columns["PinchEvent"] = _coded("pinch", arrays["pinch"][held], grid, {0: "no pinch", 1: "pinch"})
    columns["StatusCounter"] = np.arange(grid.size) % _COUNTER_MODULO
    return [
        _message(definition, {k: v[i].item() for k, v in columns.items()}, float(grid[i]), f"status frame {i}")
        for i in range(grid.size)
    ]


# -------------------------------------------------------------------------------------------- logs


class _Kept(io.BytesIO):
    """An in-memory file that keeps its content when a python-can writer closes it."""

    value = b""

    def close(self) -> None:
        if not self.closed:
            self.value = self.getvalue()
        super().close()


def write_log(messages: Sequence[can.Message], path: str | Path) -> None:
    """Write frames to a CAN log, ``.asc`` or ``.blf`` by suffix, atomically (temporary file in the
    same folder, then os.replace). Timestamps are simulated time [s], >= 0 and non-decreasing; the log's
    time origin is simulated time 0 (python-can would otherwise start it at the first frame)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".asc", ".blf"):
        raise WrsimError(f"{path}: unsupported CAN log type '{path.suffix}': use .asc or .blf")
    previous = 0.0
    for i, msg in enumerate(messages):
        t = msg.timestamp
        if not (math.isfinite(t) and t >= previous):
            raise WrsimError(
                f"{path}: frame {i}: timestamp {t:.9g} s must be finite, >= 0 and not "
                f"before the previous frame ({previous:.9g} s)"
            )
        previous = t
    buffer = _Kept()
    if suffix == ".asc":
        text = io.TextIOWrapper(buffer, encoding="ascii", newline="\n")
        with can.ASCWriter(text) as writer:
            if messages and messages[0].timestamp > 0.0:
                writer.log_event("wrsim: time origin = simulation time 0 s", 0.0)
            for msg in messages:
                writer.on_message_received(msg)
        write_text_atomic(path, buffer.value.decode("ascii"))
        return
    with can.BLFWriter(buffer) as writer:
        writer.start_timestamp = 0.0
        for msg in messages:
            writer.on_message_received(msg)
    write_bytes_atomic(path, buffer.value)


def decode_log(path: str | Path, db: Database | None = None) -> list[dict]:
    """Decode every frame of a CAN log whose ID the DBC knows: ``{"time": s, "message": name,
    "signals": {signal: physical value in the DBC unit}}`` (coded values as numbers). Frames with
    unknown IDs are skipped; a known frame that does not decode is an error."""
    db = _db(db)
    decoded = []
    for frame in _log_frames(Path(path)):
        try:
            definition = db.get_message_by_frame_id(frame.msg.arbitration_id)
        except KeyError:
            continue
        if definition.is_extended_frame != frame.msg.is_extended_id:
            continue
        decoded.append({"time": frame.msg.timestamp, "message": definition.name, "signals": _decode(frame, definition)})
    return decoded


def make_replay_log(path: str | Path = REPLAY_LOG) -> None:
    """Regenerate the committed replay log from :data:`REPLAY_SEQUENCE`."""
    write_log(command_frames(REPLAY_SEQUENCE), path)
