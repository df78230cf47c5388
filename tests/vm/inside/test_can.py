"""python-can on vcan inside the VM: timing, CAN FD, and an interface that vanishes."""

import errno
import statistics

import can
import pytest

from can_peer import payload
from vmutil import Lines, peer, sh

FRAMES = 2000
PERIOD_S = 0.020  # the ECU's 50 Hz


def test_2000_frames_at_50hz_arrive_in_order_with_their_data():
    rx = peer("recv", "vcan0", str(FRAMES), "10")
    rx_lines = Lines(rx)
    assert rx_lines.next() == "ready"
    tx = peer("send", "vcan0", str(FRAMES), str(PERIOD_S))
    tx_lines = Lines(tx)
    late_s = tx_lines.next(timeout=FRAMES * PERIOD_S + 120)["late_s"]
    frames = rx_lines.next(timeout=60)["frames"]
    assert tx.wait(10) == 0 and rx.wait(10) == 0

    assert len(frames) == FRAMES
    assert [f[1] for f in frames] == [0x123] * FRAMES
    assert [f[2] for f in frames] == [payload(i).hex() for i in range(FRAMES)]
    t = [f[0] for f in frames]
    periods_ms = [(b - a) * 1e3 for a, b in zip(t, t[1:])]
    dev_ms = sorted(abs(p - PERIOD_S * 1e3) for p in periods_ms)
    mean_ms = statistics.fmean(periods_ms)
    print(f"\nvcan0 50 Hz: {len(frames)}/{FRAMES} frames in order; period (kernel rx stamps) "
          f"mean {mean_ms:.4f} ms, sd {statistics.pstdev(periods_ms):.3f} ms, "
          f"min {min(periods_ms):.3f} ms, max {max(periods_ms):.3f} ms, "
          f"|jitter| median {dev_ms[len(dev_ms) // 2]:.3f} ms, "
          f"p99 {dev_ms[int(len(dev_ms) * 0.99)]:.3f} ms; sender late: "
          f"median {sorted(late_s)[len(late_s) // 2] * 1e3:.3f} ms, "
          f"max {max(late_s) * 1e3:.3f} ms")
    assert all(b > a for a, b in zip(t, t[1:]))
    # Absolute deadlines: whatever the jitter, the mean period does not drift.
    assert abs(mean_ms - PERIOD_S * 1e3) < 0.5


def fd_frame():
    return can.Message(arbitration_id=0x18DA10F1, is_extended_id=True, is_fd=True,
                       bitrate_switch=True, data=bytes((i * 37 + 5) & 0xFF for i in range(64)))


def round_trip(iface, msg):
    with can.Bus(interface="socketcan", channel=iface, fd=True) as rx, \
            can.Bus(interface="socketcan", channel=iface, fd=True) as tx:
        tx.send(msg, timeout=1.0)
        return rx.recv(timeout=10)


def check_fd(got, sent):
    assert got is not None
    assert (got.arbitration_id, got.is_extended_id, got.is_fd, got.bitrate_switch, got.dlc) == \
        (sent.arbitration_id, True, True, True, 64)
    assert bytes(got.data) == bytes(sent.data)


def test_can_fd_64_bytes_round_trip_on_fd_vcan():
    sh("hl-vcan", "add", "vcanfd0", "--fd")
    try:
        assert "mtu 72 " in sh("ip", "link", "show", "vcanfd0")
        sent = fd_frame()
        check_fd(round_trip("vcanfd0", sent), sent)
    finally:
        sh("hl-vcan", "del", "vcanfd0")


def test_can_fd_needs_the_fd_mtu_and_hl_vcan_fd_switches_it():
    assert "mtu 16 " in sh("ip", "link", "show", "vcan0")  # vcan0 starts classic
    sent = fd_frame()
    with pytest.raises(can.CanOperationError) as e:
        round_trip("vcan0", sent)
    assert e.value.error_code == errno.EINVAL
    sh("hl-vcan", "fd", "vcan0")
    try:
        check_fd(round_trip("vcan0", sent), sent)
    finally:
        sh("hl-vcan", "classic", "vcan0")
    assert "mtu 16 " in sh("ip", "link", "show", "vcan0")


def send_one(iface, can_id):
    with can.Bus(interface="socketcan", channel=iface) as bus:
        bus.send(can.Message(arbitration_id=can_id, is_extended_id=False, data=b"\x01"),
                 timeout=1.0)


def test_vcan0_deleted_and_readded_under_a_running_receiver():
    """What python-can reports when the interface goes away, and that reopening works.

    Deleting the interface queues ENETDOWN then ENODEV on a bound raw socket: python-can's
    recv() raises CanOperationError("Error receiving: Network is down", error_code=100), then
    the next recv() raises error_code=19 (No such device). The socket is unbound from then on
    and hears nothing, even after the interface is back: a receiver must open a new bus.
    Opening fails with OSError ENODEV while the interface is missing, and a bus opened after
    `ip link add` but before `ip link set up` first reports ENETDOWN once.
    """
    rx = peer("replug", "vcan0", "30")
    lines = Lines(rx)
    assert lines.next() == "ready"
    send_one("vcan0", 0x100)
    assert lines.next() == {"event": "frame", "bus": "old", "id": 0x100}

    sh("hl-vcan", "del", "vcan0")
    ev = lines.next()
    assert (ev["event"], ev["type"], ev["errno"]) == ("error", "CanOperationError", errno.ENETDOWN)
    assert "Network is down" in ev["message"]
    assert lines.next() == {"event": "old-again", "result": "error", "errno": errno.ENODEV}

    sh("hl-vcan", "add", "vcan0")
    assert lines.next() == {"event": "reopened"}
    send_one("vcan0", 0x200)
    ev = lines.next()
    if ev == {"event": "error", "bus": "new", "errno": errno.ENETDOWN}:
        ev = lines.next()  # bound in the moment between `ip link add` and `up`
    assert ev == {"event": "frame", "bus": "new", "id": 0x200}
    assert lines.next() == {"event": "old-after-readd", "result": None}
    assert rx.wait(10) == 0
