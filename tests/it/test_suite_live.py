"""hdlampd --suite (docs/lab.md "In real time"): a suite's variants one after the other in real
time with the reference ECU in process on the virtual bus, measured on every published frame.

While a variant runs, /status carries "suite" (the variant, its photometers' newest illuminance
against the limit of their range's bin, the bins so far) and /metrics hdlamp_suite_*. At the end
the results are the ones `hdlamp suite run` writes, and each bin's pass or fail is the one the
same variant gives in virtual time. A signal stops the suite: the variant running and those not
run are errors, never passes. Bad input: exit 2 with what is wrong."""
import json
import os
import signal
import socket
import subprocess
import time
import urllib.request

import pytest

from scenario import HDLAMPD, dbc_path

VARIANT = "oncoming-straight-70mph"


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def daemon_args(hd84, out, port, *extra):
    return [HDLAMPD, "--suite", "fmvss108-adb", "--suite-out", str(out), "--ecu", "reference",
            "--dbc", dbc_path("hd84.dbc"),
            "--set", f"lamps.left={hd84}/hd84_left.lid.exr",
            "--set", f"lamps.right={hd84}/hd84_right.lid.exr",
            "--set", "render.size=160x90", "--set", "stream.tcp=",
            "--set", f"http.listen=127.0.0.1:{port}", *extra]


def get(port, path):
    with urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=5) as r:
        return r.read().decode()


def statuses(p, port, want):
    """/status while the daemon runs, until want(status) or the daemon ends."""
    seen = []
    while p.poll() is None:
        try:
            s = json.loads(get(port, "/status"))
        except (OSError, ValueError):
            time.sleep(0.05)
            continue
        seen.append(s)
        if want(s):
            return s, seen
        time.sleep(0.1)
    return None, seen


def bins(report):
    return {v["id"]: [(c["name"], c["status"]) for c in v["cases"]] for v in report["variants"]}


def test_live_suite_shows_its_photometers_and_agrees_with_sil(hdlamp, hd84, tmp_path):
    port = free_port()
    p = subprocess.Popen(daemon_args(hd84, tmp_path / "live", port, "--suite-only", VARIANT),
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        # a frame past 60 m: the photometer's range in a bin with a limit, bins filled so far
        s, _ = statuses(p, port, lambda s: (s.get("suite") or {}).get("current") and
                        any(b["samples"] for b in s["suite"]["current"]["bins"]))
        assert s, "no /status with the suite's bins"
        metrics = get(port, "/metrics")
    finally:
        _, err = p.communicate(timeout=120)
    print(err[-3000:])
    assert p.returncode == 0, err
    cur = s["suite"]["current"]
    assert s["suite"]["name"] == "fmvss108-adb" and s["suite"]["variants"] == 1
    assert cur["id"] == VARIANT and cur["index"] == 0
    (ph,) = cur["photometers"]
    assert ph["id"] == "driver" and ph["range_m"] > 0 and ph["lx"] is not None
    # the limit of the newest range's bin (Table XXI), none beyond 220 m
    want = 3.1 if ph["range_m"] < 30 else 1.8 if ph["range_m"] < 60 else \
        0.6 if ph["range_m"] < 120 else 0.3 if ph["range_m"] <= 220 else None
    assert ph["limit_lx"] == want, ph
    assert [b["name"] for b in cur["bins"]] == [
        f"oncoming {a} m, photometer driver"
        for a in ("15.0-29.9", "30.0-59.9", "60.0-119.9", "120.0-220.0")]
    assert all(b["status"] in ("passing", "not_reached") for b in cur["bins"])
    assert 'hdlamp_suite_photometer_lux{variant="oncoming-straight-70mph",photometer="driver"}' \
        in metrics
    assert "hdlamp_suite_variants 1" in metrics
    assert "suite fmvss108-adb: 1 variants" in err and "PASSED" in err
    live = json.loads((tmp_path / "live" / "report.json").read_text())
    assert live["ecu"] == "reference" and live["passed"] is True
    (v,) = live["variants"]
    assert v["error"] == "" and v["frames"] > 100
    assert (tmp_path / "live" / "runs" / f"{VARIANT}.json").exists()
    assert (tmp_path / "live" / "index.html").exists()
    assert (tmp_path / "live" / v["plot_file"]).exists()
    # the virtual bus of the run, as candump -L: the restbus's inputs and the ECU's pages
    assert v["trace_file"] == f"traces/{VARIANT}.log"
    ids = {line.split()[2].split("#")[0] for line in
           (tmp_path / "live" / v["trace_file"]).read_text().splitlines()}
    assert {"110", "121", "122", "320", "321"} <= ids, ids
    # the same variant in virtual time: the same pass or fail in every bin
    r = subprocess.run([hdlamp, "suite", "run", "fmvss108-adb", "--only", VARIANT, "--out",
                        str(tmp_path / "sil")], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    sil = json.loads((tmp_path / "sil" / "report.json").read_text())
    assert bins(sil) == bins(live)


def test_live_suite_with_the_ecu_ignoring_objects_fails_as_in_sil(hdlamp, hd84, tmp_path):
    port = free_port()
    d = subprocess.run(daemon_args(hd84, tmp_path / "live", port, "--suite-only", VARIANT,
                                   "--ecu-fault", "ignore-objects"),
                       capture_output=True, text=True, timeout=300)
    assert d.returncode == 3, d.stderr[-3000:]
    live = json.loads((tmp_path / "live" / "report.json").read_text())
    assert live["fault"] == "ignore-objects" and live["passed"] is False
    r = subprocess.run([hdlamp, "suite", "run", "fmvss108-adb", "--only", VARIANT, "--fault",
                        "ignore-objects", "--out", str(tmp_path / "sil")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 3, r.stderr
    sil = json.loads((tmp_path / "sil" / "report.json").read_text())
    assert bins(sil) == bins(live)
    assert {s for b in bins(live).values() for _, s in b} == {"fail"}


def test_a_signal_stops_the_suite_and_nothing_passes_unrun(hd84, tmp_path):
    port = free_port()
    p = subprocess.Popen(daemon_args(hd84, tmp_path / "live", port, "--suite-only",
                                     "oncoming-straight"),
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        s, _ = statuses(p, port, lambda s: (s.get("suite") or {}).get("current") and
                        s["suite"]["current"]["scene_t_s"] > 1.0)
        assert s and s["suite"]["current"]["index"] == 0
        p.send_signal(signal.SIGTERM)
    finally:
        _, err = p.communicate(timeout=120)
    assert p.returncode == 3, err[-3000:]
    rep = json.loads((tmp_path / "live" / "report.json").read_text())
    first, second = rep["variants"]
    assert first["error"].startswith("the run ended before the scenario's end: signal")
    assert second["error"] == "not run: the suite was stopped by a signal"
    assert rep["passed"] is False and rep["totals"]["errors"] == 2


@pytest.mark.parametrize("extra, says", [
    (["--suite-only", "nothing"], "--suite-only 'nothing': no scenario or variant"),
    (["--scenario", "x.json"], "--suite: not with --scenario"),
    (["--suite-out", "/proc/no/such"], "cannot make the directory"),
])
def test_bad_input(hd84, tmp_path, extra, says):
    d = subprocess.run(daemon_args(hd84, tmp_path / "o", free_port(), *extra),
                       capture_output=True, text=True, timeout=60)
    assert d.returncode == 2 and says in d.stderr, d.stderr


def test_a_suite_needs_an_ecu(hd84, tmp_path):
    args = [a for a in daemon_args(hd84, tmp_path / "o", free_port()) if a != "reference"]
    args.remove("--ecu")
    d = subprocess.run(args + ["--can", "vcan9"], capture_output=True, text=True, timeout=60)
    assert d.returncode == 2 and "give --ecu MODEL, or --restbus IFACE" in d.stderr, d.stderr


def test_live_page_shows_the_suite(hd84, tmp_path):
    """The live page's Suite panel in chromium while a variant runs: the variant, the driver's
    photometer with its range, illuminance and limit, the bins so far; its screenshot kept as
    suite-live.png in the build tree (and at HL_LAB_LIVE_SCREENSHOT: docs/lab/suite-live.png)."""
    import shutil
    from test_http_browser import BROWSER_DIR, build_dir, npm_install

    for tool in ("/usr/bin/chromium", shutil.which("node"), shutil.which("npm")):
        if not tool or not os.access(tool, os.X_OK):
            pytest.fail(f"missing {tool}: tools/setup installs chromium, nodejs and npm")
    modules = npm_install()
    port = free_port()
    p = subprocess.Popen(daemon_args(hd84, tmp_path / "live", port, "--suite-only",
                                     "oncoming-straight-60mph"),
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    shot = os.path.join(build_dir(), "suite-live.png")
    try:
        statuses(p, port, lambda s: True)  # the HTTP server is up
        b = subprocess.run(["node", os.path.join(BROWSER_DIR, "suite_live_page.cjs"),
                            f"http://127.0.0.1:{port}/", shot, str(tmp_path / "chromium")],
                           env=dict(os.environ, NODE_PATH=modules), capture_output=True,
                           text=True, timeout=240)
    finally:
        p.send_signal(signal.SIGTERM)
        _, err = p.communicate(timeout=120)
    assert b.returncode == 0, b.stderr + err[-2000:]
    seen = json.loads(b.stdout.strip().splitlines()[-1])
    print(json.dumps(seen, indent=1)[:3000])
    assert seen["pageErrors"] == []
    assert seen["head"].startswith("fmvss108-adb: variant 1 of 1, Oncoming, straight road at "
                                   "60 mph")
    (ph,) = seen["photometers"]
    assert ph["key"] == "driver" and ph["cells"][0] == "driver"
    assert float(ph["cells"][1]) > 0 and ph["cells"][4] in ("under", "over", "")
    assert [b["key"] for b in seen["bins"]] == [b["name"] for b in
                                               seen["status"]["current"]["bins"]]
    assert any(int(b["cells"][1]) > 0 for b in seen["bins"])
    dest = os.environ.get("HL_LAB_LIVE_SCREENSHOT")
    if dest:
        shutil.copyfile(shot, dest)
