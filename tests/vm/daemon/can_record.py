"""Records CAN frames as a logger on the bus would: can_record.py IFACE OUT ID...

Receives the given IDs (hex) on IFACE with a kernel filter, prints "ready" once the socket is
bound, and on SIGTERM or SIGINT writes every frame to OUT as JSON lines [t, id, hex] with the
kernel's receive timestamp (seconds, CLOCK_REALTIME), then exits 0. A separate process, so the
test's sender does not share its interpreter with the receiver.
"""

import json
import signal
import sys

import can

stop = False


def on_signal(signum, frame):
    global stop
    stop = True


def main(argv):
    iface, out = argv[1], argv[2]
    filters = [{"can_id": int(i, 16), "can_mask": 0x7FF, "extended": False} for i in argv[3:]]
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    frames = []
    with can.Bus(interface="socketcan", channel=iface, can_filters=filters) as bus:
        print("ready", flush=True)
        while not stop:
            msg = bus.recv(timeout=0.1)
            if msg is not None and not msg.is_error_frame:
                frames.append((msg.timestamp, msg.arbitration_id, msg.data.hex()))
    with open(out, "w") as f:
        for t, i, d in frames:
            f.write(json.dumps([t, i, d]) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
