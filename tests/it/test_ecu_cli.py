"""hdlamp ecu's command line on the host (no CAN here: the bus tests run in the VM,
tests/vm/daemon/test_ecu_vcan.py): usage errors name the option and what was expected, bad
databases and lamps are refused with the file and the fault, the windows it writes before
opening the bus follow the rule of docs/ecu.md on the HD84 lamps, and an interface it cannot
open is a failure (exit 1) naming it."""
import json
import os

import pytest

from proc import run

HDLAMP = os.environ["HDLAMP"]
SRC = os.environ.get("HL_SOURCE_DIR", ".")


def ecu(*args):
    return run(HDLAMP, "ecu", *args, ok=False)


@pytest.mark.parametrize("args,msg", [
    ([], "hdlamp ecu: --can IFACE or --fmu OUT.fmu is required"),
    (["--can", "vcan0", "--fmu", "x.fmu"], "hdlamp ecu: --can and --fmu exclude each other"),
    (["--can", "vcan0", "--fault", "late=0"],
     "hdlamp ecu: --fault 'late=0': expected ignore-objects, no-failsafe, late=MS (1..10000), "
     "stuck-counter, bad-crc, or with --fmu step-error=N or step-crash=N"),
    (["--can", "vcan0", "--fault", "step-crash=5"],
     "hdlamp ecu: --fault step-error and step-crash are the FMU's: they need --fmu"),
    (["--can", "vcan0", "--fault", "sleepy"], "hdlamp ecu: --fault 'sleepy': expected"),
    (["--can", "vcan0", "--camera", "1,2"], "hdlamp ecu: --camera '1,2': expected X,Y,Z[,YAW,PITCH]"),
    (["--can", "vcan0", "--lamp-left", "0,0.7,0.65,0"], "hdlamp ecu: --lamp-left '0,0.7,0.65,0': expected"),
    (["--can", "vcan0", "--camera", "1,2,3,4,5,6"], "hdlamp ecu: --camera '1,2,3,4,5,6': expected"),
    (["--can", "vcan0", "--camera", "1,2,3,"], "hdlamp ecu: --camera '1,2,3,': expected"),
    (["--can", "vcan0", "--lamp-right", "0,-0.7,6"], "hdlamp ecu: --lamp-right '0,-0.7,6': expected"),
    (["--can", "vcan0", "--margin-deg", "-1"], "hdlamp ecu: --margin-deg '-1': expected degrees in [0, 45]"),
    (["--can", "vcan0", "--window-fraction", "1"], "hdlamp ecu: --window-fraction '1': expected a number in (0, 1)"),
    (["--can", "vcan0", "--timeout-ms", "2.5"], "hdlamp ecu: --timeout-ms '2.5': expected an integer in [1, 60000]"),
    (["--can", "vcan0", "--lid", "a.lid.exr"], "hdlamp ecu: --lid needs two files"),
    (["--can", "vcan0", "--lamps", "d", "--lid", "a", "--lid", "b"], "hdlamp ecu: --lamps and --lid exclude each other"),
    (["--can", "vcan0", "extra"], "hdlamp ecu: argument 'extra': expected options only"),
])
def test_usage_errors(args, msg):
    r = ecu(*args)
    assert r.returncode == 2, r.stderr
    assert r.stderr.startswith(msg), r.stderr


def test_bad_databases_and_lamps(tmp_path):
    r = ecu("--can", "vcan0", "--inputs-dbc", os.path.join(SRC, "dbc", "hd84.dbc"))
    assert r.returncode == 1
    assert r.stderr.startswith("hdlamp ecu: the input database: no message has the attribute "
                               "HdlInput"), r.stderr
    missing = tmp_path / "none.dbc"
    r = ecu("--can", "vcan0", "--dbc", str(missing))
    assert r.returncode == 1 and f"'{missing}'" in r.stderr, r.stderr
    broken = tmp_path / "broken.dbc"
    broken.write_text('VERSION "x"\nBO_ 12 M: 8 N\n SG_ S : 0|8@1+ (1,0) [0|1] "" N\nBO_ oops\n')
    r = ecu("--can", "vcan0", "--dbc", str(broken))
    assert r.returncode == 1 and r.stderr.startswith(f"hdlamp ecu: '{broken}':4:"), r.stderr
    r = ecu("--can", "vcan0", "--lamps", str(tmp_path))
    assert r.returncode == 1 and "hd84_left.lid.exr" in r.stderr, r.stderr


def test_windows_and_no_interface(tmp_path):
    """The windows are written before the bus is opened; this host has no CAN (or no such
    interface): exit 1, naming it."""
    out = tmp_path / "w.json"
    r = ecu("--can", "hlnosuch0", "--windows", str(out))
    assert r.returncode == 1
    assert r.stderr.startswith("hdlamp ecu: can: 'hlnosuch0': "), r.stderr
    w = json.loads(out.read_text())
    for side in ("left", "right"):
        assert len(w[side]) == 95
        # the matrix rows: 28 windows each, in H order, each narrower than its LED's
        # 60/28 or 40/28 degrees plus its soft edges
        for row, span in ((0, 60.0), (1, 40.0), (2, 40.0)):
            ws = w[side][28 * row:28 * row + 28]
            centres = [(a[0] + a[1]) / 2 for a in ws]
            assert centres == sorted(centres)
            assert all(a[1] - a[0] < 1.45 * span / 28 for a in ws)
            assert all(a[2] < a[3] for a in ws)
        # row 3, the high beam, reaches above the horizon, row 1 stays below it
        assert all(a[3] > 2.0 for a in w[side][56:84])
        assert all(a[3] < 0.0 for a in w[side][0:28])
