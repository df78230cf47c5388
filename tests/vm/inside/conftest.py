"""Tests of the VM test ground itself; they run inside the VM (tests/vm/run sets HL_VM=1)."""

import os

import pytest

if os.environ.get("HL_VM") != "1":
    raise pytest.UsageError("tests/vm/inside runs inside the VM: tests/vm/run [--gpio-sim] -- "
                            "/usr/bin/python3 -m pytest tests/vm/inside")

