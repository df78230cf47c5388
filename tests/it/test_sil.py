"""hdlamp sil (docs/sil.md): the closed loop in virtual time — the restbus, the virtual CAN bus,
the ECU (the reference in process, or an FMI 2.0 FMU) and the verdicts in one process.

The reference ECU holds the glare verdict of the IIHS-like straight approach (exit 0); with
ignore-objects it glares the oncoming car past the reaction time (exit 3). The same two with the
reference exported as an FMU (hdlamp ecu --fmu) give the same reports byte for byte, but for the
ECU's name. Two runs of the same inputs give the same bytes: report, JUnit, candump and BLF
traces. python-can reads both traces back, frame for frame the same. Bad FMUs end with a clear
error naming what is wrong: exit 2 before the run, exit 1 and a failed report when the ECU fails
during it — never a hang."""
import json
import os
import shutil
import subprocess
import zipfile

import pytest

from scenario import SOURCE_DIR

SCENARIOS = [os.path.join(SOURCE_DIR, "scenarios", n) for n in (
    "iihs-approach-straight.json", "iihs-approach-curve-150m-left.json", "preceding-car.json")]
STRAIGHT = SCENARIOS[0]


def sil(hdlamp, *args, timeout=120):
    return subprocess.run([hdlamp, "sil", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout)


@pytest.fixture(scope="module")
def fmus(hdlamp, tmp_path_factory):
    """The reference ECU exported as FMUs: as it is, with ignore-objects, with its own faults."""
    d = tmp_path_factory.mktemp("fmus")
    for name, faults in (("ref", []), ("ignore", ["ignore-objects"]),
                         ("err10", ["step-error=10"]), ("crash5", ["step-crash=5"])):
        args = [hdlamp, "ecu", "--fmu", str(d / f"{name}.fmu")]
        for f in faults:
            args += ["--fault", f]
        subprocess.run(args, check=True, capture_output=True, text=True)
    return d


def without_ecu(report):
    r = json.loads(report)
    r.pop("ecu")
    return r


def test_reference_holds_and_ignoring_objects_fails(hdlamp, tmp_path):
    ok = sil(hdlamp, STRAIGHT, "--report", tmp_path / "ok.json")
    assert ok.returncode == 0, ok.stderr
    r = json.loads((tmp_path / "ok.json").read_text())
    assert r["verdict"] is True and r["end"] == "scenario_end" and r["ecu"] == "reference"
    car = r["loop"]["actors"][0]
    assert car["id"] == "oncoming-car" and car["entries"] == 1 and car["frames_over_late"] == 0
    # every ECU cycle of the 8.388 s made one frame, none lost, none judged twice
    assert r["frames"]["rendered"] == r["loop"]["frames_judged"] == r["loop"]["frames_in"]
    assert r["cycles"]["left"]["lost"] == 0 and r["cycles"]["left"]["crc_errors"] == 0
    bad = sil(hdlamp, STRAIGHT, "--fault", "ignore-objects", "--report", tmp_path / "bad.json")
    assert bad.returncode == 3, bad.stderr
    r = json.loads((tmp_path / "bad.json").read_text())
    assert r["verdict"] is False
    assert r["failed_because"] == [
        "a road user's glare over its limit after the reaction time (or, without a restbus, "
        "at all)"]
    # glared past the 60 ms reaction time, while the car is in the camera's view
    assert r["loop"]["actors"][0]["frames_over_late"] > 100
    assert r["loop"]["actors"][0]["glare_late_s"] > 2.0


def test_the_exported_fmu_gives_the_same_reports(hdlamp, fmus, tmp_path):
    for fault, fmu, code in (([], "ref", 0), (["--fault", "ignore-objects"], "ignore", 3)):
        a = sil(hdlamp, STRAIGHT, *fault, "--report", tmp_path / "a.json")
        b = sil(hdlamp, STRAIGHT, "--ecu", fmus / f"{fmu}.fmu", "--report", tmp_path / "b.json")
        assert a.returncode == b.returncode == code, (a.stderr, b.stderr)
        ra, rb = (tmp_path / "a.json").read_text(), (tmp_path / "b.json").read_text()
        assert json.loads(rb)["ecu"] == f"{fmu}.fmu"
        # byte for byte but for the ECU's name
        assert ra.replace('"ecu":"reference"', f'"ecu":"{fmu}.fmu"') == rb


@pytest.mark.parametrize("scn", SCENARIOS, ids=lambda p: os.path.basename(p))
def test_two_runs_give_the_same_bytes(hdlamp, tmp_path, scn):
    outs = []
    for run in ("1", "2"):
        d = tmp_path / run
        d.mkdir()
        p = sil(hdlamp, scn, "--report", d / "report.json", "--junit", d / "junit.xml",
                "--trace", d / "bus.log")
        assert p.returncode in (0, 3), p.stderr
        p = sil(hdlamp, scn, "--trace", d / "bus.blf", "--frames", d / "frames",
                "--report", d / "report-frames.json", "--set", "render.size=96x54")
        assert p.returncode in (0, 3), p.stderr
        outs.append(d)
    names = sorted(os.listdir(outs[0] / "frames"))
    assert len(names) == json.loads((outs[0] / "report.json").read_text())["frames"]["rendered"]
    names = ["report.json", "junit.xml", "bus.log", "bus.blf"] + [f"frames/{n}" for n in names]
    for name in names:
        a, b = (outs[0] / name).read_bytes(), (outs[1] / name).read_bytes()
        assert a and a == b, name
    # with frames or without, the same report
    assert (outs[0] / "report.json").read_bytes() == (outs[0] / "report-frames.json").read_bytes()
    # no wall-clock time in the report: the one timing line goes to the log only
    assert "render_ms_max\":0.000" in (outs[0] / "report.json").read_text()


def test_traces_read_back_by_python_can(hdlamp, tmp_path):
    can = pytest.importorskip("can") if os.environ.get("CI") != "true" else __import__("can")
    p = sil(hdlamp, STRAIGHT, "--trace", tmp_path / "bus.log")
    assert p.returncode == 0, p.stderr
    p = sil(hdlamp, STRAIGHT, "--trace", tmp_path / "bus.blf")
    assert p.returncode == 0, p.stderr
    log = list(can.LogReader(str(tmp_path / "bus.log")))
    blf = list(can.LogReader(str(tmp_path / "bus.blf")))
    assert len(log) == len(blf) > 10000
    ids = set()
    for a, b in zip(log, blf):
        assert (a.arbitration_id, a.is_extended_id, a.is_fd, bytes(a.data)) == \
            (b.arbitration_id, b.is_extended_id, b.is_fd, bytes(b.data))
        assert abs(a.timestamp - b.timestamp) < 1e-6  # candump -L has microseconds
        ids.add(a.arbitration_id)
    # the restbus's three messages (hd84_inputs.dbc) and the ECU's dimming frames
    assert {0x110, 0x121, 0x122} <= ids and len(ids) > 3
    # frames in the order they ended on the bus, one at a time
    assert all(x.timestamp <= y.timestamp for x, y in zip(log, log[1:]))


def test_junit_as_a_ci_reads_it(hdlamp, tmp_path):
    junitparser = pytest.importorskip("junitparser") if os.environ.get("CI") != "true" \
        else __import__("junitparser")
    p = sil(hdlamp, STRAIGHT, "--fault", "ignore-objects", "--junit", tmp_path / "j.xml")
    assert p.returncode == 3
    suites = list(junitparser.JUnitXml.fromfile(str(tmp_path / "j.xml")))
    assert len(suites) == 1 and suites[0].tests == 2 and suites[0].failures == 1
    cases = {c.name: c for c in suites[0]}
    assert set(cases) == {"frames", "glare at oncoming-car"}
    assert cases["frames"].is_passed
    assert not cases["glare at oncoming-car"].is_passed
    assert "after the reaction time" in cases["glare at oncoming-car"].result[0].message


def repack(src, dst, edit=None, drop=None):
    with zipfile.ZipFile(src) as zi, zipfile.ZipFile(dst, "w") as zo:
        for item in zi.infolist():
            if drop and item.filename == drop:
                continue
            data = zi.read(item.filename)
            if edit and item.filename == "modelDescription.xml":
                data = edit(data.decode()).encode()
            zo.writestr(item, data)


def test_bad_fmus_are_clear_errors_not_hangs(hdlamp, fmus, tmp_path):
    ref = fmus / "ref.fmu"
    (tmp_path / "text.fmu").write_text("this is not a zip archive\n")
    p = sil(hdlamp, STRAIGHT, "--ecu", tmp_path / "text.fmu")
    assert p.returncode == 2 and "text.fmu': not a zip archive" in p.stderr, p.stderr

    repack(ref, tmp_path / "nobin.fmu", drop="binaries/linux64/hdlamp_ecu.so")
    p = sil(hdlamp, STRAIGHT, "--ecu", tmp_path / "nobin.fmu")
    assert p.returncode == 2 and "binaries/linux64/hdlamp_ecu.so" in p.stderr, p.stderr

    def integer_speed(xml):
        i = xml.index('name="VEH_Speed"')
        j = xml.index("<Real", i)
        return xml[:j] + "<Integer" + xml[j + 5:]
    repack(ref, tmp_path / "type.fmu", edit=integer_speed)
    p = sil(hdlamp, STRAIGHT, "--ecu", tmp_path / "type.fmu")
    assert p.returncode == 2, p.stderr
    assert "input 'VEH_Speed'" in p.stderr and "is Integer; expected Real" in p.stderr

    repack(ref, tmp_path / "name.fmu", edit=lambda x: x.replace('"VEH_Speed"', '"VEH_Sped"'))
    p = sil(hdlamp, STRAIGHT, "--ecu", tmp_path / "name.fmu")
    assert p.returncode == 2 and "input 'VEH_Sped'" in p.stderr, p.stderr

    repack(ref, tmp_path / "out.fmu",
           edit=lambda x: x.replace('"right.row1_led05"', '"right.row1_led5"'))
    p = sil(hdlamp, STRAIGHT, "--ecu", tmp_path / "out.fmu")
    assert p.returncode == 2 and "no output 'right.row1_led05'" in p.stderr, p.stderr

    for fmu, what in (("err10", "fmi2DoStep at t=0.16 s returned fmi2Error"),
                      ("crash5", "killed by signal SIGSEGV")):
        p = sil(hdlamp, STRAIGHT, "--ecu", fmus / f"{fmu}.fmu", "--report", tmp_path / "r.json",
                "--junit", tmp_path / "j.xml", timeout=60)
        assert p.returncode == 1 and what in p.stderr, p.stderr
        r = json.loads((tmp_path / "r.json").read_text())
        assert r["end"] == "ecu_error" and r["verdict"] is False and what in r["ecu_error"]
        assert r["failed_because"] == [
            "the ECU in the loop failed: the run did not reach the scenario's end"]
        assert what in (tmp_path / "j.xml").read_text()


def test_bad_options(hdlamp, tmp_path):
    p = sil(hdlamp, STRAIGHT, "--fault", "sleepy")
    assert p.returncode == 2 and "--fault 'sleepy': expected" in p.stderr
    p = sil(hdlamp, tmp_path / "none.json")
    assert p.returncode == 2 and "none.json" in p.stderr
    p = sil(hdlamp, STRAIGHT, "--ecu", tmp_path / "missing.fmu")
    assert p.returncode == 2 and "missing.fmu" in p.stderr
    p = sil(hdlamp, STRAIGHT, "--trace", tmp_path / "bus.txt")
    assert p.returncode == 2 and "bus.txt" in p.stderr
    p = sil(hdlamp)
    assert p.returncode == 2 and "usage: hdlamp sil" in p.stderr


def test_latency_is_the_derivation(hdlamp, tmp_path):
    """docs/loop.md, "In virtual time: the exact derivation": the report's input, mask and frame
    times of the car's enter event are the sums of the wire times of the frames that carried
    them, counted here bit by bit (tests/it/canwire.py) from the run's own trace, to the ns."""
    import canwire
    p = sil(hdlamp, STRAIGHT, "--report", tmp_path / "r.json", "--trace", tmp_path / "bus.log")
    assert p.returncode == 0, p.stderr
    r = json.loads((tmp_path / "r.json").read_text())
    ev = [e for e in r["loop"]["event_list"] if e["event"] == "enter"]
    assert len(ev) == 1 and ev[0]["masked"]
    ev = ev[0]
    frames = []
    for line in (tmp_path / "bus.log").read_text().splitlines():
        t, _, f = line.split()
        can_id, data = f.split("#")
        frames.append((round(float(t.strip("()")) * 1e6), int(can_id, 16), bytes.fromhex(data)))
    bit_ns = 2000  # 500 kbit/s
    ifs = canwire.INTERMISSION * bit_ns

    def w(f):
        return canwire.frame_bits(f[1], f[2]) * bit_ns

    def sent_at(d_ns, ids, n):
        """The first n frames of these IDs that end after d: back to back from d on."""
        fs = [f for f in frames if f[0] * 1000 > d_ns and f[1] in ids][:n]
        # the trace's own times agree with the model frame by frame (µs in candump -L)
        end = d_ns
        for k, f in enumerate(fs):
            end += (ifs if k else 0) + w(f)
            assert f[0] == end // 1000, (f, end)
        return end

    d = ev["t_enter_ns"]
    assert d == 1480000000 and ev["t_enter_s"] == 1.48
    # input: the vehicle state, then the car's info and box frames
    t_input = sent_at(d, {0x110, 0x121, 0x122}, 3)
    assert ev["t_input_ns"] == t_input
    assert t_input - d == 696000  # docs/loop.md: 115 + 113 + 114 bits and two intermissions
    # mask: the ECU's next step, the vehicle state of that deadline, the 24 masked pages
    s = d + 20000000
    t_mask = sent_at(s, {0x110, 0x320, 0x321}, 25)
    assert ev["t_mask_ns"] == t_mask and t_mask - d == 25978000
    # frame: the right lamp's cycle completed the pair within render.coalesce_ms (5 ms of the
    # left's): the frame is made at once
    assert ev["t_frame_ns"] == t_mask
    assert r["loop"]["latency_ms"]["mask"]["max"] == 25.978
    assert r["loop"]["latency_ms"]["frame"]["max"] == 25.978
    # one frame per ECU cycle (420 of 20 ms in the 8.388 s), but for the first: the left lamp's
    # first cycle makes a frame alone (the right had none yet, nothing to wait for), the
    # right's first another after the window
    assert r["cycles"]["left"]["complete"] == r["cycles"]["right"]["complete"] == 420
    assert r["frames"]["rendered"] == 421
