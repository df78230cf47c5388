"""The guest itself: Debian's 6.1 kernel with CAN loaded, and what Python needs of it."""

import multiprocessing
import os


def test_kernel_is_debian_6_1_with_can_loaded():
    assert os.uname().release.startswith("6.1.0-") and os.uname().release.endswith("-amd64")
    with open("/proc/modules") as f:
        loaded = {line.split()[0] for line in f}
    assert {"can", "can_raw", "can_dev", "vcan", "9p", "overlay", "configfs"} <= loaded


def square(q, n):
    q.put(n * n)


def test_multiprocessing_works():
    # multiprocessing's queues and locks are POSIX semaphores in /dev/shm.
    with open("/proc/mounts") as f:
        assert any(line.split()[1:3] == ["/dev/shm", "tmpfs"] for line in f)
    q = multiprocessing.Queue()
    p = multiprocessing.Process(target=square, args=(q, 12))
    p.start()
    assert q.get(timeout=60) == 144
    p.join(60)
    assert p.exitcode == 0
