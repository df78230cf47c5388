"""libgpiod v2 tools against the gpio-sim chip that `tests/vm/run --gpio-sim` creates.

The chip has one bank, lines named hl-strobe, hl-ready, hl-fault, hl-in0 .. hl-in4 (offsets
0..7). gpio-sim's sysfs side (HL_GPIO_SIM/sim_gpioN/{value,pull}) is the far end of each line:
`value` shows what a consumer drives, `pull` is what an input reads when nobody drives it.
"""

import os
import re
import subprocess
import time

import pytest

from vmutil import Lines, sh

NAMES = ["hl-strobe", "hl-ready", "hl-fault", "hl-in0", "hl-in1", "hl-in2", "hl-in3", "hl-in4"]


@pytest.fixture(scope="module")
def chip():
    chip = os.environ.get("HL_GPIO_CHIP")
    assert chip, "no HL_GPIO_CHIP: run the VM with tests/vm/run --gpio-sim"
    return chip


def sim(offset, attr):
    return os.path.join(os.environ["HL_GPIO_SIM"], f"sim_gpio{offset}", attr)


def read(path):
    with open(path) as f:
        return f.read().strip()


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def wait_for(pred, what, timeout_s=20):
    deadline = time.monotonic() + timeout_s
    while not pred():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(0.05)


def test_chip_has_the_named_lines(chip):
    info = sh("gpioinfo", "-c", chip)
    names = re.findall(r'^\s*line\s+\d+:\s+"([^"]*)"', info, re.M)
    assert names == NAMES
    assert sh("gpioinfo", "hl-ready").split()[:3] == [os.path.basename(chip), "1", '"hl-ready"']


def test_gpioset_drives_the_lines(chip):
    p = subprocess.Popen(["gpioset", "-c", chip, "hl-strobe=1", "hl-ready=0", "hl-fault=on"])
    try:
        wait_for(lambda: read(sim(0, "value")) == "1", "gpioset to drive hl-strobe")
        assert [read(sim(i, "value")) for i in (0, 1, 2)] == ["1", "0", "1"]
    finally:
        p.terminate()
        p.wait(10)
    # Active-low: logical 1 is a low level on the wire.
    p = subprocess.Popen(["gpioset", "-c", chip, "--active-low", "hl-fault=1"])
    try:
        wait_for(lambda: read(sim(2, "value")) == "0", "gpioset -l to drive hl-fault low")
    finally:
        p.terminate()
        p.wait(10)


def test_pulled_line_reads_back(chip):
    write(sim(3, "pull"), "pull-up")
    assert sh("gpioget", "-c", chip, "hl-in0") == '"hl-in0"=active\n'
    assert sh("gpioget", "-c", chip, "--numeric", "hl-in0") == "1\n"
    assert sh("gpioget", "-c", chip, "--numeric", "--active-low", "hl-in0") == "0\n"
    write(sim(3, "pull"), "pull-down")
    assert sh("gpioget", "-c", chip, "hl-in0") == '"hl-in0"=inactive\n'
    assert sh("gpioget", "-c", chip, "--numeric", "hl-in0") == "0\n"
    # A bias requested through the character device moves gpio-sim's pull too.
    assert sh("gpioget", "-c", chip, "--numeric", "--bias=pull-up", "hl-in2", "hl-in3") == "1 1\n"
    assert read(sim(5, "pull")) == "pull-up"
    assert sh("gpioget", "-c", chip, "--numeric", "--bias=pull-down", "hl-in2") == "0\n"


def test_gpiomon_sees_the_edges(chip):
    write(sim(4, "pull"), "pull-down")
    p = subprocess.Popen(["gpiomon", "-c", chip, "--num-events=3", "--format=%o %l %E",
                          "--unquoted", "hl-in1"], stdout=subprocess.PIPE, text=True)
    events = Lines(p, parse=str)
    try:
        wait_for(lambda: 'consumer="gpiomon"' in sh("gpioinfo", "-c", chip, "hl-in1"),
                 "gpiomon to request hl-in1")
        # One edge at a time: gpio-sim raises its interrupts from a work item, and two pulls
        # before it runs would be one interrupt.
        for pull, edge in (("pull-up", "rising"), ("pull-down", "falling"), ("pull-up", "rising")):
            write(sim(4, "pull"), pull)
            assert events.next(timeout=30) == f"4 hl-in1 {edge}"
        assert p.wait(30) == 0  # --num-events=3: done
    finally:
        p.kill()
        p.wait()
