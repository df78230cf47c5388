"""Tests of hdlampd on real SocketCAN (vcan) and gpio-sim; they run inside the VM."""

import os
import sys

import pytest

if os.environ.get("HL_VM") != "1":
    raise pytest.UsageError("tests/vm/daemon runs inside the VM: tests/vm/run -- "
                            "/usr/bin/python3 -m pytest tests/vm/daemon")

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "inside"))  # vmutil: sh, Lines
sys.path.insert(0, os.path.join(HERE, "..", "..", "it"))  # scenario: generate, compare


@pytest.fixture(scope="session")
def hdlamp():
    path = os.environ.get("HDLAMP")
    assert path and os.access(path, os.X_OK), "HDLAMP must name the built hdlamp binary"
    return path
