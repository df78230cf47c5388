"""hdlamp scenario validate / builtin (docs/scenarios.md): exit codes 0/1/2, each fault as
FILE:LINE:COL: KEY: MESSAGE, the shipped scenarios listed, written byte for byte and valid; the
candump drive generator (`hdlamp scenario --dbc ...`) still works beside the new verbs."""
import json
import os

from proc import run

SRC = os.environ.get("HL_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
SHIPPED = sorted(f[:-5] for f in os.listdir(os.path.join(SRC, "scenarios")) if f.endswith(".json"))

GOOD = """{
  "version": 1,
  "duration_s": 8,
  "road": {
    "segments": [
      {"kind": "straight", "length_m": 50},
      {"kind": "arc", "length_m": 400, "radius_m": 250, "turn": "right"}
    ]
  },
  "actors": [
    {"id": "car", "kind": "car", "role": "oncoming",
     "path": {"start_s_m": 350, "speed_mps": 22.352}}
  ]
}
"""


def where(text, needle, nth=0):
    """1-based line and column of the nth occurrence of needle, counted here from the text."""
    i = -1
    for _ in range(nth + 1):
        i = text.index(needle, i + 1)
    return text.count("\n", 0, i) + 1, i - (text.rfind("\n", 0, i) + 1) + 1


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def test_validate_accepts_a_good_file(hdlamp, tmp_path):
    path = write(tmp_path, "good.json", GOOD)
    r = run(hdlamp, "scenario", "validate", path)
    assert r.stdout.startswith(f"{path}: ok: 8.00 s, road 450.0 m in 2 segment(s), 2 lane(s), "
                               "1 road user(s)"), r.stdout
    assert r.stderr == ""


def test_validate_names_file_line_column_and_key(hdlamp, tmp_path):
    key_text = GOOD.replace('"turn": "right"', '"turn": "right", "bank_deg": 2')
    time_text = GOOD.replace(
        '"path": {"start_s_m": 350, "speed_mps": 22.352}',
        '"path": {"waypoints": [{"t_s": 3, "x_m": 1, "y_m": 0},\n'
        '                       {"t_s": 2, "x_m": 2, "y_m": 0}]}').replace('"oncoming"',
                                                                        '"crossing"')
    road_text = GOOD.replace('"turn": "right"}', '"turn": "right", "start_s_m": 40}')
    bad_key = write(tmp_path, "bad_key.json", key_text)
    bad_time = write(tmp_path, "bad_time.json", time_text)
    bad_road = write(tmp_path, "bad_road.json", road_text)
    good = write(tmp_path, "good.json", GOOD)
    r = run(hdlamp, "scenario", "validate", bad_key, good, bad_time, bad_road, ok=False)
    assert r.returncode == 1, r
    lines = r.stderr.splitlines()
    (kl, kc), (tl, tc), (rl, rc) = (where(key_text, '"bank_deg"'), where(time_text, '"t_s"', 1),
                                    where(road_text, '"start_s_m": 40'))
    assert (kl, tl, rl) == (7, 13, 7)
    assert lines == [
        f"{bad_key}:{kl}:{kc}: road.segments[1].bank_deg: unknown key 'bank_deg'; expected one "
        "of: kind, length_m, radius_m, turn, start_s_m",
        f"{bad_time}:{tl}:{tc}: actors[0].path.waypoints[1].t_s: 2 s is not after the previous "
        "waypoint's 3 s: expected strictly increasing times",
        f"{bad_road}:{rl}:{rc}: road.segments[1].start_s_m: the road does not connect: this "
        "segment starts at s = 40 m, expected 50 m (where segment 0 ends)",
    ], r.stderr
    # the valid file among them is still reported valid
    assert r.stdout.startswith(f"{good}: ok"), r.stdout


def test_validate_wrong_type_and_json_syntax(hdlamp, tmp_path):
    wrong = write(tmp_path, "wrong.json", GOOD.replace('"duration_s": 8', '"duration_s": "8"'))
    broken = write(tmp_path, "broken.json", GOOD.replace('"version": 1,', '"version": 1'))
    r = run(hdlamp, "scenario", "validate", wrong, broken, ok=False)
    assert r.returncode == 1
    lines = r.stderr.splitlines()
    assert where(GOOD, '"duration_s"') == (3, 3)
    assert lines[0] == (f"{wrong}:3:3: duration_s: expected a number in (0, 3600] s, "
                        "found a string"), lines
    assert lines[1].startswith(f"{broken}:3:"), lines  # jansson's line and column


def test_validate_usage_and_missing_file(hdlamp, tmp_path):
    r = run(hdlamp, "scenario", "validate", ok=False)
    assert r.returncode == 2 and "usage: hdlamp scenario validate" in r.stderr
    missing = str(tmp_path / "nope.json")
    r = run(hdlamp, "scenario", "validate", missing, ok=False)
    assert r.returncode == 1
    assert r.stderr.strip() == f"{missing}: cannot open: No such file or directory"


def test_builtin_lists_and_writes_every_shipped_scenario(hdlamp, tmp_path):
    r = run(hdlamp, "scenario", "builtin", "--list")
    names = [line.split("\t")[0] for line in r.stdout.splitlines()]
    assert names == SHIPPED
    for want in ("iihs-approach-straight", "iihs-approach-curve-250m-left",
                 "iihs-approach-curve-250m-right", "preceding-car", "pedestrian-edge-60m",
                 "demo-drive"):
        assert want in names
    for name in names:
        out = tmp_path / f"{name}.json"
        run(hdlamp, "scenario", "builtin", name, "--out", out)
        with open(os.path.join(SRC, "scenarios", f"{name}.json"), "rb") as f:
            assert out.read_bytes() == f.read()
        run(hdlamp, "scenario", "validate", out)
        assert json.loads(out.read_text())["version"] == 1


def test_builtin_refusals(hdlamp, tmp_path):
    r = run(hdlamp, "scenario", "builtin", "no-such-scenario", "--out", tmp_path / "x.json",
            ok=False)
    assert r.returncode == 1
    assert "no built-in scenario 'no-such-scenario'" in r.stderr
    assert not (tmp_path / "x.json").exists()
    r = run(hdlamp, "scenario", "builtin", "../etc/passwd", "--out", tmp_path / "x.json",
            ok=False)
    assert r.returncode == 2 and "expected a name" in r.stderr
    for args in (["builtin"], ["builtin", "demo-drive"], ["builtin", "--list", "demo-drive"]):
        r = run(hdlamp, "scenario", *args, ok=False)
        assert r.returncode == 2 and "usage: hdlamp scenario builtin" in r.stderr, args


def test_drive_generator_still_works(hdlamp, tmp_path):
    log = tmp_path / "drive.log"
    run(hdlamp, "scenario", "--dbc", os.path.join(SRC, "dbc", "hd84.dbc"), "--out", log,
        "--hold", "low", "--phase-cycles", "2")
    assert len(log.read_text().splitlines()) == 2 * 2 * 12  # 2 cycles, 2 lamps, 12 pages
    r = run(hdlamp, "scenario", "--help")
    assert "hdlamp scenario validate FILE..." in r.stdout


def modes_in_log(hdlamp, dbc, log):
    """Each lamp's HL_Mode_x values in the log's order, decoded with hdlamp dbc decode."""
    out = run(hdlamp, "dbc", "decode", "--dbc", dbc, log).stdout
    got = {"L": [], "R": []}
    for line in out.splitlines():
        sig = json.loads(line)["signals"]
        for lamp in got:
            if f"HL_Mode_{lamp}" in sig:
                got[lamp].append(sig[f"HL_Mode_{lamp}"])
    return got


# the shipped databases' VAL_ of HL_Mode_L / HL_Mode_R
UNSET, LOW, HIGH, GLAREFREE = 0, 1, 2, 3


def test_drive_says_each_phases_beam_mode(hdlamp, tmp_path):
    # hdlamp scenario's HD84 drive: N low, N high, 2N glare-free, N bend left, N bend right
    # (the low beam turned), the 6 cycles of the faults and N more of low beam; every cycle
    # carries its mode in the lamps' HdlBeamMode signal (the CRC and missing-frame faults hit
    # other pages or frame A, so every mode-carrying frame is there)
    n = 3
    want = [LOW] * n + [HIGH] * n + [GLAREFREE] * 2 * n + [LOW] * 2 * n + [LOW] * (6 + n)
    for dbc in ("hd84.dbc", "hd84_fd.dbc"):
        path = os.path.join(SRC, "dbc", dbc)
        log = str(tmp_path / f"{dbc}.log")
        run(hdlamp, "scenario", "--dbc", path, "--out", log, "--phase-cycles", n)
        assert modes_in_log(hdlamp, path, log) == {"L": want, "R": want}, dbc


def test_hold_says_the_presets_beam_mode(hdlamp, tmp_path):
    path = os.path.join(SRC, "dbc", "hd84.dbc")
    for preset, mode, want in (("low", None, LOW), ("high", None, HIGH),
                               ("glarefree", None, GLAREFREE), ("bend_left", None, LOW),
                               ("bend_right", None, LOW), ("high", "glarefree", GLAREFREE),
                               ("high", "UNSET", UNSET)):
        log = str(tmp_path / f"{preset}-{mode}.log")
        run(hdlamp, "scenario", "--dbc", path, "--out", log, "--hold", preset,
            "--phase-cycles", 4, *(["--mode", mode] if mode else []))
        assert modes_in_log(hdlamp, path, log) == {"L": [want] * 4, "R": [want] * 4}, \
            (preset, mode)
    # a mode no VAL_ names is refused (exit 1), as before
    r = run(hdlamp, "scenario", "--dbc", path, "--out", str(tmp_path / "x.log"), "--hold",
            "high", "--mode", "dipped", ok=False)
    assert r.returncode == 1 and "--mode 'dipped'" in r.stderr, r.stderr
