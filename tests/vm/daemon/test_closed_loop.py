"""The closed loop on vcan0 (docs/loop.md): hdlampd plays the IIHS-like straight approach and
sends the ECU's inputs (restbus), `hdlamp ecu` answers with its dimming cycles, hdlampd renders
them and judges the glare at the oncoming driver's eye; --exit-at-end stops it at the
scenario's end and --report writes the verdict.

Every time judged here is one of the daemon's own CLOCK_MONOTONIC stamps (the camera cycle's
deadline, the restbus's send, the lamp cycle's completion, the render's end) or a scenario time,
never the test's sleeps. The latency bound is the design's (docs/loop.md, "How many cycles"):
the ECU answers at its next 20 ms deadline after the camera cycle arrived (<= 1 cycle, plus
how late the ECU woke), the render thread shows the first cycle complete after it finished the
frame it was rendering (<= 1 render), and that frame's render ends one render later. Under TCG
the render takes far longer than on the host, so the bound uses the daemon's own largest render
time; and the reaction time the verdict allows is set to 1 s here (the 60 ms default is the
host's figure: TCG is ~50x slower), which the ignore-objects run still fails by seconds."""
import json
import os
import subprocess

from proc import run
from scenario import HDLAMPD, dbc_path
from vmutil import Lines

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.environ.get("HL_SOURCE_DIR", os.path.join(HERE, "..", "..", ".."))
SCENARIO = os.path.join(SOURCE, "scenarios", "iihs-approach-straight.json")
ECU_CYCLE_MS = 20.0
REACTION_MS = 1000.0


def start_ecu(hdlamp, lamps, *args):
    p = subprocess.Popen([hdlamp, "ecu", "--can", "vcan0", "--lamps", str(lamps), *args],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines = Lines(p)
    start = lines.next(timeout=240)
    assert start["event"] == "start", start
    return p, lines


def stop_ecu(p, lines):
    p.send_signal(2)
    events = []
    while True:
        obj = lines.next(timeout=60)
        events.append(obj)
        if obj["event"] == "summary":
            break
    assert p.wait(30) == 0
    return events


def closed_loop(hdlamp, tmp_path, *ecu_args):
    """One run of the scenario: hdlampd's exit code, its report, its event lines, the ECU's
    JSON lines."""
    lamps = tmp_path / "lamps"
    if not (lamps / "hd84_left.lid.exr").exists():
        run(hdlamp, "model", "--out", lamps)
    report, events = tmp_path / "report.json", tmp_path / "events.jsonl"
    ecu, ecu_lines = start_ecu(hdlamp, lamps, *ecu_args)
    try:
        d = subprocess.run(
            [HDLAMPD, "--can", "vcan0", "--dbc", dbc_path("hd84.dbc"), "--scenario", SCENARIO,
             "--restbus", "vcan0", "--exit-at-end", "--report", str(report),
             "--loop-events", str(events),
             "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
             "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
             "--set", "render.size=64x36", "--set", "render.combine=cpu",
             "--set", "render.headlight=cpu", "--set", "stream.tcp=", "--set", "http.listen=",
             "--set", "restbus.light_switch=high", "--set", "restbus.adb_enable=true",
             "--set", f"loop.reaction_ms={REACTION_MS:g}"],
            capture_output=True, text=True, timeout=900)
    finally:
        ecu_events = stop_ecu(ecu, ecu_lines)
    print(d.stderr[-2000:])
    assert report.exists(), d.stderr
    rep = json.loads(report.read_text())
    lines = [json.loads(x) for x in events.read_text().splitlines()]
    return d.returncode, rep, lines, ecu_events


def sil_agrees(hdlamp, tmp_path, rep, *ecu_args):
    """docs/sil.md: the same scenario in virtual time (hdlamp sil, the reference ECU in process
    on the virtual bus) gives the verdict vcan gave and the same event list: which road users,
    entering and leaving in which order."""
    sil_report = tmp_path / "sil.json"
    p = subprocess.run([hdlamp, "sil", SCENARIO, "--report", str(sil_report), *ecu_args,
                        "--set", "restbus.light_switch=high", "--set", "restbus.adb_enable=true",
                        "--set", f"loop.reaction_ms={REACTION_MS:g}"],
                       capture_output=True, text=True, timeout=900)
    sil = json.loads(sil_report.read_text())
    print("sil:", p.stderr[-600:], json.dumps(sil["loop"]["event_list"]))
    assert p.returncode == (0 if rep["verdict"] else 3)
    assert sil["verdict"] == rep["verdict"]
    assert [(e["event"], e["actor"]) for e in sil["loop"]["event_list"]] == \
        [(e["event"], e["actor"]) for e in rep["loop"]["event_list"]]
    assert [a["id"] for a in sil["loop"]["actors"]] == [a["id"] for a in rep["loop"]["actors"]]


def oncoming(rep):
    (a,) = [a for a in rep["loop"]["actors"] if a["id"] == "oncoming-car"]
    return a


def test_closed_loop_glare_free_high_beam_holds_its_verdict(hdlamp, tmp_path):
    code, rep, lines, ecu = closed_loop(hdlamp, tmp_path)
    loop = rep["loop"]
    car = oncoming(rep)
    enters = [e for e in loop["event_list"] if e["event"] == "enter"]
    print("report:", json.dumps({k: rep[k] for k in ("frames", "cycles", "end", "verdict")}))
    print("oncoming-car:", json.dumps(car))
    print("events:", json.dumps(loop["event_list"]))
    assert rep["end"] == "scenario_end"
    assert code == 0, rep["failed_because"]
    assert rep["verdict"] is True and rep["failed_because"] == []
    # the car entered the camera's view once (at 250 m) and stayed in it to the end or left
    assert car["entries"] == 1 and len(enters) == 1
    e = enters[0]
    assert e["actor"] == "oncoming-car" and e["masked"] is True
    # the event lines say what the report says
    assert [x for x in lines if x["event"] == "enter"] == enters
    # the order of the loop's times
    assert e["t_enter_ns"] <= e["t_input_ns"] < e["t_mask_ns"] <= e["t_frame_ns"]
    lat = e["latency_ms"]
    cyc = e["latency_cycles"]
    for k in ("input", "mask", "frame"):
        assert abs(cyc[k] - lat[k] / ECU_CYCLE_MS) < 1e-3
    # the design's bound (module docstring): input within one camera period of its deadline
    # (the restbus sends at it), mask within the ECU's next deadline (+ its lateness) and one
    # render, the frame one render after that
    render_ms = rep["frames"]["render_ms_max"]
    (summary,) = [x for x in ecu if x["event"] == "summary"]
    ecu_late_ms = summary["late_max_ms"]
    bound_mask = lat["input"] + ECU_CYCLE_MS + ecu_late_ms + render_ms + ECU_CYCLE_MS
    print(f"latency: input {lat['input']:.1f} ms, mask {lat['mask']:.1f} ms "
          f"({cyc['mask']:.2f} cycles), frame {lat['frame']:.1f} ms ({cyc['frame']:.2f} "
          f"cycles); render max {render_ms:.1f} ms, ECU late max {ecu_late_ms:.1f} ms; "
          f"bound mask {bound_mask:.1f} ms, frame {bound_mask + render_ms:.1f} ms")
    assert lat["input"] <= 40.0
    assert lat["mask"] <= bound_mask
    assert lat["frame"] <= bound_mask + render_ms
    # never over the limit in view after the measured latency: every over-limit frame in view
    # lies before the masking frame, so the time over the limit is at most the latency
    assert car["frames_over_late"] == 0
    assert car["glare_s"] <= lat["frame"] / 1e3 + 1e-6
    # every frame was handed over and judged; the car was glared before the camera saw it
    # only where the ECU could not know (beyond the camera's range), reported apart
    assert loop["frames_dropped"] == 0 and loop["frames_judged"] == loop["frames_in"]
    assert loop["frames_in"] == rep["frames"]["rendered"] > 0
    assert car["frames_over"] == (car["frames_over_unseen"] + car["frames_over_in_reaction"]
                                  + car["frames_over_late"])
    # the high beam was on before the camera saw the car (beyond its 250 m): the ECU's mask,
    # not a low beam, kept the glare down afterwards
    assert car["frames_over_unseen"] > 0
    assert e["t_enter_s"] > 0.5
    sil_agrees(hdlamp, tmp_path, rep)


def test_closed_loop_ecu_ignoring_objects_fails_the_verdict(hdlamp, tmp_path):
    code, rep, lines, _ = closed_loop(hdlamp, tmp_path, "--fault", "ignore-objects")
    car = oncoming(rep)
    print("oncoming-car:", json.dumps(car))
    assert rep["end"] == "scenario_end"
    assert code == 3
    assert rep["verdict"] is False
    assert any("glare" in r for r in rep["failed_because"])
    assert car["entries"] == 1 and car["frames_over_late"] > 0 and car["passed"] is False
    # the car glared for seconds after the allowed reaction time, never masked
    assert car["glare_late_s"] > 1.0
    # no dimming cycle masked it within the reaction time: under the limit again only when
    # the geometry took it out of the beam (passing by), if at all
    (e,) = [e for e in rep["loop"]["event_list"] if e["event"] == "enter"]
    assert e["masked"] is False or e["latency_ms"]["mask"] > REACTION_MS + 1000.0
    sil_agrees(hdlamp, tmp_path, rep, "--fault", "ignore-objects")
