#!/usr/bin/python3
"""tools/bench's osi section (docs/osi.md "Measured"): hdlampd on a live ASAM OSI stream over UDP
(esmini's framing, 50 Hz: a scenario written by `hdlamp scenario osi`, sent at its own pace)
while a second sender floods the same port with garbage datagrams (random bytes of 1 to 1,400,
half of them in esmini's framing so that they reach the decoder, by default 10,000 a second for
60 s). hdlampd replays a recorded HD84 log beside it in real time
and renders every lamp cycle at the default 1280x720 with the moving scene. Measured from the
daemon's own counters (/metrics before and after): lamp cycles rendered and not rendered, the
OSI messages taken and the datagrams counted by reason, the kernel's socket drops; and the same
run without the flood. The goal (issue: OSI input) is 0 cycles not rendered under the flood.

Writes DIR/osi.json and DIR/osi.png; tools/bench puts the same object into bench.json's "osi"
key. A bench, not a test: nothing here fails on a speed.

  tools/bench_osi.py [--out DIR] [--build DIR] [--seconds S] [--rate N] [--rt]
"""
import argparse
import json
import os
import random
import re
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

SRC = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def _loadavg():
    with open("/proc/loadavg") as f:
        return [float(x) for x in f.read().split()[:3]]


def _metrics(port):
    """{name{labels}: value} of /metrics."""
    with urllib.request.urlopen(f"http://127.0.0.1:{port}/metrics", timeout=10) as r:
        text = r.read().decode()
    out = {}
    for line in text.splitlines():
        if line and not line.startswith("#"):
            name, value = line.rsplit(" ", 1)
            out[name] = float(value)
    return out


def _sum(m, family):
    return sum(v for k, v in m.items() if k == family or k.startswith(family + "{"))


def _trace_messages(path):
    data = open(path, "rb").read()
    out, i = [], 0
    while i < len(data):
        (n,) = struct.unpack_from("<I", data, i)
        out.append(data[i + 4:i + 4 + n])
        i += 4 + n
    return out


def _datagrams(msg, part=8192):
    parts = [msg[i:i + part] for i in range(0, len(msg), part)]
    return [struct.pack("<iI", -(k + 1) if k == len(parts) - 1 else k + 1, len(p)) + p
            for k, p in enumerate(parts)]


def _stream(port, msgs, stop):
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    t0 = time.monotonic()
    for k, m in enumerate(msgs):
        if stop.is_set():
            break
        time.sleep(max(0.0, t0 + k * 0.02 - time.monotonic()))
        for d in _datagrams(m):
            sock.sendto(d, ("127.0.0.1", port))
    sock.close()


def _flood(port, rate, seconds, sent):
    """rate garbage datagrams a second, in bursts every 10 ms, for seconds: half random bytes,
    half esmini-framed (a whole message's header) random bytes that reach the decoder."""
    rng = random.Random(1)
    pool = [bytes(rng.getrandbits(8) for _ in range(rng.randint(1, 1400))) for _ in range(256)]
    pool = [p if k % 2 else struct.pack("<iI", -1, len(p)) + p for k, p in enumerate(pool)]
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    t0 = time.monotonic()
    k = 0
    while time.monotonic() - t0 < seconds:
        due = int((time.monotonic() - t0) * rate)
        while k < due:
            try:
                sock.sendto(pool[k & 255], ("127.0.0.1", port))
            except OSError:
                pass
            k += 1
        time.sleep(0.01)
    sent[0] = k
    sock.close()


def _scenario(path, seconds):
    """A straight road long enough; the ego at 20 m/s; a car oncoming and one ahead."""
    doc = {"version": 1, "title": "OSI flood bench", "duration_s": seconds,
           "road": {"segments": [{"kind": "straight", "length_m": 40 * seconds + 500}],
                    "lanes": {"count": 2, "width_m": 3.5}},
           "ego": {"start_s_m": 10, "lane": 1, "speed_mps": 20},
           "actors": [{"id": "oncoming", "kind": "car", "role": "oncoming",
                       "path": {"lane": 2, "start_s_m": 40 * seconds + 300, "speed_mps": 20}},
                      {"id": "ahead", "kind": "car", "role": "preceding",
                       "path": {"lane": 1, "start_s_m": 60, "speed_mps": 20}}]}
    with open(path, "w") as f:
        json.dump(doc, f)


def run_once(build, work, msgs, seconds, rate, rt, log):
    hdlampd = os.path.join(build, "daemon", "hdlampd")
    port = random.randint(20000, 60000)
    lamps = os.path.join(work, "lamps")
    cmd = [hdlampd, "--replay", os.path.join(work, "drive.log"), "--dbc",
           os.path.join(SRC, "dbc", "hd84.dbc"), "--world", f"osi:udp:127.0.0.1:{port}",
           "--set", f"lamps.left={lamps}/hd84_left.lid.exr",
           "--set", f"lamps.right={lamps}/hd84_right.lid.exr",
           "--set", "http.listen=127.0.0.1:0", "--set", "scene.world_wait_s=30",
           *(["--set", "sched.realtime_priority=10"] if rt else [])]
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    stop = threading.Event()
    http = None
    sender = None
    lines = []
    try:
        while http is None:
            line = p.stderr.readline()
            if not line:
                raise RuntimeError("hdlampd exited: " + "".join(lines[-20:]))
            lines.append(line)
            if "waiting up to" in line and sender is None:
                sender = threading.Thread(target=_stream, args=(port, msgs, stop), daemon=True)
                sender.start()
            m = re.search(r"live view on http://.*\(port (\d+)\)", line)
            if m:
                http = int(m.group(1))
        threading.Thread(target=lambda: lines.extend(p.stderr), daemon=True).start()
        time.sleep(3)  # warm-up: the first frames, the stream running
        before = _metrics(http)
        sent = [0]
        t0 = time.monotonic()
        if rate:
            _flood(port, rate, seconds, sent)
        else:
            time.sleep(seconds)
        wall = time.monotonic() - t0
        time.sleep(0.5)
        after = _metrics(http)
    finally:
        stop.set()
        p.terminate()
        p.wait(timeout=30)
    d = {k: after.get(k, 0) - before.get(k, 0) for k in after}
    reasons = {re.search(r'reason="([a-z_]+)"', k).group(1): int(v) for k, v in d.items()
               if k.startswith("hdlamp_osi_messages_total{")}
    out = {
        "flood_rate_per_s": rate, "seconds": round(wall, 2), "garbage_sent": sent[0],
        "garbage_sent_per_s": round(sent[0] / wall, 1),
        "datagrams_counted": int(_sum(d, "hdlamp_osi_datagrams_total")),
        "socket_drops": int(_sum(d, "hdlamp_osi_socket_drops_total")),
        "osi_by_reason": reasons,
        "lamp_cycles": int(_sum(d, "hdlamp_cycles_total")),
        "cycles_not_rendered": int(_sum(d, "hdlamp_cycles_not_rendered_total")),
        "frames": int(_sum(d, "hdlamp_frames_total")),
        "realtime": rt, "loadavg": _loadavg(),
    }
    log(f"osi: flood {rate}/s for {out['seconds']} s: {out['garbage_sent']} garbage sent, "
        f"{out['datagrams_counted']} datagrams counted, {out['socket_drops']} dropped by the "
        f"kernel; {out['lamp_cycles']} lamp cycles, {out['cycles_not_rendered']} not rendered; "
        f"OSI ok {reasons.get('ok', 0)}")
    return out


def section(build, outdir, seconds=60, rate=10000, rt=False, log=print):
    hdlamp = os.path.join(build, "tools", "hdlamp")
    with tempfile.TemporaryDirectory(prefix="hl-bench-osi-") as work:
        subprocess.run([hdlamp, "model", "--out", os.path.join(work, "lamps")], check=True,
                       capture_output=True)
        cycles = int((seconds + 40) * 50)
        subprocess.run([hdlamp, "scenario", "--dbc", os.path.join(SRC, "dbc", "hd84.dbc"),
                        "--out", os.path.join(work, "drive.log"), "--hold", "low",
                        "--phase-cycles", str(cycles)], check=True, capture_output=True)
        scn = os.path.join(work, "scn.json")
        _scenario(scn, seconds + 40)
        trace = os.path.join(work, "stream_gt_.osi")
        subprocess.run([hdlamp, "scenario", "osi", scn, "--out", trace], check=True,
                       capture_output=True)
        msgs = _trace_messages(trace)
        s = {"stream_hz": 50, "message_bytes": len(msgs[1]),
             "baseline": run_once(build, work, msgs, seconds, 0, rt, log),
             "flood": run_once(build, work, msgs, seconds, rate, rt, log)}
    s["goal"] = "0 lamp cycles not rendered under the flood"
    s["met"] = s["flood"]["cycles_not_rendered"] == 0
    os.makedirs(outdir, exist_ok=True)
    with open(os.path.join(outdir, "osi.json"), "w") as f:
        json.dump(s, f, indent=1)
    return s


def plot(s, path, footer=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    runs = [("baseline", "no flood"), ("flood", f"{s['flood']['flood_rate_per_s']:,}/s garbage")]
    names = [label for _, label in runs]
    a1.bar(names, [s[k]["lamp_cycles"] for k, _ in runs], color="#4a7", label="rendered")
    a1.bar(names, [s[k]["cycles_not_rendered"] for k, _ in runs], color="#c33",
           label="not rendered")
    for i, (k, _) in enumerate(runs):
        a1.text(i, s[k]["lamp_cycles"], f"{s[k]['cycles_not_rendered']} not rendered",
                ha="center", va="bottom")
    a1.set_ylabel("lamp cycles")
    a1.set_title(f"hdlampd, {s['flood']['seconds']:.0f} s, OSI at 50 Hz")
    a1.legend(loc="lower right")
    r = s["flood"]["osi_by_reason"]
    keys = [k for k in sorted(r) if r[k]]
    a2.barh(keys, [r[k] for k in keys], color="#47a")
    a2.set_xscale("log")
    a2.set_title(f"flood: counted by reason; kernel drops {s['flood']['socket_drops']}")
    if footer:
        fig.text(0.01, 0.01, footer, fontsize=7, color="#555")
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    fig.savefig(path, dpi=100)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(SRC, "docs", "osi"))
    ap.add_argument("--build", default=os.path.join(SRC, "build"))
    ap.add_argument("--seconds", type=float, default=60)
    ap.add_argument("--rate", type=int, default=10000)
    ap.add_argument("--rt", action="store_true")
    a = ap.parse_args()
    s = section(a.build, a.out, a.seconds, a.rate, a.rt)
    plot(s, os.path.join(a.out, "osi.png"), f"load {s['flood']['loadavg']}")
    print(json.dumps({"met": s["met"], "flood": s["flood"]}, indent=1))


if __name__ == "__main__":
    sys.exit(main())
