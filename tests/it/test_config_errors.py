"""hdlampd checks every configuration value at load: a bad one stops the start with exit status 2
and one line naming where it was set (the file and line, or the option as given), the key and
what was expected, before anything starts (nothing on stdout, no stream, no renderer)."""
import socket
import subprocess

import pytest

from scenario import HDLAMPD, dbc_path
from proc import run


@pytest.fixture(scope="module")
def setup(hdlamp, tmp_path_factory):
    d = tmp_path_factory.mktemp("cfg")
    run(hdlamp, "model", "--out", d / "lamps")
    log = d / "hold.log"
    run(hdlamp, "scenario", "--dbc", dbc_path("hd84.dbc"), "--out", log, "--hold", "low",
        "--phase-cycles", "2")
    return d, log


def base(d, log, lamps=True, tcp=""):
    """A start that works (a replay, tiny frames, no TCP) but for what a test adds."""
    args = ["--replay", str(log), "--dbc", dbc_path("hd84.dbc")]
    if lamps:
        args += ["--set", f"lamps.left={d}/lamps/hd84_left.lid.exr",
                 "--set", f"lamps.right={d}/lamps/hd84_right.lid.exr"]
    return args + ["--set", "render.size=160x90", "--set", f"stream.tcp={tcp}",
                   "--set", "http.listen="]


def refused(*args):
    r = subprocess.run([HDLAMPD, *[str(a) for a in args]], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 2, r.stderr
    assert r.stdout == ""
    return r.stderr


# (key=value, what the message says after "key 'KEY': ")
BAD = [
    ("render.view=foo", "'foo': expected display, lux or hdr"),
    ("render.scene=moon", "'moon': expected sphere, wall, road, bird or bounce"),
    ("render.combine=vulkan", "'vulkan': expected auto, cpu or gles"),
    ("render.size=160x9", "'160x9': expected WxH, each 16..8192"),
    ("render.threads=17", "'17': expected an integer 0..16"),
    ("http.listen=999.1.1.1:80",
     "'999.1.1.1:80': host '999.1.1.1': expected an IPv4 address, [IPv6 address] or localhost"),
    ("http.listen=127.0.0.1:99999",
     "'127.0.0.1:99999': port '99999': expected 0..65535 (0 = any free port)"),
    ("stream.tcp=localhost:http",
     "'localhost:http': port 'http': expected 0..65535 (0 = any free port)"),
    ("stream.tcp=:0", "':0': expected HOST:PORT (an IPv4 address, [IPv6] or localhost; port "
     "0..65535, 0 = any free port), or empty for off"),
    ("stream.max_clients=65", "'65': expected an integer 1..64"),
    ("gpio.trigger_edge=up", "'up': expected rising, falling or both"),
    ("can.lamps=left;right", "'left;right': expected 1..8 lamp names (letters, digits, _ -) "
     "separated by commas, such as left,right"),
    ("can.timeout_ms=0", "'0': expected an integer 1..60000"),
    ("can.replay_passes=many", "'many': expected an integer 0..1000000"),
    ("lamps.failsafe=preset:", "'preset:': expected hold, dark or preset:NAME (NAME.json in "
     "lamps.presets)"),
    ("verdict.traffic=centre", "'centre': expected right or left"),
    ("road.levels=1", "'1': expected two numbers 0.01..1000, as A,B"),
    (f"stream.unix=/tmp/{'x' * 103}.sock", f"'/tmp/{'x' * 103}.sock': path too long (at most "
     "107 bytes: a Unix socket's address)"),
]


@pytest.mark.parametrize("assignment,what", BAD, ids=[a for a, _ in BAD])
def test_bad_value_by_set_names_the_option(setup, assignment, what):
    d, log = setup
    key = assignment.split("=")[0]
    err = refused(*base(d, log), "--set", assignment)
    assert err == f"hdlampd: --set {assignment}: key '{key}': {what}\n"


@pytest.mark.parametrize("assignment,what", BAD, ids=[a for a, _ in BAD])
def test_bad_value_in_the_file_names_file_and_line(setup, tmp_path, assignment, what):
    d, log = setup
    key, value = assignment.split("=", 1)
    section, name = key.split(".")
    conf = tmp_path / "bad.conf"
    conf.write_text(f"; a bench\n[{section}]\n\n{name} = {value}\n")
    err = refused("--config", conf, *base(d, log))
    assert err == f"hdlampd: '{conf}':4: key '{key}': {what}\n"


def test_short_options_are_named_as_given(setup):
    d, log = setup
    err = refused(*base(d, log), "--timeout-ms", "0")
    assert err == "hdlampd: --timeout-ms 0: key 'can.timeout_ms': '0': expected an integer " \
                  "1..60000\n"
    err = refused(*base(d, log), "--loop-passes", "-2")
    assert err == "hdlampd: --loop-passes -2: key 'can.replay_passes': '-2': expected an " \
                  "integer 0..1000000\n"


def test_unknown_key_names_an_option_that_exists(setup, tmp_path):
    d, log = setup
    conf = tmp_path / "typo.conf"
    conf.write_text("[render]\nveiw = lux\n")
    err = refused("--config", conf, *base(d, log))
    assert err == (f"hdlampd: '{conf}':2: key 'render.veiw': unknown key (hdlampd "
                   "--print-config lists every key)\n")
    r = subprocess.run([HDLAMPD, "--print-config"], capture_output=True, text=True, timeout=30)
    assert r.returncode == 0 and "\n[render]\n" in r.stdout and "\nview = display\n" in r.stdout


def test_files_the_keys_name_are_checked_at_load(setup, tmp_path):
    d, log = setup
    # a missing LID file, named with the line that set it
    conf = tmp_path / "lids.conf"
    conf.write_text(f"[lamps]\nleft = {d}/lamps/hd84_left.lid.exr\nright = {tmp_path}/no.exr\n")
    err = refused("--config", conf, *base(d, log, lamps=False))
    assert err == (f"hdlampd: '{conf}':3: key 'lamps.right': '{tmp_path}/no.exr': No such file "
                   "or directory; expected a LID file (.lid.exr)\n")
    # a missing preset: the path and the reason, no ':0:0:'
    err = refused(*base(d, log), "--set", f"lamps.presets={d}/lamps",
                  "--set", "lamps.failsafe=preset:nope")
    assert err == (f"hdlampd: --set lamps.failsafe=preset:nope: key 'lamps.failsafe': "
                   f"'{d}/lamps/nope.json': No such file or directory; expected the preset "
                   "NAME.json in the directory lamps.presets\n")
    assert ":0:0:" not in err
    # a missing DBC
    err = refused(*base(d, log), "--dbc", tmp_path / "none.dbc")
    assert err == (f"hdlampd: --dbc {tmp_path}/none.dbc: key 'can.dbc': '{tmp_path}/none.dbc': "
                   "No such file or directory; expected a DBC file\n")
    # a Unix socket in a directory that does not exist
    err = refused(*base(d, log), "--set", f"stream.unix={tmp_path}/run/f.sock")
    assert err == (f"hdlampd: --set stream.unix={tmp_path}/run/f.sock: key 'stream.unix': "
                   f"'{tmp_path}/run': No such file or directory; expected the directory of the "
                   "socket to exist\n")


def test_a_key_set_twice_is_warned_about_with_both_lines(setup, tmp_path):
    d, log = setup
    conf = tmp_path / "dup.conf"
    conf.write_text("[render]\nview = lux\nexposure_ev = 1\n[render]\nview = foo\n")
    err = refused("--config", conf, *base(d, log))
    assert err == (f"hdlampd: '{conf}':5: warning: key 'render.view' set again (first at line "
                   "2); the last value counts\n"
                   f"hdlampd: '{conf}':5: key 'render.view': 'foo': expected display, lux or "
                   "hdr\n")
    conf.write_text("[render]\nview = lux\n[render]\nview = hdr\n")
    r = subprocess.run([HDLAMPD, "--config", str(conf), "--print-config"], capture_output=True,
                       text=True, timeout=30)
    assert r.returncode == 0
    assert r.stderr == (f"hdlampd: '{conf}':4: warning: key 'render.view' set again (first at "
                        "line 2); the last value counts\n")
    assert "\nview = hdr\n" in r.stdout


def test_localhost_and_port_0_are_taken_as_the_docs_say(setup):
    """stream.tcp = localhost:0: a free loopback port, the one the start line names."""
    d, log = setup
    p = subprocess.Popen([HDLAMPD, *base(d, log, tcp="localhost:0"), "--loop"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        lines = []
        while True:
            line = p.stderr.readline()
            assert line, f"hdlampd exited early: {lines}"
            lines.append(line)
            if line.startswith("hdlampd: frame stream on localhost:0 (port "):
                port = int(line.split("(port ")[1].split(")")[0])
                break
        assert port > 0
        c = socket.create_connection(("127.0.0.1", port), timeout=10)
        c.close()
    finally:
        p.terminate()
        p.communicate(timeout=30)
    assert p.returncode == 0
