"""hdlamp glare: the light of the HD84 pair at road users' eyes, driven as a user would.

The oncoming driver at 50 m is under the ADB glare limit with the low beam and over it with the
plain high beam; the JSON's E is sum I / r^2 of its own fields; the intensities equal a bilinear
lookup of the combined distribution exported by 'hdlamp lid export' (1 %); the limit is the row of
the set at the largest tabulated distance not beyond the road user's, read here from the set."""
import json
import math
import os
import re

import numpy as np

from pngread import pixel, read_png
from proc import run

REGS = os.path.join(os.environ.get("HL_SOURCE_DIR", "."), "regulations")
ADB = "unece-r149-01-adb-glare"


def scenario(tmp, actors):
    """A straight two-lane road, the ego standing at s 0 in lane 1 with the default lamps."""
    doc = {
        "version": 1, "title": "still", "duration_s": 10,
        "road": {"segments": [{"kind": "straight", "length_m": 400}],
                 "lanes": {"count": 2, "width_m": 3.5}},
        "ego": {"start_s_m": 0, "lane": 1, "speed_mps": 0},
        "actors": actors,
    }
    path = tmp / "scenario.json"
    path.write_text(json.dumps(doc))
    return path


def oncoming(name, eye_x):
    """Still in lane 2, facing -x: its default eye [-1.8, 0.37, 1.1] is at world x eye_x."""
    return {"id": name, "kind": "car", "role": "oncoming",
            "path": {"lane": 2, "start_s_m": eye_x - 1.8, "speed_mps": 0}}


def glare(hdlamp, hd84, scn, preset, *extra, codes=(0, 1)):
    r = run(hdlamp, "glare", "--scenario", scn, "--lid", hd84 / "hd84_left.lid.exr",
            "--lid", hd84 / "hd84_right.lid.exr", "--preset", preset, "--json", *extra, ok=False)
    assert r.returncode in codes, (r.returncode, r.stderr)
    rows = [json.loads(l) for l in r.stdout.splitlines()]
    assert rows
    return r.returncode, rows


def test_low_beam_under_limit_at_50m_high_beam_over(hdlamp, hd84, tmp_path):
    scn = scenario(tmp_path, [oncoming("at50", 50.0)])
    code, (low,) = glare(hdlamp, hd84, scn, "low")
    assert low["id"] == "at50" and low["role"] == "oncoming" and low["kind"] == "car"
    assert low["limit_id"] == "Oncoming 50 m" and low["limit_cd"] == 625
    assert 50.0 <= low["distance_m"] < 50.2
    assert low["pair_half_cd"] < low["limit_cd"] and low["pass"] is True and code == 0
    # the high beam from the built-in preset and from the preset file: the same, over the limit
    for preset in ("high", hd84 / "high.json"):
        code, (high,) = glare(hdlamp, hd84, scn, preset)
        assert high["pair_half_cd"] > high["limit_cd"] == 625
        assert high["pass"] is False and code == 1
        assert high["illuminance_lx"] > 10 * low["illuminance_lx"]


def test_e_is_sum_of_i_over_r_squared(hdlamp, hd84):
    """Along the shipped IIHS-like approach, every frame and road user, both beams."""
    for preset in ("low", "high"):
        _, rows = glare(hdlamp, hd84, "iihs-approach-straight", preset, "--frames", "0:8:0.5")
        assert len(rows) == 17
        assert [r["t_s"] for r in rows] == [0.5 * k for k in range(17)]
        for r in rows:
            left, right = r["lamps"]
            assert (left["side"], right["side"]) == ("left", "right")
            e = sum(l["intensity_cd"] / l["r_m"] ** 2 for l in r["lamps"])
            assert math.isclose(r["illuminance_lx"], e, rel_tol=1e-6, abs_tol=1e-12), r
            half = 0.5 * (left["intensity_cd"] + right["intensity_cd"])
            assert math.isclose(r["pair_half_cd"], half, rel_tol=1e-6, abs_tol=1e-9), r
            assert r["pass"] == (r["pair_half_cd"] <= r["limit_cd"])
        # the car comes closer: the distance falls frame by frame
        d = [r["distance_m"] for r in rows]
        assert all(b < a for a, b in zip(d, d[1:])), d


def segment_rows():
    """The set's rows as {(class, distance): [(h0, h1, max_cd, id)]}, read from the file."""
    with open(os.path.join(REGS, ADB + ".json"), encoding="utf-8") as f:
        reg = json.load(f)

    def h(s):
        return -float(s[:-1]) if s.endswith("L") else float(s[:-1])

    rows = {}
    for q in reg["requirements"]:
        m = re.match(r"(Oncoming|Preceding) (\d+) m", q["id"])
        h0, h1 = sorted((h(q["from"][0]), h(q["to"][0])))
        rows.setdefault((m.group(1).lower(), float(m.group(2))), []).append(
            (h0, h1, q["max_cd"], q["id"]))
    return rows


def test_limit_at_largest_tabulated_distance_not_beyond(hdlamp, hd84, tmp_path):
    eyes = [30.0, 50.0, 75.0, 99.0, 100.0, 150.0, 200.0, 350.0]
    actors = [oncoming(f"on{int(x)}", x) for x in eyes]
    actors.append({"id": "ahead", "kind": "car", "role": "preceding",
                   "path": {"lane": 1, "start_s_m": 120, "speed_mps": 0}})
    actors.append({"id": "walker", "kind": "pedestrian", "role": "roadside",
                   "path": {"lane": 1, "offset_m": -2.5, "start_s_m": 60, "speed_mps": 0}})
    _, rows = glare(hdlamp, hd84, scenario(tmp_path, actors), "low")
    table = segment_rows()
    for r in rows:
        if r["role"] == "roadside":
            assert r["limit_cd"] is None and r["limit_id"] is None and r["pass"] is True
            continue
        dists = sorted(d for (c, d) in table if c == r["role"])
        below = [d for d in dists if d <= r["distance_m"]]
        d = below[-1] if below else dists[0]
        cands = table[(r["role"], d)]
        holding = [c for c in cands if c[0] <= r["axis_h_deg"] <= c[1]]
        want = min(holding or cands, key=lambda c: c[2])
        assert (r["limit_distance_m"], r["limit_cd"], r["limit_id"]) == (d, want[2], want[3]), r
    ids = {r["id"]: r for r in rows}
    assert ids["on30"]["limit_id"] == "Oncoming 50 m"  # closer than the table: its nearest row
    assert ids["on99"]["limit_id"] == "Oncoming 50 m"  # between: not beyond
    assert ids["on350"]["limit_id"] == "Oncoming 200 m"
    assert ids["ahead"]["limit_id"] == "Preceding 100 m"


def combined_table(hdlamp, hd84, preset, side):
    """The lamp's distribution under the preset, as 'lid export' writes it: (hs, vs, values)."""
    tmp = hd84 / f"glare-{preset}-{side}"
    tmp.mkdir(exist_ok=True)
    run(hdlamp, "lid", "combine", hd84 / f"hd84_{side}.lid.exr", hd84 / f"{preset}.json",
        "--lamp", side, "--out", tmp / "L.exr")
    run(hdlamp, "lid", "export", tmp / "L.exr", "--source", "1", "--out", tmp / "L.csv",
        "--angles", "A")
    lines = [l for l in (tmp / "L.csv").read_text().splitlines() if not l.startswith("#")]
    hs = np.array([float(x) for x in lines[0].split(",")[1:]])
    vs, vals = [], []
    for l in lines[1:]:
        f = [float(x) for x in l.split(",")]
        vs.append(f[0])
        vals.append(f[1:])
    order = np.argsort(vs)
    return hs, np.array(vs)[order], np.array(vals)[order]


def bilinear(hs, vs, vals, h, v):
    if not (hs[0] <= h <= hs[-1] and vs[0] <= v <= vs[-1]):
        return 0.0
    i = min(int(np.searchsorted(hs, h, side="right")) - 1, len(hs) - 2)
    j = min(int(np.searchsorted(vs, v, side="right")) - 1, len(vs) - 2)
    fx = (h - hs[i]) / (hs[i + 1] - hs[i])
    fy = (v - vs[j]) / (vs[j + 1] - vs[j])
    lo = (1 - fx) * vals[j][i] + fx * vals[j][i + 1]
    hi = (1 - fx) * vals[j + 1][i] + fx * vals[j + 1][i + 1]
    return (1 - fy) * lo + fy * hi


def test_intensity_is_the_lookup_of_the_combined_distribution(hdlamp, hd84, tmp_path):
    scn = scenario(tmp_path, [oncoming(f"at{x}", float(x)) for x in (50, 100, 200)])
    for preset in ("low", "high"):
        _, rows = glare(hdlamp, hd84, scn, preset)
        for side, k in (("left", 0), ("right", 1)):
            hs, vs, vals = combined_table(hdlamp, hd84, preset, side)
            for r in rows:
                lamp = r["lamps"][k]
                want = bilinear(hs, vs, vals, lamp["h_deg"], lamp["v_deg"])
                assert want > 0
                assert math.isclose(lamp["intensity_cd"], want, rel_tol=0.01), (preset, r)


def test_table_and_usage(hdlamp, hd84, tmp_path):
    scn = scenario(tmp_path, [oncoming("at50", 50.0)])
    lids = ["--lid", hd84 / "hd84_left.lid.exr", "--lid", hd84 / "hd84_right.lid.exr"]
    r = run(hdlamp, "glare", "--scenario", scn, *lids, "--preset", "low", "--at", "0")
    lines = r.stdout.splitlines()
    assert lines[0].split()[:4] == ["t_s", "id", "kind", "role"]
    assert lines[1].split()[1:4] == ["at50", "car", "oncoming"] and lines[1].endswith("pass")
    assert "0 over the limit: PASS" in lines[-1]
    for bad in (["--scenario", scn, "--lid", hd84 / "hd84_left.lid.exr"],
                ["--scenario", scn, *lids, "--at", "1", "--frames", "0:1:1"],
                ["--scenario", scn, *lids, "--frames", "2:1:1"],
                ["--scenario", scn, *lids, "--frames", "0:1:0"],
                ["--scenario", scn, *lids, "--at", "x"],
                [*lids]):
        r = run(hdlamp, "glare", *bad, ok=False)
        assert r.returncode == 2, (bad, r.stderr)
    r = run(hdlamp, "glare", "--scenario", scn, *lids, "--preset", "nope", ok=False)
    assert r.returncode == 1 and "no such preset" in r.stderr
    r = run(hdlamp, "glare", "--scenario", scn, *lids, "--regulation",
            "unece-r149-01-passing-c", ok=False)
    assert r.returncode == 1 and "half the pair" in r.stderr


FAIL_RGB = (255, 50, 50)
PASS_RGB = (60, 230, 90)
NONE_RGB = (95, 95, 95)


def tracks(img):
    """The status tracks under the panels: bands of rows mostly in the track colours, top down,
    each as (first row, the colours of its middle row)."""
    w, h, _, _ = img
    bands, prev = [], False
    for y in range(h):
        row = [pixel(img, x, y) for x in range(w)]
        is_track = sum(p in (FAIL_RGB, PASS_RGB, NONE_RGB) for p in row) > w // 2
        if is_track and not prev:
            bands.append(y)
        prev = is_track
    return [[pixel(img, x, y + 4) for x in range(w)] for y in bands]


def test_plot_marks_the_failing_stretch(hdlamp, hd84, tmp_path):
    """An oncoming car passes the standing ego under the plain high beam: over the limit while it
    comes, under it once the eye is behind the lamps; a pedestrian at the roadside has no limit.
    The PNG's tracks hold the failure colour exactly over the failing frames' stretch."""
    scn = scenario(tmp_path, [
        {"id": "passer", "kind": "car", "role": "oncoming",
         "path": {"lane": 2, "start_s_m": 100, "speed_mps": 20}},
        {"id": "walker", "kind": "pedestrian", "role": "roadside",
         "path": {"lane": 1, "offset_m": -2.5, "start_s_m": 30, "speed_mps": 0}}])
    png = tmp_path / "glare.png"
    code, rows = glare(hdlamp, hd84, scn, "high", "--frames", "0:8:0.25", "--plot", png)
    assert code == 1
    passer = [r for r in rows if r["id"] == "passer"]
    fails = [not r["pass"] for r in passer]
    k = fails.index(False)  # the first frame under the limit
    assert 0 < k < len(fails) and not any(fails[k:]) and all(fails[:k]), fails

    img = read_png(png)
    w, h, ch, _ = img
    assert (w, h, ch) == (1000, 572 + 14 * 2, 3)
    assert len({pixel(img, x, y) for y in range(h) for x in range(w)}) >= 10  # not uniform

    track_passer, track_walker = tracks(img)
    cols = [x for x, p in enumerate(track_passer) if p in (FAIL_RGB, PASS_RGB)]
    x0, x1 = cols[0], cols[-1]
    fail_cols = [x for x, p in enumerate(track_passer) if p == FAIL_RGB]
    assert fail_cols == list(range(x0, fail_cols[-1] + 1))  # one stretch from the start
    assert all(track_passer[x] == PASS_RGB for x in range(fail_cols[-1] + 1, x1 + 1))
    # it ends halfway between the last failing frame and the first passing one
    t_end = 0.5 * (passer[k - 1]["t_s"] + passer[k]["t_s"])
    want = x0 + t_end / 8.0 * (x1 - x0)
    assert abs(fail_cols[-1] - want) <= 1.5, (fail_cols[-1], want)
    # the roadside pedestrian: no limit along the whole axis, never the failure colour
    assert all(track_walker[x] == NONE_RGB for x in range(x0, x1 + 1))
    assert FAIL_RGB not in track_walker
    # the passer's curves are in the failure colour in its stretch only
    red = [(x, y) for y in range(30, h - 40) for x in range(0, w)
           if pixel(img, x, y) == FAIL_RGB]
    assert red and all(x <= fail_cols[-1] + 2 for x, _ in red)

    # the low beam: nobody over the limit, no failure colour anywhere
    code, _ = glare(hdlamp, hd84, scn, "low", "--frames", "0:8:0.25", "--plot", png)
    img = read_png(png)
    assert code == 0 and (img[0], img[1]) == (1000, 600)
    assert not any(pixel(img, x, y) == FAIL_RGB for y in range(img[1]) for x in range(img[0]))
    assert [p for p in tracks(img)[0] if p in (FAIL_RGB, PASS_RGB)] == \
        [PASS_RGB] * (x1 - x0 + 1)
