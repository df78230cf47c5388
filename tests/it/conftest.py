import os
import subprocess
import sys

import pytest

sys.path.insert(0, os.path.dirname(__file__))


@pytest.fixture(scope="session")
def hdlamp():
    path = os.environ.get("HDLAMP")
    if not path or not os.access(path, os.X_OK):
        pytest.fail("HDLAMP must name the built hdlamp binary (run through ctest)")
    return path


@pytest.fixture(scope="session")
def hd84(hdlamp, tmp_path_factory):
    """The HD84 lamp pair and presets, generated once per session."""
    out = tmp_path_factory.mktemp("hd84")
    subprocess.run([hdlamp, "model", "--out", str(out)], check=True, capture_output=True)
    return out

