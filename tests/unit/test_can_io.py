"""CAN side of issue 5: the DBC layout, switch commands from ASC/BLF logs and a virtual bus, the switch
sequence file, ECU status frames, log round trips and every bad-input message."""

from __future__ import annotations

import os
import re
import struct
import threading
import time
import warnings
from pathlib import Path

import can
import numpy as np
import pytest
from can.interfaces.virtual import channels as virtual_channels

from wrsim.data.can import (
    DBC_PATH,
    REPLAY_LOG,
    REPLAY_SEQUENCE,
    ClippedWarning,
    Command,
    command_frames,
    decode_log,
    load_dbc,
    make_replay_log,
    read_commands,
    status_frames,
    write_log,
    write_sequence,
)
from wrsim.errors import SourceError, WrsimError

DB = load_dbc()
# Starts after 0 (the log's time origin must stay at simulated time 0) and carries voltage offsets.
SEQUENCE = [Command(0.25, 1, 0.0), Command(1.0, 0, 0.0), Command(1.3, 2, 2.0), Command(2.05, 0, -1.5)]


def same_commands(got: list[Command], want: list[Command]) -> None:
    assert [c.command for c in got] == [c.command for c in want]
    assert [c.time for c in got] == pytest.approx([c.time for c in want], abs=1e-6)
    assert [c.voltage_offset for c in got] == pytest.approx([c.voltage_offset for c in want], abs=1e-9)


def command_frame(t: float, command: int, offset: float = 0.0, end: int = 0) -> can.Message:
    """One WR_SwitchCommand frame; `command` may be 3 (fits the 2-bit field, is no command)."""
    data = DB.encode_message(
        "WR_SwitchCommand",
        {"SwitchCommand": command, "SequenceEnd": end, "CommandCounter": 0, "VoltageOffset": offset},
        strict=False,
    )
    return can.Message(timestamp=t, arbitration_id=0x1A0, is_extended_id=False, data=data, channel=0)


def asc(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "log.asc"
    path.write_text(
        "date Mon Jan 01 00:00:00.000 2024\nbase hex  timestamps absolute\n"
        "internal events logged\nBegin Triggerblock Mon Jan 01 00:00:00.000 2024\n" + body + "End TriggerBlock\n"
    )
    return path


# ---------------------------------------------------------------------------------------- the DBC


def test_dbc_layout():
    command, status = DB.get_message_by_name("WR_SwitchCommand"), DB.get_message_by_name("WR_Status")
    assert (command.frame_id, command.length, command.cycle_time, command.senders) == (0x1A0, 2, 100, ["BCM"])
    assert (status.frame_id, status.length, status.cycle_time, status.senders) == (0x1A1, 8, 10, ["WR_ECU"])
    assert not command.is_extended_frame and not status.is_extended_frame
    assert command.get_signal_by_name("SwitchCommand").choices == {0: "Stop", 1: "Up", 2: "Down"}
    offset = command.get_signal_by_name("VoltageOffset")
    assert (offset.is_signed, offset.scale, offset.minimum, offset.maximum, offset.unit) == (True, 0.1, -8, 8, "V")
    units = {s.name: (s.scale, s.unit) for s in status.signals}
    assert units["WindowPosition"] == (0.1, "mm") and units["PinchForce"] == (0.1, "N")
    assert units["SupplyVoltage"] == (0.1, "V") and units["MotorState"] == (1, None)
    assert all(s.comment for m in DB.messages for s in m.signals)  # the DBC documents every signal


def test_malformed_dbc_names_file_line_and_column(tmp_path):
    text = DBC_PATH.read_text()
    bad = tmp_path / "bad.dbc"
    bad.write_text(text.replace("SG_ PinchForce : 16|16@1+", "SG_ PinchForce : 16|16@1+ garbage"))
    line = next(i for i, l in enumerate(bad.read_text().splitlines(), 1) if "garbage" in l)
    with pytest.raises(SourceError, match=rf"^{re.escape(str(bad))}:{line}:28: DBC syntax error: .*garbage"):
        load_dbc(bad)
    bad.write_text(text.replace(" SG_ SupplyVoltage : 32|8", " SG_ SupplyVoltage : 30|8"))
    with pytest.raises(
        WrsimError,
        match=r"bad.dbc: not a valid DBC file: The signals SupplyVoltage and "
        r"PinchForce are overlapping in message WR_Status",
    ):
        load_dbc(bad)


def test_a_dbc_is_read_within_bounds(tmp_path):
    """A 200,000-line DBC took 15 s and 0.75 GB of cantools; a FIFO would block: one error naming the file."""
    big = tmp_path / "big.dbc"
    big.write_text(DBC_PATH.read_text() + "\n" * (4 << 20))
    with pytest.raises(WrsimError, match=r"big\.dbc: larger than 4 MB, the limit for an input file of this kind"):
        load_dbc(big)
    os.mkfifo(tmp_path / "fifo.dbc")
    with pytest.raises(WrsimError, match=r"fifo\.dbc: not a regular file"):
        load_dbc(tmp_path / "fifo.dbc")


def test_dbc_missing_item_or_wrong_unit_is_named(tmp_path):
    text = DBC_PATH.read_text()
    bad = tmp_path / "bad.dbc"
    bad.write_text(text.replace("PinchForce", "ClampForce"))
    with pytest.raises(WrsimError, match=r"bad.dbc: message 'WR_Status' has no signal 'PinchForce'"):
        load_dbc(bad)
    bad.write_text(text.replace('[-200|1500] "mm"', '[-200|1500] "s"'))
    with pytest.raises(WrsimError, match=r"bad.dbc: signal WR_Status.WindowPosition: cannot convert 'm'"):
        load_dbc(bad)
    with pytest.raises(WrsimError, match=r"missing.dbc: cannot read"):
        load_dbc(tmp_path / "missing.dbc")


# ------------------------------------------------------------------------ commands: logs and the bus


@pytest.mark.parametrize("suffix", [".asc", ".blf"])
def test_command_log_round_trip(tmp_path, suffix):
    frames = command_frames(SEQUENCE)
    # one frame per unit, then every 100 ms until the next unit; SequenceEnd only on the last frame
    assert [round(f.timestamp, 6) for f in frames[:4]] == [0.25, 0.35, 0.45, 0.55]
    assert len(frames) == 8 + 3 + 8 + 1
    path = tmp_path / f"cmd{suffix}"
    write_log(frames, path)
    same_commands(read_commands(path), SEQUENCE)
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temp file left behind


def test_other_frames_are_ignored_and_decode_log_reads_all(tmp_path):
    t = np.array([0.0, 0.5])
    status = status_frames(t, [0.1, 0.2], [1, 1], [0, 0], [0.0, 0.0], [13.0, 13.0], period=0.25)
    commands = command_frames([Command(0.0, 0), Command(0.3, 1)])
    foreign = can.Message(timestamp=0.1, arbitration_id=0x7FF, data=[1, 2, 3], is_extended_id=False)
    mixed = sorted([*status, *commands, foreign], key=lambda m: m.timestamp)
    path = tmp_path / "mixed.asc"
    write_log(mixed, path)
    same_commands(read_commands(path), [Command(0.0, 0), Command(0.3, 1)])
    decoded = decode_log(path)
    assert [d["message"] for d in decoded].count("WR_Status") == 3
    assert [d["message"] for d in decoded].count("WR_SwitchCommand") == len(commands)
    assert len(decoded) == len(mixed) - 1  # the unknown ID is skipped


def send_when_listened(channel: str, frames: list[can.Message], preserve: bool = True) -> threading.Thread:
    """Send `frames` on a virtual channel as soon as a second bus (the reader) has joined it."""
    sender = can.Bus(interface="virtual", channel=channel, preserve_timestamps=preserve)

    def run() -> None:
        with sender:
            deadline = time.monotonic() + 10.0
            while len(virtual_channels[channel]) < 2 and time.monotonic() < deadline:
                time.sleep(0.001)
            for frame in frames:
                sender.send(frame)

    thread = threading.Thread(target=run)
    thread.start()
    return thread


def test_virtual_bus_round_trip_stops_at_sequence_end():
    frames = command_frames(SEQUENCE)
    trailing = command_frame(3.0, 1)  # after SequenceEnd: not read
    thread = send_when_listened("wrsim-test-round-trip", [*frames, trailing])
    got = read_commands("virtual:wrsim-test-round-trip", timeout=5.0)
    thread.join()
    same_commands(got, SEQUENCE)


def test_virtual_bus_errors():
    with pytest.raises(
        WrsimError,
        match=r"virtual:wrsim-test-silent: no frame for 0.05 s after 0 frame\(s\); "
        r"the last WR_SwitchCommand frame of a sequence must set SequenceEnd = 1",
    ):
        read_commands("virtual:wrsim-test-silent", timeout=0.05)
    thread = send_when_listened("wrsim-test-wall", command_frames(SEQUENCE), preserve=False)
    with pytest.raises(
        WrsimError,
        match=r"virtual:wrsim-test-wall: frame 0: timestamp .* is wall-clock time; "
        r".*preserve_timestamps=True",
    ):
        read_commands("virtual:wrsim-test-wall", timeout=5.0)
    thread.join()
    with pytest.raises(WrsimError, match=r"name the virtual channel"):
        read_commands("virtual:")


# ------------------------------------------------------------------------ commands: bad input


def test_garbage_asc_line_is_named(tmp_path):
    path = asc(tmp_path, " 0.000000 Start of measurement\n 0.100000 1  1A0  Rx   d 2 01 00\nhello world\n")
    with pytest.raises(SourceError, match=rf"^{re.escape(str(path))}:7:1: not an ASC line .*'hello world'"):
        read_commands(path)
    path = asc(tmp_path, " 0.100000 1  garbage\n")
    with pytest.raises(SourceError, match=r"log.asc:5:1: channel 1: neither a CAN frame"):
        read_commands(path)
    path = asc(tmp_path, " 0.100000 1  1A0  Rx   d 2 01 0Z\n")
    with pytest.raises(SourceError, match=r"log.asc:5:1: malformed CAN frame \(invalid literal .*'0Z'\)"):
        read_commands(path)
    path = asc(tmp_path, " 0.100000 1  1A0  Rx   d 2 01\n")
    with pytest.raises(WrsimError, match=r"log.asc:5: frame 0: DLC 2 but 1 data byte\(s\)"):
        read_commands(path)


def test_asc_events_and_statistics_are_not_errors(tmp_path):
    path = asc(
        tmp_path,
        " 0.000000 Start of measurement\n// a comment\n 0.050000 1  Statistic: D 0 R 0\n"
        " 0.060000 CAN 1 Status:chip status error active\n 0.100000 1  1A0  Rx   d 2 01 00\n"
        " 0.150000 1  ErrorFrame\n",
    )
    same_commands(read_commands(path), [Command(0.1, 1)])


def test_asc_frame_swallowed_by_python_can_header_parsing_is_reported(tmp_path):
    path = tmp_path / "bare.asc"
    path.write_text(" 0.100000 1  1A0  Rx   d 2 01 00\n 0.200000 1  1A0  Rx   d 2 02 00\n")
    with pytest.raises(SourceError, match=r"bare.asc:1:1: CAN frame not read"):
        read_commands(path)


def test_malformed_blf_is_named(tmp_path):
    path = tmp_path / "bad.blf"
    path.write_text("not a binary log\n" * 20)
    with pytest.raises(WrsimError, match=r"bad.blf: malformed BLF file: Unexpected file format"):
        read_commands(path)
    write_log(command_frames(SEQUENCE), path)
    path.write_bytes(path.read_bytes()[:-40])
    with pytest.raises(WrsimError, match=r"bad.blf: truncated BLF file: \d+ bytes, the header declares \d+"):
        read_commands(path)
    with pytest.raises(WrsimError, match=r"log.trc: unsupported CAN log type '.trc'"):
        read_commands(tmp_path / "log.trc")


@pytest.mark.parametrize("compression", [0, 6])
def test_a_blf_object_of_length_zero_is_named(tmp_path, compression):
    """python-can's reader loops for ever on an object of length 0 (in a log container or around one)."""
    path = tmp_path / "zero.blf"
    with can.BLFWriter(path, compression_level=compression) as writer:
        for frame in command_frames(SEQUENCE):
            writer.on_message_received(frame)
    assert [c.command for c in read_commands(path)] == [c.command for c in SEQUENCE]
    data = bytearray(path.read_bytes())
    objects = [k for k in range(len(data) - 3) if data[k : k + 4] == b"LOBJ"]
    at = objects[1] if compression == 0 else objects[0]  # a frame inside the container, or the container
    struct.pack_into("<L", data, at + 8, 0)
    path.write_bytes(bytes(data))
    where = r"an object of length 0 in the log data" if compression == 0 else rf"the object at byte {at} has length 0"
    with pytest.raises(WrsimError, match=rf"zero.blf: malformed BLF file: {where}"):
        read_commands(path)


def test_non_increasing_command_times_name_frame_and_times(tmp_path):
    path = tmp_path / "c.asc"
    write_log([command_frame(0.0, 0), command_frame(0.2, 1), command_frame(0.2, 0)], path)
    with pytest.raises(
        WrsimError,
        match=r"c.asc:8: frame 2: time 0.2 s does not increase \(previous: 0.2 s\); "
        r"switch command times must rise strictly",
    ):
        read_commands(path)


def test_unknown_command_and_offset_out_of_range(tmp_path):
    path = tmp_path / "c.blf"
    write_log([command_frame(0.0, 0), command_frame(0.1, 3)], path)
    with pytest.raises(
        WrsimError,
        match=r"c.blf: frame 1 \(t = 0.1 s\): unknown switch command 3 "
        r"\(0 stop, 1 up, 2 down\)",
    ):
        read_commands(path)
    write_log([command_frame(0.0, 1, -12.8)], path)
    with pytest.raises(
        WrsimError,
        match=r"frame 0 \(t = 0 s\): voltage offset -12.8 V outside the DBC "
        r"range \[-8, 8\] V",
    ):
        read_commands(path)
    write_log([command_frame(0.0, 1, end=1), command_frame(0.1, 0)], path)
    with pytest.raises(
        WrsimError,
        match=r"frame 1 \(t = 0.1 s\): WR_SwitchCommand after the end-of-sequence "
        r"frame \(.*frame 0\)",
    ):
        read_commands(path)
    write_log([can.Message(timestamp=0.0, arbitration_id=0x1A0, data=[1], is_extended_id=False)], path)
    with pytest.raises(WrsimError, match=r"frame 0: cannot decode WR_SwitchCommand: Wrong data size"):
        read_commands(path)
    write_log([], path)
    with pytest.raises(WrsimError, match=r"c.blf: no WR_SwitchCommand frame \(ID 0x1A0\)"):
        read_commands(path)


# ------------------------------------------------------------------------------- switch sequence file


def test_write_sequence_format_and_offsets(tmp_path):
    path = tmp_path / "seq.txt"
    write_sequence(SEQUENCE, path)
    note = "not applied: a time-based unit has no voltage field"
    assert path.read_text().splitlines() == [
        "# switch sequence (thesis 4.3.3.2): T <time s> <command: 0 stop, 1 up, 2 down>",
        "T 0.25 1",
        "T 1.0 0",
        "T 1.3 2",
        f"# voltage offset +2 V from 1.3 s {note}",
        "T 2.05 0",
        f"# voltage offset -1.5 V from 2.05 s {note}",
    ]
    with pytest.raises(WrsimError, match=r"seq.txt: unit 2: voltage offset \+2 V from 1.3 s not applied"):
        write_sequence(SEQUENCE, path, strict=True)


def test_write_sequence_rejects_bad_units(tmp_path):
    path = tmp_path / "seq.txt"
    with pytest.raises(WrsimError, match=r"seq.txt: unit 2: time 0.5 s does not increase \(previous: 0.5 s\)"):
        write_sequence([Command(0.0, 0), Command(0.5, 1), Command(0.5, 2)], path)
    with pytest.raises(WrsimError, match=r"unit 1: time 1 s does not increase \(previous: 1 s\)"):
        write_sequence([Command(1.0, 0), Command(1.0000000001, 1)], path)  # equal at 1 ns
    with pytest.raises(WrsimError, match=r"seq.txt: unit 1 \(t = 1 s\): unknown switch command 4"):
        write_sequence([Command(0.0, 0), Command(1.0, 4)], path)
    with pytest.raises(WrsimError, match=r"unit 0: time -0.1 s must be finite and >= 0"):
        write_sequence([Command(-0.1, 0)], path)
    with pytest.raises(WrsimError, match=r"empty switch sequence"):
        write_sequence([], path)
    assert not path.exists()


# ---------------------------------------------------------------------------------------- status frames


def waveforms() -> dict[str, np.ndarray]:
    t = np.linspace(0.0, 1.0, 1001)  # 1 ms simulation points
    return {
        "time": t,
        "position": 0.05 + 0.4 * t,  # m
        "motor_state": np.where(t < 0.3333, 1.0, np.where(t < 0.6, 0.0, 2.0)),
        "pinch": (t > 0.5).astype(float),
        "force": 150.0 * np.clip(t - 0.5, 0.0, None) ** 2 * 4.0,  # N
        "supply": 13.0 - 0.7 * np.sin(7.0 * t),  # V
    }


def test_status_frames_decode_to_sampled_values_within_resolution(tmp_path):
    w = waveforms()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing is clipped here
        frames = status_frames(**w)
    grid = np.array([f.timestamp for f in frames])
    assert grid == pytest.approx(np.arange(101) * 0.01, abs=1e-12)  # DBC cycle time 10 ms
    for suffix in (".asc", ".blf"):
        path = tmp_path / f"status{suffix}"
        write_log(frames, path)
        decoded = decode_log(path)
        assert [d["message"] for d in decoded] == ["WR_Status"] * 101
        assert [d["time"] for d in decoded] == pytest.approx(grid, abs=1e-6)
        s = {k: np.array([d["signals"][k] for d in decoded]) for k in decoded[0]["signals"]}
        np.testing.assert_allclose(
            s["WindowPosition"], 1e3 * np.interp(grid, w["time"], w["position"]), atol=0.05 + 1e-9
        )
        np.testing.assert_allclose(s["PinchForce"], np.interp(grid, w["time"], w["force"]), atol=0.05 + 1e-9)
        np.testing.assert_allclose(s["SupplyVoltage"], np.interp(grid, w["time"], w["supply"]), atol=0.05 + 1e-9)
        held = np.searchsorted(w["time"], grid + 1e-9, side="right") - 1
        np.testing.assert_array_equal(s["MotorState"], w["motor_state"][held])
        np.testing.assert_array_equal(s["PinchEvent"], w["pinch"][held])
        np.testing.assert_array_equal(s["StatusCounter"], np.arange(101) % 16)
        assert s["MotorState"][33] == 1 and s["MotorState"][34] == 0  # held, not interpolated


def test_status_frames_clip_with_a_counted_warning():
    w = waveforms()
    w["force"] = np.where(w["time"] > 0.9, 2500.0, 10.0)
    w["supply"] = np.full_like(w["time"], -1.0)
    with pytest.warns(ClippedWarning) as record:
        frames = status_frames(**w, period=0.1)
    messages = sorted(str(r.message) for r in record)
    assert messages == [
        "WR_Status.PinchForce: 1 sample(s) outside the DBC range [0, 2000] N clipped",
        "WR_Status.SupplyVoltage: 11 sample(s) outside the DBC range [0, 25.5] V clipped",
    ]
    last = DB.decode_message(0x1A1, frames[-1].data)
    assert (last["PinchForce"], last["SupplyVoltage"]) == (2000.0, 0.0)


def test_status_frames_bad_input():
    w = waveforms()
    with pytest.raises(WrsimError, match=r"'force' has shape \(3,\); every waveform must be 1-D"):
        status_frames(**{**w, "force": np.zeros(3)})
    with pytest.raises(WrsimError, match=r"'time' does not rise at sample 2 \(0.001 s after 0.002 s\)"):
        status_frames(**{**w, "time": np.concatenate([[0.0, 0.002, 0.001], w["time"][3:] + 1.0])})
    with pytest.raises(WrsimError, match=r"motor_state: value 3 at t = 0.5 s is not one of 0 stop, 1 up, 2 down"):
        status_frames(**{**w, "motor_state": np.where(w["time"] >= 0.5, 3.0, 0.0)})
    with pytest.raises(WrsimError, match=r"'supply' is not finite at sample 0"):
        status_frames(**{**w, "supply": np.full_like(w["time"], np.nan)})
    with pytest.raises(WrsimError, match=r"period 0 s must be > 0"):
        status_frames(**w, period=0.0)


def test_write_log_bad_input(tmp_path):
    with pytest.raises(WrsimError, match=r"x.csv: unsupported CAN log type '.csv'"):
        write_log([], tmp_path / "x.csv")
    with pytest.raises(
        WrsimError,
        match=r"x.asc: frame 1: timestamp 0.1 s must be finite, >= 0 and not before "
        r"the previous frame \(0.2 s\)",
    ):
        write_log([command_frame(0.2, 0), command_frame(0.1, 1)], tmp_path / "x.asc")
    assert not (tmp_path / "x.asc").exists()


# ---------------------------------------------------------------------------------- the replay log


def test_committed_replay_log_is_reproducible_and_drives_a_full_cycle(tmp_path):
    commands = read_commands(REPLAY_LOG)
    same_commands(commands, list(REPLAY_SEQUENCE))
    assert [c.command for c in commands] == [0, 1, 0, 2, 0]  # stop, up, stop, down, stop
    up, down = commands[2].time - commands[1].time, commands[4].time - commands[3].time
    assert up > 4.5 and down > 4.0  # longer than a 3.5-4.5 s stroke (thesis 5.3.1)
    fresh = tmp_path / "replay.asc"
    make_replay_log(fresh)

    def body(path: Path) -> list[str]:  # python-can stamps the header dates with the wall clock
        return [l for l in path.read_text().splitlines() if not l.startswith(("date ", "Begin Triggerblock"))]

    assert body(fresh) == body(REPLAY_LOG)
