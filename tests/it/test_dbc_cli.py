# SPDX-License-Identifier: MIT
"""hdlamp dbc: info, encode and decode of the shipped HD84 databases, end to end."""
import json
import os
import random
import re
import subprocess

import pytest

HDLAMP = os.environ.get("HDLAMP", "hdlamp")
SRC = os.environ.get("HL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
HD84 = os.path.join(SRC, "dbc", "hd84.dbc")
HD84_FD = os.path.join(SRC, "dbc", "hd84_fd.dbc")


def run(*args, stdin=None, check=True):
    p = subprocess.run([HDLAMP, "dbc", *args], input=stdin, capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"hdlamp dbc {' '.join(args)}: {p.returncode}\n{p.stderr}")
    return p


def decode(dbc, lines):
    p = run("decode", "--dbc", dbc, "-", stdin="".join(l + "\n" for l in lines))
    return [json.loads(l) for l in p.stdout.splitlines()]


@pytest.mark.parametrize("path,messages,profile,mode_msgs,mode_layout", [
    (HD84, {"HL_Dim_L": 0x320, "HL_Dim_R": 0x321}, "P1", {"HL_Dim_L", "HL_Dim_R"}, "58|6@1+"),
    (HD84_FD, {"HL_DimA_L": 0x330, "HL_DimB_L": 0x331, "HL_DimA_R": 0x332, "HL_DimB_R": 0x333}, "P5",
     {"HL_DimB_L", "HL_DimB_R"}, "114|6@1+"),
])
def test_info_shows_every_attribute_the_daemon_needs(path, messages, profile, mode_msgs,
                                                     mode_layout):
    out = run("info", path).stdout
    assert '  SG_     HdlBeamMode          INT [0, 1] default 0\n' in out
    blocks = re.split(r"\n(?=message )", out)
    seen = {}
    for b in blocks[1:]:
        m = re.match(r"message (\S+) id 0x([0-9A-F]+) \(standard\) (\d+) bytes", b)
        assert m, b[:200]
        name, msg_id = m.group(1), int(m.group(2), 16)
        assert messages[name] == msg_id
        lamp = "left" if name.endswith("_L") else "right"
        assert f'  HdlLamp="{lamp}"\n' in b
        assert f'  HdlE2E="{profile} dataid=0x{msg_id:04X}"\n' in b
        assert "  GenMsgCycleTime=20\n" in b
        sources = [int(s) for s in re.findall(r"HdlSource=(\d+)\n", b)]
        seen[name] = sorted(s for s in sources if s)
        # the beam mode: one signal per lamp, in the slot after the last source, VAL_ named
        modes = re.findall(r"\n    (HL_Mode_[LR]) +(\S+) .*\n(?:        .*\n)*?        HdlBeamMode=1\n"
                           r"        values: (.*)\n", b)
        if name in mode_msgs:
            assert modes == [(f"HL_Mode_{name[-1]}", mode_layout,
                              '0="unset" 1="low" 2="high" 3="glarefree"')], b[-600:]
        else:
            assert modes == [] and "HdlBeamMode=1" not in b
        # every other signal (each shows its HdlSource) has the default, no mode
        n_signals = {"HL_Dim_L": 3 + 95 + 1, "HL_DimA_L": 2 + 80, "HL_DimB_L": 2 + 15 + 1}
        assert b.count("\n        HdlSource=") == n_signals[name[:-1] + "L"]
        assert b.count("HdlBeamMode=0 (default)") == n_signals[name[:-1] + "L"] - len(modes)
    assert set(seen) == set(messages)
    for lamp in "LR":
        got = sorted(s for n, v in seen.items() if n.endswith(lamp) for s in v)
        assert got == list(range(1, 96))
    if profile == "P1":
        assert "HL_Page_L            M" in out
        assert "present when HL_Page_L=11" in out
        assert re.search(r"HL_Mode_L +58\|6@1\+ +\(1,0\) \[0\|3\] \"\" -> HL_L\n"
                         r"        present when HL_Page_L=11\n", out)


def classic_cycle(values, counter0=0):
    """The 24 frames of one cycle of hd84.dbc: 12 pages per lamp, all with the cycle's counter."""
    lines = []
    for lamp, vals in zip("LR", values):
        for page in range(12):
            sigs = [f"HL_Page_{lamp}={page}"]
            for slot in range(8):
                k = 8 * page + slot + 1
                if k <= 95:
                    sigs.append(f"LED_{k:03d}={vals[k - 1] / 63!r}")
            p = run("encode", "--dbc", HD84, "--message", f"HL_Dim_{lamp}", "--e2e",
                    "--counter", str(counter0 % 15), "--time", f"100.{page:06d}", *sigs)
            lines.append(p.stdout.strip())
    return lines


def test_classic_full_cycle_round_trip_both_lamps():
    rng = random.Random(3)
    values = [[rng.randrange(64) for _ in range(95)] for _ in range(2)]
    lines = classic_cycle(values)
    assert len(lines) == 24
    assert re.fullmatch(r"\(0000000100\.000000\) can0 320#[0-9A-F]{16}", lines[0])
    frames = decode(HD84, lines)
    assert len(frames) == 24
    got = [[None] * 95, [None] * 95]
    for i, f in enumerate(frames):
        lamp = i // 12
        assert f["e2e"] == "ok", f
        assert f["iface"] == "can0"
        assert f["id"] == ("0x320" if lamp == 0 else "0x321")
        assert f["name"] == ("HL_Dim_L", "HL_Dim_R")[lamp]
        sig = f["signals"]
        suffix = "LR"[lamp]
        assert sig[f"HL_Page_{suffix}"] == i % 12
        assert sig[f"HL_Alive_{suffix}"] == 0  # one counter for the whole cycle
        for name, v in sig.items():
            if name.startswith("LED_"):
                k = int(name[4:])
                assert got[lamp][k - 1] is None
                got[lamp][k - 1] = v
    for lamp in range(2):
        assert got[lamp] == [v * (1 / 63) for v in values[lamp]]  # raw * factor, as DBC defines


def test_fd_full_cycle_round_trip_both_lamps():
    rng = random.Random(4)
    values = [[rng.randrange(64) for _ in range(95)] for _ in range(2)]
    lines = []
    for lamp, vals in zip("LR", values):
        for part, first, last in (("A", 1, 80), ("B", 81, 95)):
            sigs = [f"LED_{k:03d}={vals[k - 1] / 63!r}" for k in range(first, last + 1)]
            p = run("encode", "--dbc", HD84_FD, "--message", f"HL_Dim{part}_{lamp}", "--e2e",
                    "--counter", "200", "--time", "5.5", *sigs)
            lines.append(p.stdout.strip())
    assert re.fullmatch(r"\(0000000005\.500000\) can0 330##0[0-9A-F]{128}", lines[0])
    assert re.fullmatch(r"\(0000000005\.500000\) can0 331##0[0-9A-F]{32}", lines[1])
    frames = decode(HD84_FD, lines)
    got = [{}, {}]
    for i, f in enumerate(frames):
        assert f["e2e"] == "ok", f
        assert f["signals"][f"HL_Counter_{'AB'[i % 2]}_{'LR'[i // 2]}"] == 200
        got[i // 2].update({int(n[4:]): v for n, v in f["signals"].items() if n.startswith("LED_")})
    for lamp in range(2):
        assert [got[lamp][k] for k in range(1, 96)] == [v * (1 / 63) for v in values[lamp]]  # raw * factor, as DBC defines


def flip(line, bit):
    """Flips one payload bit of a candump line (bit 0 = MSB of the first data byte)."""
    if "##" in line:
        head, data = line.split("##")
        head, data = head + "##" + data[0], data[1:]
    else:
        head, data = line.split("#")
        head += "#"
    b = bytearray(bytes.fromhex(data))
    b[bit // 8] ^= 0x80 >> (bit % 8)
    return head + b.hex().upper()


def test_flipped_bit_shows_crc():
    lines = classic_cycle([[1] * 95, [2] * 95])[:12]
    for bit in (0, 9, 20, 63):  # in the CRC, the counter, a source, the reserved slot
        frames = decode(HD84, [flip(lines[11], bit)])
        assert frames[0]["e2e"] == "crc"
    fd = run("encode", "--dbc", HD84_FD, "--message", "HL_DimA_L", "--e2e", "--counter", "1",
             "--time", "1", "LED_080=1").stdout.strip()
    assert decode(HD84_FD, [fd])[0]["e2e"] == "ok"
    for bit in (0, 15, 23, 507):
        assert decode(HD84_FD, [flip(fd, bit)])[0]["e2e"] == "crc"


def test_counter_repeated_and_lost():
    # the counter steps once per cycle and is followed per page
    c = {n: classic_cycle([[0] * 95, [0] * 95], counter0=n)[:12] for n in (0, 1, 5)}
    frames = decode(HD84, [c[0][0], c[0][1], c[0][0], c[1][0], c[1][1], c[5][0], c[5][1]])
    assert [f["e2e"] for f in frames] == ["ok", "ok", "repeated", "ok", "ok", "lost", "lost"]
    assert frames[5]["lost"] == 3 and frames[6]["lost"] == 3


def test_decode_unknown_short_and_malformed(tmp_path):
    log = tmp_path / "x.log"
    log.write_text("(1.000000) can0 7FF#00\n"
                   "(1.000000) can0 320#0102\n"
                   "(1.000000) can0 320#01020\n"
                   "(2.000000) vcan1 18FEF100#0102\n")
    p = run("decode", "--dbc", HD84, str(log), check=False)
    assert p.returncode == 1
    frames = [json.loads(l) for l in p.stdout.splitlines()]
    assert frames[0] == {"t": 1.0, "iface": "can0", "id": "0x7ff", "name": None}
    assert frames[1] == {"t": 1.0, "iface": "can0", "id": "0x320", "name": "HL_Dim_L",
                         "error": "short frame: 2 of 8 bytes"}
    assert frames[2] == {"t": 2.0, "iface": "vcan1", "id": "0x18fef100", "name": None}
    assert f"hdlamp dbc: '{log}':3:26: expected a second hex digit of the data byte" in p.stderr
    assert "1 with unknown IDs" not in p.stderr and "2 with unknown IDs, 1 short, 1 malformed" in p.stderr


def test_encode_errors():
    p = run("encode", "--dbc", HD84, "--message", "HL_Dim_L", "HL_Page_L=0", "LED_001=1.5",
            check=False)
    assert p.returncode == 1 and "LED_001=1.5: out of range" in p.stderr
    p = run("encode", "--dbc", HD84, "--message", "HL_Dim_L", "HL_Page_L=1", "LED_001=1",
            check=False)
    assert p.returncode == 1 and "signal LED_001 is not selected" in p.stderr
    p = run("encode", "--dbc", HD84, "--message", "HL_Dim_L", "Nope=1", check=False)
    assert p.returncode == 1 and "has no signal 'Nope'" in p.stderr
    p = run("encode", "--dbc", HD84, "--message", "HL_Dim_L", "--e2e", "--counter", "15",
            check=False)
    assert p.returncode == 2 and "counter 15: expected 0..14 for P1" in p.stderr
    p = run("encode", "--dbc", HD84, "--message", "Nope", check=False)
    assert p.returncode == 1
    # VAL_ names work as values: page 3 by its description
    p = run("encode", "--dbc", HD84, "--message", "HL_Dim_L", "--time", "0",
            "HL_Page_L=sources 25-32")
    assert p.stdout == "(0000000000.000000) can0 320#0030000000000000\n"


def test_usage_and_bad_database(tmp_path):
    assert run(check=False).returncode == 2
    assert run("decode", check=False).returncode == 2
    assert run("info", check=False).returncode == 2
    assert run("frob", check=False).returncode == 2
    assert run("--help").stdout.startswith("usage: hdlamp dbc info [--strict] FILE")
    bad = tmp_path / "bad.dbc"
    bad.write_text('VERSION ""\n\nBO_ 1 A: 8 E\n SG_ S : 0|8@3+ (1,0) [0|1] "" X\n')
    p = run("info", str(bad), check=False)
    assert p.returncode == 1
    assert p.stderr == (f"hdlamp dbc: '{bad}':4:14: expected the byte order 0 (Motorola) or "
                        "1 (Intel) after '@', found number 3\n")
    warn = tmp_path / "warn.dbc"
    warn.write_text('BO_ 1 A: 8 E\n SG_ S : 0|8@1+ (1,0) [0|1] "" X\nSGTYPE_ x : 8@1+;\n')
    p = run("info", str(warn))
    assert f"'{warn}':3:1: warning: skipped unknown section 'SGTYPE_'" in p.stderr


def test_extended_id_fd_float_round_trip(tmp_path):
    db = tmp_path / "ext.dbc"
    db.write_text('BO_ 2566848766 Ext: 64 ECU\n'
                  ' SG_ Temp : 0|12@1- (0.5,-10) [-1034|1033.5] "degC" X\n'
                  ' SG_ Big : 71|64@0+ (1,0) [0|0] "" X\n'
                  ' SG_ F : 480|32@1- (1,0) [0|0] "" X\n'
                  'SIG_VALTYPE_ 2566848766 F : 1;\n')
    p = run("encode", "--dbc", str(db), "--message", "Ext", "--time", "7.25", "--iface", "vcan0",
            "Temp=-230.5", "Big=18446744073709549568", "F=-0.15625")
    line = p.stdout.strip()
    # -230.5 -> raw (-230.5 + 10) / 0.5 = -441 = 0xE47 in 12 bits, Intel: 47 0E
    # Big, Motorola from bit 71 (MSB of byte 8): bytes 8..15 = FF FF FF FF FF FF F8 00
    # F = -0.15625f = 0xBE200000, Intel from byte 60: 00 00 20 BE
    data = "470E" + "00" * 6 + "FFFFFFFFFFFFF800" + "00" * 44 + "000020BE"
    assert line == "(0000000007.250000) vcan0 18FF00FE##0" + data
    f = decode(str(db), [line])[0]
    assert f["id"] == "0x18ff00fe" and f["name"] == "Ext" and f["e2e"] == "none"
    assert f["signals"] == {"Temp": -230.5, "Big": 18446744073709549568, "F": -0.15625}
