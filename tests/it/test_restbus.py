"""hdlampd's restbus on this host, which has no CAN (the frames on vcan: tests/vm/daemon/
test_restbus_vcan.py): the daemon runs on with the interface missing, counts every frame due as
link_down, logs the failure once; /status's camera cycle equals the projection the test
computes from the scenario file at the cycle's own scenario time; /metrics passes promtool; a
database without the input attributes, a field of view wider than the database carries
and a range farther than its distance signal stop the start (exit 2) naming what is wrong."""
import json
import subprocess
import time

from proc import run
from restbus_wire import SCENARIO, project
from scenario import HDLAMPD, dbc_path
from test_metrics import parse
from test_verdict_live import Daemon, hold_log


def test_restbus_without_can_counts_and_reports_the_projection(hdlamp, hd84, tmp_path):
    scn = tmp_path / "restbus.json"
    scn.write_text(json.dumps(SCENARIO))
    log = hold_log(hdlamp, str(tmp_path), "high")
    d = Daemon(hd84, log, "--scenario", scn, "--restbus", "nosuchcan7")
    try:
        until = time.monotonic() + 60
        while True:
            status = json.loads(d.get("/status"))
            rb = status["restbus"]
            if rb["camera_cycles"] >= 20 or time.monotonic() > until:
                break
            time.sleep(0.1)
        text = d.get("/metrics")
    finally:
        d.p.send_signal(15)
        assert d.p.wait(30) == 0
    assert rb["interface"] == "nosuchcan7" and not rb["open"]
    assert rb["dbc"].endswith("/hd84_inputs.dbc")
    assert rb["camera_cycles"] >= 20
    # every frame due was counted as not sent, by message and in total
    sent = sum(m["sent"] for m in rb["messages"])
    failed = sum(m["failed"] for m in rb["messages"])
    assert sent == 0 and failed == rb["link_down"] > 0
    veh = rb["messages"][0]
    assert veh["name"] == "HDI_Vehicle" and veh["cycle_ms"] == 20 and veh["id"] == "0x110"
    assert [m["cycle_ms"] for m in rb["messages"][1:]] == [40, 40]
    assert rb["vehicle"] == {"speed_mps": 5, "yaw_rate_rad_s": 0, "steering_rad": 0,
                             "light_switch": "auto", "adb_enable": True}
    logged = [l for l in d.log if "restbus: 'nosuchcan7'" in l]
    assert len(logged) == 1 and "link_down" in logged[0], logged
    # the newest camera cycle at its own scenario time, computed here from the file
    cam = rb["camera"]
    want = project(cam["t_s"])
    assert [o["id"] for o in cam["objects"]] == sorted(want, key=lambda i: want[i][5])
    classes = {1: "oncoming", 2: "preceding", 3: "pedestrian", 0: "other"}
    for o in cam["objects"]:
        w = want[o["id"]]
        assert o["class"] == classes[w[0]]
        for got, exp in zip(o["h_deg"] + o["v_deg"], w[1:5]):
            assert abs(got - exp) <= 1e-4, (o, w)  # /status prints 4 decimals
        assert abs(o["distance_m"] - w[5]) <= 1e-3
    assert rb["objects_sent"] >= 3 * 20
    # /metrics: promtool clean, the restbus families there
    lint = subprocess.run(["promtool", "check", "metrics"], input=text, capture_output=True,
                          text=True)
    assert lint.returncode == 0 and not lint.stdout.strip() and "error" not in lint.stderr, \
        lint.stdout + lint.stderr
    fam = parse(text)
    frames = {l: v for _, l, v in fam["hdlamp_restbus_frames_total"]["samples"]}
    assert frames['message="HDI_Vehicle",result="sent"'] == 0
    assert frames['message="HDI_Vehicle",result="failed"'] > 0
    errors = {l: v for _, l, v in fam["hdlamp_restbus_tx_errors_total"]["samples"]}
    assert errors['reason="link_down"'] > 0 and errors['reason="error"'] == 0
    for name in ("hdlamp_restbus_jitter_max_seconds", "hdlamp_restbus_overruns_total",
                 "hdlamp_restbus_bus_off_total", "hdlamp_restbus_objects_total",
                 "hdlamp_restbus_link_up"):
        assert name in fam, name


def test_restbus_refuses_a_database_without_inputs(hdlamp, hd84, tmp_path):
    scn = tmp_path / "restbus.json"
    scn.write_text(json.dumps(SCENARIO))
    log = hold_log(hdlamp, str(tmp_path), "high", cycles=5)
    base = [HDLAMPD, "--replay", log, "--dbc", dbc_path("hd84.dbc"),
            "--set", f"lamps.left={hd84}/hd84_left.lid.exr",
            "--set", f"lamps.right={hd84}/hd84_right.lid.exr",
            "--set", "render.size=32x18", "--set", "stream.tcp=", "--set", "http.listen=",
            "--scenario", str(scn), "--restbus", "can9"]
    r = subprocess.run(base + ["--set", f"restbus.dbc={dbc_path('hd84.dbc')}"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stderr
    assert (f"hdlampd: restbus.dbc '{dbc_path('hd84.dbc')}': no message has the attribute "
            "HdlInput") in r.stderr, r.stderr
    r = subprocess.run(base + ["--set", "restbus.fov_deg=170,30"], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 2, r.stderr
    assert "restbus.fov_deg 170,30: wider than the database" in r.stderr, r.stderr
    # a database read leniently has its warnings logged (here before the range's refusal)
    odd = tmp_path / "odd_inputs.dbc"
    text = open(dbc_path("hd84_inputs.dbc")).read()
    odd.write_text(text.replace("\nBO_ 272 ", "\nHDL_UNKNOWN_SECTION_ 1 2 3;\nBO_ 272 ", 1))
    line = text[:text.index("\nBO_ 272 ")].count("\n") + 2
    r = subprocess.run(base + ["--set", f"restbus.dbc={odd}", "--set", "restbus.range_m=700"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stderr
    assert f"hdlampd: restbus.dbc '{odd}':{line}:1: warning: " in r.stderr, r.stderr
    assert ("restbus.range_m 700: farther than the database") in r.stderr, r.stderr
    assert "its distance signal's range ends at 655.35 m" in r.stderr, r.stderr
    r = subprocess.run([HDLAMPD, "--replay", log, "--restbus", "can9"], capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 2
    assert "restbus.interface needs scene.scenario" in r.stderr, r.stderr
