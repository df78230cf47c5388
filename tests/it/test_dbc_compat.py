# SPDX-License-Identifier: MIT
"""hdlamp dbc with databases and logs as other tools write them (docs/dbc-compat.md): lenient
loading with warnings, --strict, NaN and infinity in the JSON, python-can's candump logs."""
import json
import math
import os
import subprocess

HDLAMP = os.environ.get("HDLAMP", "hdlamp")
SRC = os.environ.get("HL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
HD84 = os.path.join(SRC, "dbc", "hd84.dbc")

FLOATS_DBC = """VERSION ""
BU_: ECU
BO_ 256 Floats: 8 ECU
 SG_ F : 0|32@1- (1,0) [0|0] "" ECU
 SG_ G : 32|32@1- (2,1) [0|0] "" ECU
BO_ 257 Doubles: 8 ECU
 SG_ D : 0|64@1- (1,0) [0|0] "" ECU
SIG_VALTYPE_ 256 F : 1;
SIG_VALTYPE_ 256 G : 1;
SIG_VALTYPE_ 257 D : 2;
"""

# A comment and a value table for a signal the message no longer has, line 5 column 14.
STALE_DBC = """VERSION ""
BU_: ECU
BO_ 256 Msg: 8 ECU
 SG_ Speed : 0|16@1+ (0.01,0) [0|655.35] "km/h" ECU
CM_ SG_ 256 OldSpeed "removed in 2019";
"""


def run(*args, stdin=None):
    return subprocess.run([HDLAMP, "dbc", *args], input=stdin, capture_output=True, text=True)


def test_decode_writes_nan_and_infinity_as_distinct_strings(tmp_path):
    dbc = tmp_path / "floats.dbc"
    dbc.write_text(FLOATS_DBC)
    log = ("(1.000000) can0 100#0000C07F0000803F\n"  # F NaN, G 1.0 -> 3
           "(2.000000) can0 100#0000807F000080FF\n"  # F +inf, G -inf
           "(3.000000) can0 100#000080FF00000000\n"  # F -inf, G 0 -> 1
           "(4.000000) can0 101#000000000000F87F\n")  # D NaN
    p = run("decode", "--dbc", str(dbc), "-", stdin=log)
    assert p.returncode == 0, p.stderr
    assert p.stderr == ""
    frames = [json.loads(l) for l in p.stdout.splitlines()]
    assert [f["signals"] for f in frames] == [
        {"F": "NaN", "G": 3},
        {"F": "Infinity", "G": "-Infinity"},
        {"F": "-Infinity", "G": 1},
        {"D": "NaN"},
    ]
    # the strings read back into the values with float()
    assert math.isnan(float(frames[0]["signals"]["F"]))
    assert float(frames[1]["signals"]["F"]) == math.inf
    assert float(frames[2]["signals"]["F"]) == -math.inf


def test_lenient_warns_with_place_strict_refuses(tmp_path):
    dbc = tmp_path / "stale.dbc"
    dbc.write_text(STALE_DBC)
    p = run("info", str(dbc))
    assert p.returncode == 0
    assert p.stderr == (f"hdlamp dbc: '{dbc}':5:13: warning: expected a signal of message "
                        "'Msg', found 'OldSpeed': statement skipped\n")
    assert "Speed" in p.stdout
    p = run("info", "--strict", str(dbc))
    assert p.returncode == 1
    assert p.stderr == (f"hdlamp dbc: '{dbc}':5:13: expected a signal of message 'Msg', "
                        "found 'OldSpeed'\n")
    # decoding is the same as with the statement removed
    clean = tmp_path / "clean.dbc"
    clean.write_text(STALE_DBC.rsplit("CM_", 1)[0])
    line = "(1.000000) can0 100#3412000000000000\n"
    a = run("decode", "--dbc", str(dbc), "-", stdin=line)
    b = run("decode", "--strict", "--dbc", str(clean), "-", stdin=line)
    assert a.returncode == 0 and b.returncode == 0
    assert a.stdout == b.stdout
    assert json.loads(a.stdout)["signals"] == {"Speed": 46.6}


ASC = """date Mon Nov 23 07:00:00.000 am 2026
base hex  timestamps absolute
internal events logged
// version 9.0.0
Begin Triggerblock Mon Nov 23 07:00:00.000 am 2026
   0.000000 Start of measurement
   1.000000 1  320             Rx   d 8 00 01 00 00 00 00 00 00
   2.501000 1  ErrorFrame
   3.000000 1  321             Rx   d 8 00 01 01 00 00 00 00 00
   3.500000 2  ErrorFrame
   4.000000 1  7FF             Rx   d 2 AA BB
   5.000000 1  ErrorFrame
End TriggerBlock
"""


def test_python_can_log_with_error_frames_decodes_every_line(tmp_path):
    asc, log = tmp_path / "bus.asc", tmp_path / "bus.log"
    asc.write_text(ASC)
    # python-can as a user has it: .asc read, candump .log written
    script = ("import can, sys\n"
              "with can.LogReader(sys.argv[1]) as r, can.Logger(sys.argv[2]) as w:\n"
              "    for m in r:\n"
              "        w.on_message_received(m)\n")
    subprocess.run(["/usr/bin/python3", "-c", script, str(asc), str(log)], check=True)
    lines = [l for l in log.read_text().splitlines() if l]
    assert len(lines) == 6
    assert sum(l.endswith(" 20000080#") for l in lines) == 3  # error frames without data
    p = run("decode", "--dbc", HD84, str(log))
    assert p.returncode == 0, p.stderr
    out = [json.loads(l) for l in p.stdout.splitlines()]
    assert len(out) == len(lines)  # every line accounted for
    errors = [f for f in out if f.get("error_frame")]
    assert [(f["t"], f["iface"], f["id"], f["len"]) for f in errors] == [
        (2.501, "can0", "0x20000080", 0), (3.5, "can1", "0x20000080", 0),
        (5.0, "can0", "0x20000080", 0)]
    assert [f.get("name") for f in out if not f.get("error_frame")] == [
        "HL_Dim_L", "HL_Dim_R", None]
    assert p.stderr == ("hdlamp dbc: 2 frames decoded, 1 with unknown IDs, 0 short, "
                        "0 malformed lines, 3 error frames\n")
