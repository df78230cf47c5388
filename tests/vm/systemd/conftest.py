"""hdlampd as the systemd service it ships as; runs inside the VM with systemd as PID 1
(tests/vm/systemd/run, tests/vm/run --systemd)."""

import os
import sys

import pytest

if os.environ.get("HL_VM") != "1" or not os.path.isdir("/run/systemd/system"):
    raise pytest.UsageError("tests/vm/systemd runs inside the VM under systemd: "
                            "tests/vm/systemd/run SOURCE_DIR BUILD_DIR")

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "inside"))  # vmutil: sh, replay_can
sys.path.insert(0, os.path.join(HERE, "..", "..", "it"))  # threads: check_policies
