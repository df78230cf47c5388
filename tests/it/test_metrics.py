"""hdlampd's /metrics parses as Prometheus text exposition format 0.0.4, checked strictly."""
import re
import subprocess
import time
import urllib.request

from proc import run
from scenario import HDLAMPD, dbc_path, generate

NAME = r"[a-zA-Z_:][a-zA-Z0-9_:]*"
LABEL = r'[a-zA-Z_][a-zA-Z0-9_]*="(?:[^"\\\n]|\\[\\"n])*"'
SAMPLE = re.compile(rf"^({NAME})(?:\{{((?:{LABEL})(?:,{LABEL})*)?\}})? (-?(?:[0-9.]+(?:e[+-]?[0-9]+)?|\+Inf|-Inf|NaN))$")


def parse(text):
    """{family: {"type", "help", "samples": [(name, labels, value)]}}; raises on any fault."""
    families, current = {}, None
    assert text.endswith("\n"), "the exposition ends with a newline"
    for n, line in enumerate(text.splitlines(), 1):
        if line.startswith("# HELP "):
            name, _, help_ = line[7:].partition(" ")
            assert re.fullmatch(NAME, name), (n, line)
            families.setdefault(name, {"samples": []})["help"] = help_
        elif line.startswith("# TYPE "):
            name, _, kind = line[7:].partition(" ")
            assert kind in ("counter", "gauge", "histogram", "summary", "untyped"), (n, line)
            fam = families.setdefault(name, {"samples": []})
            assert "type" not in fam and not fam["samples"], f"line {n}: TYPE after samples"
            fam["type"] = kind
            current = name
        else:
            m = SAMPLE.match(line)
            assert m, f"line {n}: not a sample: {line!r}"
            name, labels, value = m.group(1), m.group(2) or "", float(m.group(3))
            base = re.sub(r"_(bucket|sum|count)$", "", name)
            fam = families.get(name) or families.get(base)
            assert fam is not None and current in (name, base), f"line {n}: {name} outside its family"
            fam["samples"].append((name, labels, value))
    for name, fam in families.items():
        assert "type" in fam and "help" in fam and fam["samples"], name
        if fam["type"] == "counter":
            assert all(v >= 0 for _, _, v in fam["samples"]), name
        if fam["type"] == "histogram":
            # one series per set of labels other than le (e.g. stage="mask")
            series = {}
            for s, l, v in fam["samples"]:
                le = re.search(r'(?:^|,)le="([^"]*)"', l)
                key = re.sub(r',?le="[^"]*"', "", l).strip(",")
                series.setdefault(key, {"buckets": [], "count": []})
                if s.endswith("_bucket"):
                    assert le, f"{name}: a bucket without le"
                    series[key]["buckets"].append((le.group(1), v))
                elif s.endswith("_count"):
                    series[key]["count"].append(v)
            for key, ser in series.items():
                buckets = ser["buckets"]
                assert buckets and buckets[-1][0] == "+Inf", f"{name}{{{key}}}: last bucket +Inf"
                values = [v for _, v in buckets]
                assert values == sorted(values), f"{name}{{{key}}}: buckets must be cumulative"
                assert ser["count"] == [values[-1]], \
                    f"{name}{{{key}}}: _count equals the +Inf bucket"
    return families


def test_metrics_parse_and_count_the_drive(hdlamp, tmp_path):
    run(hdlamp, "model", "--out", tmp_path)
    log, _, counters = generate(hdlamp, dbc_path("hd84.dbc"), str(tmp_path), phase=5)
    p = subprocess.Popen([HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"),
                          "--set", f"lamps.left={tmp_path}/hd84_left.lid.exr",
                          "--set", f"lamps.right={tmp_path}/hd84_right.lid.exr",
                          "--set", "render.size=160x90", "--set", "stream.tcp=",
                          "--set", "http.listen=127.0.0.1:0", "--loop",
                          # the verdict families too, for promtool's lint below
                          "--set", "verdict.sets=unece-r149-01-passing-c,unece-r149-01-adb-glare"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    port = None
    while port is None:
        line = p.stderr.readline()
        assert line, "hdlampd exited early"
        if "live view on http://" in line:
            port = int(line.rsplit("(port ", 1)[1].split(")")[0])
    # scrape until a whole pass of the drive was counted (an event; a busy machine is slower)
    until = time.monotonic() + 60
    while True:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/metrics", timeout=10) as r:
            ctype = r.headers.get("Content-Type")
            text = r.read().decode()
        left = [v for s, l, v in parse(text)["hdlamp_cycles_total"]["samples"]
                if l == 'lamp="left"']
        if left and left[0] >= counters["left"]["cycles"] or time.monotonic() > until:
            break
        time.sleep(0.1)
    p.send_signal(15)
    assert p.wait(10) == 0
    # Prometheus' own linter: names, units, types, help; any message is a failure
    lint = subprocess.run(["promtool", "check", "metrics"], input=text, capture_output=True,
                          text=True)
    assert lint.returncode == 0 and not lint.stdout.strip() and "error" not in lint.stderr, \
        lint.stdout + lint.stderr
    assert ctype.startswith("text/plain; version=0.0.4")
    fam = parse(text)
    for name in ("hdlamp_cycles_total", "hdlamp_crc_errors_total", "hdlamp_lost_cycles_total",
                 "hdlamp_incomplete_cycles_total", "hdlamp_ring_snapshots_total",
                 "hdlamp_lamp_stale", "hdlamp_bus_state", "hdlamp_render_seconds"):
        assert name in fam, name
    assert fam["hdlamp_render_seconds"]["type"] == "histogram"
    crc = {l: v for _, l, v in fam["hdlamp_crc_errors_total"]["samples"]}
    # one CRC error per pass of the drive, on the left lamp
    assert crc['lamp="left"'] >= 1 and crc['lamp="right"'] == 0
    cycles = {l: v for _, l, v in fam["hdlamp_cycles_total"]["samples"]}
    assert cycles['lamp="left"'] >= counters["left"]["cycles"]
