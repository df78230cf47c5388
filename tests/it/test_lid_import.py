# SPDX-License-Identifier: MIT
"""hdlamp lid import / export, end to end through the built binary.

Values are checked against the input files' own tables, read here independently of the C
readers, and round trips against the LID written by 'hdlamp model'.
"""
import os
import subprocess
from pathlib import Path

import pytest

HDLAMP = os.environ.get("HDLAMP", "hdlamp")
SOURCE = Path(os.environ.get("HL_SOURCE_DIR", Path(__file__).resolve().parents[2]))
PHOTOMETRY = SOURCE / "tests" / "data" / "photometry"
MALFORMED = SOURCE / "tests" / "data" / "malformed"


def run(*args, check=True):
    p = subprocess.run([HDLAMP, *map(str, args)], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"hdlamp {' '.join(map(str, args))}: {p.returncode}\n{p.stderr}")
    return p


def ies_table(path):
    """(type, {(horizontal, vertical): cd}) from the numbers after TILT=NONE (LM-63 order)."""
    text = Path(path).read_text()
    nums = [float(x) for x in text[text.index("TILT=NONE") + 9:].split()]
    n_v, n_h, ptype = int(nums[3]), int(nums[4]), int(nums[5])
    scale = nums[2] * nums[10] * nums[11]
    vert = nums[13:13 + n_v]
    hori = nums[13 + n_v:13 + n_v + n_h]
    cd = nums[13 + n_v + n_h:]
    assert len(cd) == n_v * n_h
    return ptype, {(h, v): cd[i * n_v + j] * scale
                   for i, h in enumerate(hori) for j, v in enumerate(vert)}


def csv_table(path):
    """(system, {(column angle, row angle): cd}) of a CSV goniometer table."""
    rows = [l for l in Path(path).read_text().splitlines() if l.strip() and not l.startswith("#")]
    head = rows[0].split(",")
    cols = [float(x) for x in head[1:]]
    table = {}
    for line in rows[1:]:
        cells = line.split(",")
        assert len(cells) == len(cols) + 1
        for c, x in zip(cols, cells[1:]):
            table[(round(c, 6), round(float(cells[0]), 6))] = float(x)
    return head[0], table


def close(a, b):
    return abs(a - b) <= 1e-5 * max(1.0, abs(b))


def manifest(path, grid, sources):
    lines = ["# written by test_lid_import.py", "[grid]", *grid, ""]
    for k, (f, name) in enumerate(sources, 1):
        lines += [f"[source {k}]", f"file = {f}", f"name = {name}", ""]
    path.write_text("\n".join(lines))
    return path


def test_real_type_b_files_read_back_at_their_own_angles(tmp_path):
    files = ["flood_typeB_bilateral.ies", "flood_typeB_full.ies"]
    m = manifest(tmp_path / "b.ini", ["angles = B", "h = -60, 60", "v = -30, 20", "step = 1"],
                 [(PHOTOMETRY / f, f.split(".")[0]) for f in files])
    out = run("lid", "import", "--manifest", m, "--out", tmp_path / "b.lid.exr")
    assert [l.split("\t")[1] for l in out.stdout.splitlines()] == [f.split(".")[0] for f in files]
    for k, f in enumerate(files, 1):
        ptype, table = ies_table(PHOTOMETRY / f)
        assert ptype == 2
        run("lid", "export", tmp_path / "b.lid.exr", "--source", k, "--out", tmp_path / f"{k}.csv")
        system, got = csv_table(tmp_path / f"{k}.csv")
        assert system == "B"
        checked = 0
        for (h, v), cd in table.items():
            for hh in ([h, -h] if f.endswith("bilateral.ies") else [h]):
                if hh == int(hh) and v == int(v) and -60 <= hh <= 60 and -30 <= v <= 20:
                    assert close(got[(hh, v)], cd), (f, hh, v, got[(hh, v)], cd)
                    checked += 1
        assert checked > 100


def test_real_type_c_files_read_back_at_their_own_angles(tmp_path):
    # type C (gamma from the nadir, C counter-clockwise from the axis) is type A with
    # H = -C and V = gamma - 90: on a type A grid at 1 degree the table's angles are samples
    files = ["canopy_typeC_quadrant.ies", "indoor_typeC_full.ies"]
    m = manifest(tmp_path / "c.ini", ["h = -90, 90", "v = -30, 20", "step = 1"],
                 [(PHOTOMETRY / f, f.split(".")[0]) for f in files])
    run("lid", "import", "--manifest", m, "--out", tmp_path / "c.lid.exr")
    for k, f in enumerate(files, 1):
        ptype, table = ies_table(PHOTOMETRY / f)
        assert ptype == 1
        quadrant = max(c for c, _ in table) == 90
        run("lid", "export", tmp_path / "c.lid.exr", "--source", k, "--out", tmp_path / f"{k}.csv")
        system, got = csv_table(tmp_path / f"{k}.csv")
        assert system == "A"
        checked = lit = 0
        for (c, gamma), cd in table.items():
            for cc in ([c, 180 - c, 180 + c, 360 - c] if quadrant else [c]):
                h = ((-cc + 180) % 360) - 180
                v = gamma - 90
                if h == int(h) and v == int(v) and -90 <= h <= 90 and -30 <= v <= 20:
                    assert close(got.get((h, v), 0.0), cd), (f, c, gamma, got.get((h, v)), cd)
                    checked += 1
                    lit += cd > 0
        assert checked > 50 and lit > 25


def grid_values(tmp_path, lid, source, tag):
    """The source's grid samples (type A, grid step): its CSV export in its own angles."""
    out = tmp_path / f"{tag}.csv"
    run("lid", "export", lid, "--source", source, "--out", out)
    return csv_table(out)[1]


@pytest.mark.parametrize("angles,fmt,sources", [
    ("A", "ies", ["row1_led01", "row2_led15", "row3_led28", "apron", "lb_rise"]),
    ("C", "ies", ["row1_led01", "row2_led15", "row3_led28", "apron", "lb_rise"]),
    ("A", "csv", ["row2_led15", "motorway"]),
    ("C", "csv", ["row2_led15", "motorway"]),
    ("B", "ies", ["row1_led01", "row3_led28", "hb_spot", "lb_rise"]),
    ("B", "csv", ["row2_led15", "motorway"]),
])
def test_round_trip_through_export_and_import(tmp_path, angles, fmt, sources):
    run("model", "--out", tmp_path)
    lamp = tmp_path / "hd84_left.lid.exr"
    exported = []
    for s in sources:
        f = tmp_path / f"{s}.{fmt}"
        run("lid", "export", lamp, "--source", s, "--angles", angles, "--out", f)
        exported.append((f, s))
    m = manifest(tmp_path / "rt.ini", [], exported)
    run("lid", "import", "--manifest", m, "--out", tmp_path / "back.lid.exr")
    info = run("lid", "info", tmp_path / "back.lid.exr").stdout
    assert "type A" in info and "900 x 250" in info
    for k, s in enumerate(sources, 1):
        want = grid_values(tmp_path, lamp, s, f"want{k}")
        got = grid_values(tmp_path, tmp_path / "back.lid.exr", k, f"got{k}")
        peak = max(want.values())
        worst = 0.0
        for key in set(want) | set(got):
            w, g = want.get(key, 0.0), got.get(key, 0.0)
            if w > 0.01 * peak and abs(key[0]) < 89 and -29 < key[1] < 19:
                worst = max(worst, abs(g - w) / w)
        assert worst <= 0.005, (s, angles, fmt, worst)


def test_import_rejects_tilt_tables_naming_file_and_line(tmp_path):
    m = manifest(tmp_path / "t.ini", [], [(MALFORMED / "ies_tilt_include.ies", "tilted")])
    p = run("lid", "import", "--manifest", m, "--out", tmp_path / "t.lid.exr", check=False)
    assert p.returncode == 1
    assert "ies_tilt_include.ies':4:6: TILT=INCLUDE" in p.stderr
    assert "(source 1)" in p.stderr
    assert not (tmp_path / "t.lid.exr").exists()


@pytest.mark.parametrize("name", sorted(p.name for p in MALFORMED.iterdir()
                                        if p.suffix in (".ies", ".ldt", ".csv")))
def test_import_rejects_every_malformed_file(tmp_path, name):
    m = manifest(tmp_path / "bad.ini", [], [(MALFORMED / name, "bad")])
    p = run("lid", "import", "--manifest", m, "--out", tmp_path / "bad.lid.exr", check=False)
    assert p.returncode == 1
    assert f"{name}':" in p.stderr and "expected" in p.stderr
    assert not (tmp_path / "bad.lid.exr").exists()


def test_bad_manifest_and_usage(tmp_path):
    m = tmp_path / "m.ini"
    m.write_text("[source 1]\nfile = a.ies\nname = a\nwatts = 5\n")
    p = run("lid", "import", "--manifest", m, "--out", tmp_path / "x.lid.exr", check=False)
    assert p.returncode == 1
    assert f"'{m}':4:1: expected a [source N] key" in p.stderr
    assert run("lid", "import", "--out", tmp_path / "x.lid.exr", check=False).returncode == 2
    run("model", "--out", tmp_path)
    p = run("lid", "export", tmp_path / "hd84_left.lid.exr", "--out", tmp_path / "x.ies",
            check=False)
    assert p.returncode == 2 and "give --source" in p.stderr
    p = run("lid", "export", tmp_path / "hd84_left.lid.exr", "--source", "nope",
            "--out", tmp_path / "x.ies", check=False)
    assert p.returncode == 1 and "no source 'nope'" in p.stderr
    assert run("lid", "export", "--help").returncode == 0


def test_combined_distribution_exports_and_imports(tmp_path):
    # a combined LID (channel I, one distribution) needs no --source
    run("model", "--out", tmp_path)
    run("lid", "combine", tmp_path / "hd84_left.lid.exr", tmp_path / "low.json", "--lamp", "left",
        "--out", tmp_path / "low.lid.exr")
    out = run("lid", "export", tmp_path / "low.lid.exr", "--angles", "C", "--out",
              tmp_path / "low.ies").stdout
    assert "type C" in out
    text = (tmp_path / "low.ies").read_text()
    assert text.startswith("IES:LM-63-2019\n") and "\nTILT=NONE\n" in text
    assert text.split("TILT=NONE\n")[1].split()[5] == "1"  # photometric type 1 = C
    m = manifest(tmp_path / "low.ini", [], [(tmp_path / "low.ies", "low_beam")])
    run("lid", "import", "--manifest", m, "--out", tmp_path / "back.lid.exr")
    want = grid_values(tmp_path, tmp_path / "low.lid.exr", 1, "want")
    got = grid_values(tmp_path, tmp_path / "back.lid.exr", "low_beam", "got")
    peak = max(want.values())
    assert peak > 20000  # docs/design.md §1: low beam peaks near 25 kcd
    for key, w in want.items():
        if w > 0.01 * peak and abs(key[0]) < 89 and -29 < key[1] < 19:
            assert abs(got.get(key, 0.0) - w) <= 0.005 * w, (key, w, got.get(key))
