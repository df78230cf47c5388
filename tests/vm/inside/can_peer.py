"""A CAN peer for the VM tests: a separate process that sends or receives on a SocketCAN
interface with python-can, as an ECU or a logger would.

    can_peer.py send IFACE COUNT PERIOD_S     frames 0x123, 8 bytes (see payload), on
                                              absolute deadlines; prints {"late_s": [...]}
    can_peer.py recv IFACE COUNT TIMEOUT_S    prints "ready", then {"frames": [[t, id, hex]...]}
    can_peer.py replug IFACE TIMEOUT_S        prints "ready"; receives until the interface
                                              goes away, reopens it as soon as it is back,
                                              receives one frame; each step as a JSON line

Exit status 0 when it did its job, 1 otherwise.
"""

import errno
import json
import sys
import time

import can


def payload(i):
    """Frame i's data: its 16-bit index, big-endian, then six bytes that depend on it."""
    return bytes([i >> 8 & 0xFF, i & 0xFF] + [(i * 7 + k * 31) & 0xFF for k in range(6)])


def emit(obj):
    print(json.dumps(obj), flush=True)


def send(iface, count, period_s):
    late = []
    with can.Bus(interface="socketcan", channel=iface) as bus:
        t0 = time.monotonic() + 0.1
        for i in range(count):
            deadline = t0 + i * period_s  # absolute: no drift over the run
            now = time.monotonic()
            if deadline > now:
                time.sleep(deadline - now)
            late.append(time.monotonic() - deadline)
            bus.send(can.Message(arbitration_id=0x123, is_extended_id=False, data=payload(i)),
                     timeout=1.0)
    emit({"late_s": late})
    return 0


def recv(iface, count, timeout_s):
    frames = []
    with can.Bus(interface="socketcan", channel=iface) as bus:
        print("ready", flush=True)
        while len(frames) < count:
            msg = bus.recv(timeout=timeout_s)
            if msg is None:
                break
            frames.append([msg.timestamp, msg.arbitration_id, msg.data.hex()])
    emit({"frames": frames})
    return 0 if len(frames) == count else 1


def open_when_back(iface, timeout_s):
    """A new bus on iface, retried every 20 ms until the interface exists again."""
    deadline = time.monotonic() + timeout_s
    while True:
        try:
            return can.Bus(interface="socketcan", channel=iface)
        except OSError:  # bind() fails with ENODEV while the interface is gone
            if time.monotonic() > deadline:
                raise
            time.sleep(0.02)


def replug(iface, timeout_s):
    """See the interface vanish, reopen it when it is back, receive again."""
    old = can.Bus(interface="socketcan", channel=iface)
    print("ready", flush=True)
    try:
        while True:
            msg = old.recv(timeout=timeout_s)
            if msg is None:
                emit({"event": "timeout"})
                return 1
            emit({"event": "frame", "bus": "old", "id": msg.arbitration_id})
    except can.CanOperationError as e:
        emit({"event": "error", "bus": "old", "type": type(e).__name__,
              "errno": e.error_code, "message": str(e)})
    # The kernel queued two errors (down, then unregistered): the next recv reports the second.
    try:
        again = old.recv(timeout=0.2)
        emit({"event": "old-again", "result": None if again is None else "frame"})
    except can.CanOperationError as e:
        emit({"event": "old-again", "result": "error", "errno": e.error_code})

    new = open_when_back(iface, timeout_s)
    emit({"event": "reopened"})
    with new:
        while True:
            try:
                msg = new.recv(timeout=timeout_s)
                break
            except can.CanOperationError as e:
                # bind() to an interface that exists but is not up yet queues ENETDOWN.
                emit({"event": "error", "bus": "new", "errno": e.error_code})
                if e.error_code != errno.ENETDOWN:
                    return 1
        emit({"event": "frame", "bus": "new", "id": None if msg is None else msg.arbitration_id})
        # The old socket was unbound when its interface went away: it stays deaf.
        stale = old.recv(timeout=0.2)
        emit({"event": "old-after-readd", "result": None if stale is None else "frame"})
    old.shutdown()
    return 0 if msg is not None else 1


def main(argv):
    if len(argv) == 5 and argv[1] == "send":
        return send(argv[2], int(argv[3]), float(argv[4]))
    if len(argv) == 5 and argv[1] == "recv":
        return recv(argv[2], int(argv[3]), float(argv[4]))
    if len(argv) == 4 and argv[1] == "replug":
        return replug(argv[2], float(argv[3]))
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
