"""The FMVSS 108 ADB suite's straight oncoming scenario in real time on vcan0 (docs/lab.md,
"In real time"): `hdlamp suite run --can vcan0` (which runs hdlampd --suite with its restbus on
vcan0) against `hdlamp ecu` on vcan0, and the same variant in virtual time (the reference ECU
in process, hdlamp suite run): every bin passes or fails alike — with the ECU as it is and with
it ignoring objects.

The bins' maxima differ (the real-time frames are fewer under TCG, and the ECU answers a cycle
later than in virtual time); pass or fail may not."""
import json
import subprocess

import pytest

from proc import run
from scenario import dbc_path
from test_closed_loop import start_ecu, stop_ecu

VARIANT = "oncoming-straight-60mph"


def bins(report):
    return {v["id"]: [(c["name"], c["status"]) for c in v["cases"]] for v in report["variants"]}


@pytest.mark.parametrize("fault", [None, "ignore-objects"])
def test_suite_on_vcan_agrees_with_sil(hdlamp, tmp_path, fault):
    lamps = tmp_path / "lamps"
    run(hdlamp, "model", "--out", lamps)
    ecu, lines = start_ecu(hdlamp, lamps, *(["--fault", fault] if fault else []))
    try:
        d = subprocess.run(
            [hdlamp, "suite", "run", "fmvss108-adb", "--only", VARIANT, "--can", "vcan0",
             "--out", str(tmp_path / "vcan"),
             "--set", f"can.dbc={dbc_path('hd84.dbc')}",
             "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
             "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
             "--set", "render.size=64x36", "--set", "render.combine=cpu",
             "--set", "render.headlight=cpu", "--set", "stream.tcp=", "--set", "http.listen="],
            capture_output=True, text=True, timeout=900)
    finally:
        stop_ecu(ecu, lines)
    print(d.stderr[-3000:])
    assert d.returncode == (3 if fault else 0), d.stderr[-3000:]
    live = json.loads((tmp_path / "vcan" / "report.json").read_text())
    assert live["ecu"] == "can:vcan0"
    (v,) = live["variants"]
    assert v["error"] == "" and v["frames"] > 0
    assert all(c["samples"] > 0 for c in v["cases"])
    s = subprocess.run([hdlamp, "suite", "run", "fmvss108-adb", "--only", VARIANT,
                        *(["--fault", fault] if fault else []), "--out", str(tmp_path / "sil")],
                       capture_output=True, text=True, timeout=900)
    assert s.returncode == d.returncode, s.stderr
    sil = json.loads((tmp_path / "sil" / "report.json").read_text())
    print("vcan:", json.dumps(bins(live)), "sil:", json.dumps(bins(sil)))
    assert bins(live) == bins(sil)
    assert {st for _, st in bins(live)[VARIANT]} == ({"fail"} if fault else {"pass"})
