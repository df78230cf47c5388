"""hdlamp model / lid info / lid combine / lid plot, driven as a user would."""
import re

from proc import run
from pngread import pixel, read_png


def test_model_info_shows_95_sources_900x250_type_a(hdlamp, hd84):
    for side in ("left", "right"):
        out = run(hdlamp, "lid", "info", hd84 / f"hd84_{side}.lid.exr").stdout
        assert "sources: 95" in out
        assert "grid:    900 x 250 samples (H x V)" in out
        assert "angles:  type A" in out
        assert "H:       -89.90 .. 89.90 deg, step 0.2000" in out
        assert "V:       -29.90 .. 19.90 deg, step 0.2000" in out
        rows = [l for l in out.splitlines() if re.match(r"^\s+\d+\s", l)]
        assert len(rows) == 95
        assert "row1_led01" in rows[0] and "sign" in rows[94]


def test_exrheader_lists_every_channel_and_attribute(hd84):
    out = run("exrheader", hd84 / "hd84_left.lid.exr").stdout
    for k in range(1, 96):
        assert re.search(rf"^\s+src{k:04d}, 32-bit floating-point", out, re.M), k
    assert "src0096" not in out
    assert re.search(r'^hdlamp:angles \(type string\): "A"', out, re.M)
    assert re.search(r"^hdlamp:h \(type v2f\): \(-89\.9 89\.9\)", out, re.M)
    assert re.search(r"^hdlamp:v \(type v2f\): \(-29\.9 19\.9\)", out, re.M)
    assert re.search(r'^hdlamp:unit \(type string\): "cd"', out, re.M)
    assert re.search(r"^hdlamp:sourceNames \(type string\)", out, re.M)
    assert "zip, multi-scanline blocks" in out
    assert "(0 0) - (899 249)" in out


def test_combine_writes_one_channel_I_with_the_same_attributes(hdlamp, hd84, tmp_path):
    out = tmp_path / "L.exr"
    run(hdlamp, "lid", "combine", hd84 / "hd84_left.lid.exr", hd84 / "low.json",
        "--lamp", "left", "--out", out)
    info = run(hdlamp, "lid", "info", out).stdout
    assert "combined distribution (channel I)" in info
    assert "sources: 1" in info
    peak = float(re.search(r"^peak:\s+([\d.]+) cd", info, re.M).group(1))
    assert 15000 <= peak <= 35000
    hdr = run("exrheader", out).stdout
    assert re.search(r"^\s+I, 32-bit floating-point", hdr, re.M)
    assert re.search(r'^hdlamp:angles \(type string\): "A"', hdr, re.M)


def test_plot_shows_the_cutoff_step_and_high_beam_hot_spot(hdlamp, hd84, tmp_path):
    # Plot geometry (tools/plot.c): 1 px per sample, plot area at x = 48, y = 30.
    def at(img, h_deg, v_deg):
        x = 48 + round((h_deg + 89.9) / 0.2)
        y = 30 + round((19.9 - v_deg) / 0.2)
        return pixel(img, x, y)

    low = tmp_path / "low.png"
    run(hdlamp, "lid", "plot", hd84 / "hd84_left.lid.exr", hd84 / "low.json", "--lamp", "left",
        "--out", low)
    img = read_png(low)
    assert img[0] == 48 + 900 + 110 and img[1] == 30 + 250 + 40
    colours = {px for row in img[3] for px in zip(row[0::3], row[1::3], row[2::3])}
    assert len(colours) > 200, "a diagram of a lamp is not a handful of colours"
    # Above the horizon: black left of H = 0, lit right of it (the step).
    assert at(img, -3.1, 0.5) == (0, 0, 0)
    assert sum(at(img, 3.1, 0.5)) > 200
    # Far outside the lamp's field: black.
    assert at(img, -72.9, 12.9) == (0, 0, 0)

    high = tmp_path / "high.png"
    run(hdlamp, "lid", "plot", hd84 / "hd84_left.lid.exr", hd84 / "high.json", "--lamp", "left",
        "--out", high)
    img = read_png(high)
    # The hot spot just above the horizon is in the top of the colour scale (red end).
    r, g, b = at(img, 0.9, 0.9)  # off the H = 0 axis line
    assert r > 100 and r > 2 * g and r > 2 * b, (r, g, b)
    assert sum(at(img, -3.1, 0.5)) > 200  # high beam lights the left too


def test_errors_name_the_file_and_exit_codes(hdlamp, hd84, tmp_path):
    r = run(hdlamp, "lid", "info", tmp_path / "absent.lid.exr", ok=False)
    assert r.returncode == 1
    assert f"'{tmp_path / 'absent.lid.exr'}': No such file or directory" in r.stderr
    r = run(hdlamp, "lid", "frobnicate", "x", ok=False)
    assert r.returncode == 2
    r = run(hdlamp, "model", ok=False)
    assert r.returncode == 2
    bad = tmp_path / "bad.json"
    bad.write_text('{"left": [1, 2],\n "right": [1, 99]}\n')
    r = run(hdlamp, "lid", "combine", hd84 / "hd84_left.lid.exr", bad, "--lamp", "left",
            "--out", tmp_path / "x.exr", ok=False)
    assert r.returncode == 1
    assert f"'{bad}':2:15: right[1]: 99 is out of range: expected an integer in [0, 63]" \
        in r.stderr
    short = tmp_path / "short.json"
    short.write_text('{"left": [1, 2], "right": [1, 2]}')
    r = run(hdlamp, "lid", "plot", hd84 / "hd84_left.lid.exr", short, "--lamp", "left",
            "--out", tmp_path / "x.png", ok=False)
    assert r.returncode == 1
    assert "has 2 values per lamp; the lamp has 95 sources" in r.stderr


def test_pixel_lamp_for_scaling(hdlamp, tmp_path):
    run(hdlamp, "model", "--sources", "1024", "--out", tmp_path)
    out = run(hdlamp, "lid", "info", tmp_path / "pixel1024_left.lid.exr").stdout
    assert "sources: 1024" in out
    assert (tmp_path / "pixel1024_all.json").exists()
