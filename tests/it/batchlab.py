"""A batch lab for the tests of hdlamp batch (docs/scale.md): the HD84 lamps, two recorded drives
(a held high beam and a held low beam over the IIHS-like straight approach, each LOG.log with its
scenario LOG.json) and specs over them, and readers of the results."""
import json
import os
import shutil
import xml.etree.ElementTree as ET

from proc import run
from scenario import SOURCE_DIR, dbc_path

SCENARIO = os.path.join(SOURCE_DIR, "scenarios", "iihs-approach-straight.json")
DRIVE_CYCLES = 100  # per phase of the held drive: a few seconds of the approach, in real time


def make_lab(hdlamp, lamps, root):
    """root/drives/{high,low}.log + .json; the spec's common keys."""
    drives = os.path.join(root, "drives")
    os.makedirs(drives, exist_ok=True)
    for preset in ("high", "low"):
        run(hdlamp, "scenario", "--dbc", dbc_path("hd84.dbc"), "--out",
            os.path.join(drives, f"{preset}.log"), "--hold", preset,
            "--phase-cycles", DRIVE_CYCLES)
        shutil.copy(SCENARIO, os.path.join(drives, f"{preset}.json"))
    return {
        "spec": "hdlamp batch", "version": 1,
        "set": [f"lamps.left={lamps}/hd84_left.lid.exr",
                f"lamps.right={lamps}/hd84_right.lid.exr",
                f"can.dbc={dbc_path('hd84.dbc')}", "render.size=160x90"],
        "drives": ["drives"],
    }


def write_spec(root, spec, name="spec.json"):
    path = os.path.join(root, name)
    with open(path, "w") as f:
        json.dump(spec, f, indent=1)
    return path


def plan_tasks(plan):
    """The plan's header and its task lines."""
    with open(plan) as f:
        lines = [json.loads(line) for line in f]
    return lines[0], lines[1:]


def junit_cases(path):
    """{(testsuite, classname, name): outcome} of a JUnit file; outcome pass, failure or error."""
    cases = {}
    for suite in ET.parse(path).getroot().iter("testsuite"):
        for case in suite.iter("testcase"):
            kinds = [c.tag for c in case if c.tag in ("failure", "error")]
            key = (suite.get("name"), case.get("classname"), case.get("name"))
            assert key not in cases, f"{path}: {key} twice"
            cases[key] = kinds[0] if kinds else "pass"
    return cases


def result(out, index):
    with open(os.path.join(out, str(index), "result.json")) as f:
        return json.load(f)
