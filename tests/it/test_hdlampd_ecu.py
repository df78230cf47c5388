"""hdlampd --ecu (docs/sil.md, "Real time"): the closed loop with no CAN interface at all. The
reference ECU runs in process on the virtual bus vbus0; the restbus and the CAN input open vbus0
as they would a SocketCAN interface. On the IIHS-like straight approach the glare-free high beam
masks the oncoming car (exit 0, the verdict held, no lamp cycle lost); an ECU that ignores
objects fails it (exit 3); an FMU that crashes in a step ends the run with exit 1 and says why.
Every time judged is the daemon's own (its report)."""
import json
import os
import subprocess
import urllib.request

import pytest

from proc import run
from scenario import HDLAMPD, SOURCE_DIR, dbc_path

SCENARIO = os.path.join(SOURCE_DIR, "scenarios", "iihs-approach-straight.json")


@pytest.fixture(scope="module")
def lamps(hdlamp, tmp_path_factory):
    out = tmp_path_factory.mktemp("lamps")
    run(hdlamp, "model", "--out", out)
    return out


def hdlampd(lamps, *args, timeout=120):
    return subprocess.run(
        [HDLAMPD, "--dbc", dbc_path("hd84.dbc"),
         "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
         "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
         "--set", "render.size=160x90", "--set", "stream.tcp=", "--set", "http.listen=",
         *map(str, args)],
        capture_output=True, text=True, timeout=timeout)


def test_the_loop_runs_with_no_can_interface(lamps, tmp_path):
    p = hdlampd(lamps, "--ecu", "reference", "--scenario", SCENARIO, "--exit-at-end",
                "--report", tmp_path / "r.json")
    assert p.returncode == 0, p.stderr[-3000:]
    assert "ecu 'reference' in process on the virtual bus vbus0" in p.stderr
    r = json.loads((tmp_path / "r.json").read_text())
    assert r["verdict"] is True and r["end"] == "scenario_end"
    for lamp in ("left", "right"):
        c = r["cycles"][lamp]
        # the ECU's 50 Hz over the 8.4 s: every cycle complete, none lost, none broken
        assert c["complete"] > 300 and c["lost"] == 0 and c["crc_errors"] == 0
        assert c["incomplete"] == 0 and c["not_rendered"] == 0
    (e,) = [e for e in r["loop"]["event_list"] if e["event"] == "enter"]
    assert e["actor"] == "oncoming-car" and e["masked"] is True
    assert e["t_enter_ns"] < e["t_input_ns"] < e["t_mask_ns"] <= e["t_frame_ns"]
    assert r["loop"]["actors"][0]["frames_over_late"] == 0
    # the exit status line: the ECU's node and the bus
    status = json.loads(p.stdout.strip().splitlines()[-1])
    ecu = status["ecu"]
    assert ecu["model"] == "reference" and ecu["bus"] == "vbus0" and ecu["error"] == ""
    assert ecu["steps"] > 300 and ecu["tx_errors"] == 0
    assert ecu["frames_sent"] == 24 * ecu["steps"]
    assert status["input"]["source"] == "vbus0" and status["restbus"]["interface"] == "vbus0"


def test_an_ecu_ignoring_objects_fails_the_verdict(lamps, tmp_path):
    p = hdlampd(lamps, "--ecu", "reference", "--ecu-fault", "ignore-objects",
                "--scenario", SCENARIO, "--exit-at-end", "--report", tmp_path / "r.json")
    assert p.returncode == 3, p.stderr[-3000:]
    r = json.loads((tmp_path / "r.json").read_text())
    assert r["verdict"] is False and r["loop"]["actors"][0]["frames_over_late"] > 50


def test_a_crashing_fmu_ends_the_run(hdlamp, lamps, tmp_path):
    fmu = tmp_path / "crash.fmu"
    run(hdlamp, "ecu", "--fmu", fmu, "--fault", "step-crash=50")
    p = hdlampd(lamps, "--ecu", fmu, "--scenario", SCENARIO, "--exit-at-end",
                "--report", tmp_path / "r.json")
    assert p.returncode == 1, p.stderr[-3000:]
    assert "killed by signal SIGSEGV" in p.stderr
    r = json.loads((tmp_path / "r.json").read_text())
    assert r["end"] == "ecu_error" and r["verdict"] is False
    assert "SIGSEGV" in r["ecu_error"]


@pytest.mark.parametrize("args,why", [
    (["--ecu", "reference", "--replay", "x.log", "--scenario", SCENARIO],
     "ecu.model runs the loop on the virtual bus vbus0: not with can.replay"),
    (["--ecu", "reference", "--can", "vcan0", "--scenario", SCENARIO],
     "can.interface and restbus.interface must be vbus0 or empty"),
    (["--ecu", "reference"], "ecu.model needs scene.scenario"),
    (["--can", "vcan0", "--ecu-fault", "late=20"], "ecu.faults needs ecu.model"),
])
def test_configurations_that_cannot_be(lamps, args, why):
    p = hdlampd(lamps, *args)
    assert p.returncode == 2 and why in p.stderr, p.stderr[-2000:]


def test_bad_ecu_models_and_faults(lamps, tmp_path):
    p = hdlampd(lamps, "--ecu", tmp_path / "none.fmu", "--scenario", SCENARIO)
    assert p.returncode == 2 and "none.fmu" in p.stderr, p.stderr[-2000:]
    p = hdlampd(lamps, "--ecu", "reference", "--ecu-fault", "sleepy", "--scenario", SCENARIO)
    assert p.returncode == 2 and "ecu.faults: 'sleepy': expected" in p.stderr, p.stderr[-2000:]
