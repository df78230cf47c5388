"""hdlamp lid check: regulation verdicts on the HD84 lamp, driven as a user would."""
import json
import os

import numpy as np

from proc import run
from pngio import read_png

REGS = os.path.join(os.environ.get("HL_SOURCE_DIR", "."), "regulations")
PASSING_C = "unece-r149-01-passing-c"
DRIVING_B = "unece-r149-01-driving-b"
ADB = "unece-r149-01-adb-glare"


def check(hdlamp, *args, ok_codes=(0, 1)):
    r = run(hdlamp, "lid", "check", *args, ok=False)
    assert r.returncode in ok_codes, (r.returncode, r.stderr)
    return r


def verdict(hdlamp, hd84, preset, side, regulation, *extra):
    r = check(hdlamp, hd84 / f"hd84_{side}.lid.exr", hd84 / f"{preset}.json", "--lamp", side,
              "--regulation", regulation, "--json", *extra)
    v = json.loads(r.stdout)
    assert r.returncode == (0 if v["pass"] else 1)
    return v


def table_of(hdlamp, hd84, preset, side, regulation):
    """The combined distribution as exported to CSV: (h axis, v axis, values[v][h])."""
    tmp = hd84 / f"check-{preset}-{side}"
    tmp.mkdir(exist_ok=True)
    run(hdlamp, "lid", "combine", hd84 / f"hd84_{side}.lid.exr", hd84 / f"{preset}.json",
        "--lamp", side, "--out", tmp / "L.exr")
    run(hdlamp, "lid", "export", tmp / "L.exr", "--source", "1", "--out", tmp / "L.csv",
        "--angles", "A")
    rows = [l for l in (tmp / "L.csv").read_text().splitlines() if not l.startswith("#")]
    hs = np.array([float(x) for x in rows[0].split(",")[1:]])
    vs, vals = [], []
    for l in rows[1:]:
        f = [float(x) for x in l.split(",")]
        vs.append(f[0])
        vals.append(f[1:])
    vs = np.array(vs)
    vals = np.array(vals)
    order = np.argsort(vs)
    return hs, vs[order], vals[order]


def bilinear(hs, vs, vals, h, v):
    i = np.clip(np.searchsorted(hs, h) - 1, 0, len(hs) - 2)
    j = np.clip(np.searchsorted(vs, v) - 1, 0, len(vs) - 2)
    tx = (h - hs[i]) / (hs[i + 1] - hs[i])
    ty = (v - vs[j]) / (vs[j + 1] - vs[j])
    return ((vals[j, i] * (1 - tx) + vals[j, i + 1] * tx) * (1 - ty) +
            (vals[j + 1, i] * (1 - tx) + vals[j + 1, i + 1] * tx) * ty)


def receiver_mean(table, h, v, size=0.149, n=41):
    """The mean over a square receiver by a fine midpoint rule, independent of the C code."""
    hs, vs, vals = table
    off = ((np.arange(n) + 0.5) / n - 0.5) * size
    return float(np.mean([bilinear(hs, vs, vals, h + a, v + b) for a in off for b in off]))


def test_list_names_every_shipped_set(hdlamp):
    out = check(hdlamp, "--regulation", "list", "--regulations", REGS, ok_codes=(0,)).stdout
    ids = [l.split()[0] for l in out.splitlines()]
    for want in (PASSING_C, DRIVING_B, ADB, "unece-r149-01-passing-v",
                 "unece-r149-01-driving-a", "fmvss108-lower-lb1v", "fmvss108-upper-ub1"):
        assert want in ids, out
    assert "invalid" not in out
    # the default directory (beside the binary) holds the same sets
    assert check(hdlamp, "--regulation", "list", ok_codes=(0,)).stdout == out


def test_low_beam_json_has_the_exact_shape_and_independent_values(hdlamp, hd84):
    v = verdict(hdlamp, hd84, "low", "left", PASSING_C)
    assert list(v) == ["regulation", "beam", "traffic", "aim", "pass", "result", "requirements"]
    assert v["regulation"] == PASSING_C and v["traffic"] == "right" and v["beam"] == "passing"
    assert v["aim"] == {"h_deg": 0, "v_deg": 0}
    reqs = {r["id"]: r for r in v["requirements"]}
    for want in ("B50L", "75R", "50V", "50L", "Zone III", "Segment 25", "Segment BLL"):
        assert want in reqs, sorted(reqs)
    b50l = reqs["B50L"]
    assert list(b50l) == ["id", "kind", "h_deg", "v_deg", "value_cd", "min_cd", "max_cd",
                          "margin", "pass"]
    assert (b50l["kind"], b50l["h_deg"], b50l["v_deg"]) == ("point", -3.43, 0.57)
    assert b50l["min_cd"] is None and b50l["max_cd"] == 350
    for r in v["requirements"]:
        assert r["pass"] == (r["margin"] is not None and r["margin"] >= 0), r
        if r["kind"] in ("segment", "zone", "imax"):
            assert "at_h_deg" in r and "at_v_deg" in r
    assert v["pass"] == all(r["pass"] for r in v["requirements"])
    # the live verdicts' words: "pass" or "FAIL"
    assert v["result"] == ("pass" if v["pass"] else "FAIL")
    # the point values against an independent receiver mean of the exported table
    table = table_of(hdlamp, hd84, "low", "left", PASSING_C)
    for rid in ("B50L", "75R", "50V", "50L", "50R"):
        r = reqs[rid]
        want = receiver_mean(table, r["h_deg"], r["v_deg"])
        assert abs(r["value_cd"] - want) <= 0.01 * want + 0.5, (rid, r["value_cd"], want)
        lim = r["max_cd"] if r["min_cd"] is None else r["min_cd"]
        margin = (lim - r["value_cd"]) / lim if r["min_cd"] is None else \
            (r["value_cd"] - lim) / lim
        if r["min_cd"] is not None and r["max_cd"] is not None:
            margin = min((r["value_cd"] - r["min_cd"]) / r["min_cd"],
                         (r["max_cd"] - r["value_cd"]) / r["max_cd"])
        assert abs(r["margin"] - margin) < 1e-6, rid
    # a segment's deciding value is the extreme of the point values along it
    seg = reqs["Segment 25"]
    assert seg["min_cd"] is not None
    along = [receiver_mean(table, h, seg["at_v_deg"], n=11)
             for h in np.arange(-9.0, 9.0001, 0.1)]
    assert abs(seg["value_cd"] - min(along)) <= 0.01 * min(along) + 0.5


def test_left_hand_traffic_mirrors_h(hdlamp, hd84):
    right = verdict(hdlamp, hd84, "low", "left", PASSING_C)
    left = verdict(hdlamp, hd84, "low", "left", PASSING_C, "--traffic", "left")
    assert left["traffic"] == "left"
    r = {x["id"]: x for x in right["requirements"]}
    l = {x["id"]: x for x in left["requirements"]}
    assert l["B50L"]["h_deg"] == 3.43 and r["B50L"]["h_deg"] == -3.43
    table = table_of(hdlamp, hd84, "low", "left", PASSING_C)
    want = receiver_mean(table, 3.43, 0.57)
    assert abs(l["B50L"]["value_cd"] - want) <= 0.01 * want + 0.5


def test_regulation_aim_reports_the_cutoff(hdlamp, hd84):
    v = verdict(hdlamp, hd84, "low", "left", PASSING_C, "--aim", "regulation")
    cut = v["cutoff"]
    assert abs(v["aim"]["v_deg"] - (-0.57 - cut["v_deg"])) < 1e-9
    assert v["aim"]["h_deg"] == 0
    assert cut["g"] > 0 and cut["sharp_ok"] == (0.13 <= cut["g"] <= 0.40)
    assert cut["linear_ok"] == (cut["linearity_deg"] <= 0.2)


def test_high_beam_against_driving_beam_class_b(hdlamp, hd84):
    v = verdict(hdlamp, hd84, "high", "left", DRIVING_B)
    reqs = {r["id"]: r for r in v["requirements"]}
    imax = [r for r in v["requirements"] if r["kind"] == "imax"]
    assert len(imax) == 1
    hv = [r for r in v["requirements"] if r["kind"] == "point" and r["h_deg"] == 0 and
          r["v_deg"] == 0]
    assert hv and abs(hv[0]["min_cd"] - 0.8 * imax[0]["value_cd"]) < 1e-3 * imax[0]["value_cd"]
    assert reqs


def test_adb_oncoming_window_glarefree_passes_high_fails(hdlamp, hd84):
    def oncoming(preset):
        r = check(hdlamp, hd84 / "hd84_left.lid.exr", hd84 / f"{preset}.json", "--lamp", "left",
                  "--other", hd84 / "hd84_right.lid.exr", "--regulation", ADB, "--json")
        return {x["id"]: x for x in json.loads(r.stdout)["requirements"]}["Oncoming 50 m"]

    assert oncoming("glarefree")["pass"]
    high = oncoming("high")
    assert not high["pass"] and high["value_cd"] > high["max_cd"] == 625


def test_plot_marks_failing_requirements(hdlamp, hd84, tmp_path):
    out = tmp_path / "check.png"
    check(hdlamp, hd84 / "hd84_left.lid.exr", hd84 / "low.json", "--lamp", "left",
          "--regulation", PASSING_C, "--plot", out)
    img = read_png(out)
    assert img.shape[1] >= 800 and img.shape[0] >= 300
    assert len(np.unique(img.reshape(-1, img.shape[2]), axis=0)) > 50
    red = (img[..., 0] > 200) & (img[..., 1] < 80) & (img[..., 2] < 80)
    green = (img[..., 1] > 200) & (img[..., 0] < 100) & (img[..., 2] < 130)
    v = verdict(hdlamp, hd84, "low", "left", PASSING_C)
    assert red.sum() > 0 if not v["pass"] else red.sum() == 0
    assert green.sum() > 0


def test_usage_and_bad_sets(hdlamp, hd84, tmp_path):
    lamp = hd84 / "hd84_left.lid.exr"
    assert check(hdlamp, lamp, ok_codes=(2,)).returncode == 2
    assert check(hdlamp, lamp, "--regulation", PASSING_C, "--traffic", "up",
                 ok_codes=(2,)).returncode == 2
    r = check(hdlamp, lamp, "--regulation", ADB, ok_codes=(2,))
    assert "--other" in r.stderr
    r = check(hdlamp, lamp, "--regulation", "no-such-set", ok_codes=(1,))
    assert "no regulation set 'no-such-set'" in r.stderr
    bad = tmp_path / "bad.json"
    bad.write_text('{\n"id": "bad", "title": "t", "source": "s", "applies_to": "each_lamp",\n'
                   '"angles": "A", "receiver": {"shape": "square", "size_deg": 0.149,\n'
                   '"source": "s"},\n"requirements": [\n'
                   '{"id": "X", "kind": "point", "at": ["3L", "1Q"], "max_cd": 1, '
                   '"source": "s"}]}\n')
    r = check(hdlamp, lamp, "--regulation", bad, ok_codes=(1,))
    assert f"{bad}:6:" in r.stderr and "vertical angle" in r.stderr and "1Q" in r.stderr


def test_table_says_the_sets_beam_and_the_verdict_in_the_live_words(hdlamp, hd84):
    r = check(hdlamp, hd84 / "hd84_left.lid.exr", hd84 / "low.json", "--lamp", "left",
              "--regulation", PASSING_C, ok_codes=(1,))
    lines = r.stdout.splitlines()
    assert lines[2] == "a set for the passing beam", lines[:5]
    assert lines[-1] == "verdict: FAIL"
    assert all(line.split()[-1] in ("pass", "FAIL") for line in lines[6:-2]
               if line and "(" not in line), lines
    assert lines[5].split()[-1] == "pass"  # the column header
