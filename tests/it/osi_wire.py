"""ASAM OSI on the wire for the tests, written apart from hdlamp's C (docs/osi.md): messages from
python3-protobuf with descriptors built in code (tests/unit/world/test_osi_second_encoder.py),
trace files (each message preceded by its length, uint32 little-endian) and esmini's UDP framing
(each datagram: int32 part counter 1, 2, ... with the last negated, uint32 size, the part)."""
import math
import os
import socket
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "unit", "world"))
from test_osi_second_encoder import GroundTruth, SensorView  # noqa: E402

PART = 8192  # esmini's default part size


def read_trace(path):
    """The messages of a trace file, as bytes."""
    data = open(path, "rb").read()
    out, i = [], 0
    while i < len(data):
        (n,) = struct.unpack_from("<I", data, i)
        out.append(data[i + 4:i + 4 + n])
        i += 4 + n
    return out


def write_trace(path, messages):
    with open(path, "wb") as f:
        for m in messages:
            f.write(struct.pack("<I", len(m)) + m)


def datagrams(msg, part=PART):
    """msg split as esmini splits it."""
    parts = [msg[i:i + part] for i in range(0, len(msg), part)]
    return [struct.pack("<iI", -(k + 1) if k == len(parts) - 1 else k + 1, len(p)) + p
            for k, p in enumerate(parts)]


def send(sock, port, msg):
    for d in datagrams(msg):
        sock.sendto(d, ("127.0.0.1", port))


def car(gt, oid, x, y, yaw, size=(4.5, 1.8, 1.45), head_light=3, vtype=4, otype=2):
    """A moving object: a medium car (vehicle type 4) with its head lights on (3) by default;
    x, y the bounding box's centre."""
    o = gt.moving_object.add()
    o.id.value = oid
    o.type = otype
    b = o.base
    b.dimension.length, b.dimension.width, b.dimension.height = size
    b.position.x, b.position.y, b.position.z = x, y, size[2] / 2
    b.orientation.roll, b.orientation.pitch, b.orientation.yaw = 0.0, 0.0, yaw
    if otype == 2:
        o.vehicle_classification.type = vtype
        o.vehicle_classification.light_state.head_light = head_light
    return o


def ground_truth(t_s, host=1, objects=(), version=(3, 7, 0)):
    """A GroundTruth at t_s with the host vehicle id and objects [(id, x, y, yaw, kwargs)]."""
    gt = GroundTruth()
    gt.version.version_major, gt.version.version_minor, gt.version.version_patch = version
    ns = round(t_s * 1e9)
    gt.timestamp.seconds, gt.timestamp.nanos = ns // 1000000000, ns % 1000000000
    if host is not None:
        gt.host_vehicle_id.value = host
    for oid, x, y, yaw, kw in objects:
        car(gt, oid, x, y, yaw, **kw)
    return gt


def boundary(gt, bid, points, btype):
    b = gt.lane_boundary.add()
    b.id.value = bid
    b.classification.type = btype
    for x, y in points:
        p = b.boundary_line.add()
        p.position.x, p.position.y, p.position.z = x, y, 0.0
    return b


def free_udp_port():
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def centre_of_front(x, y, yaw, length=4.5):
    """hdlamp's body origin (the ground below the front face's centre) of an OSI box centre."""
    return x + length / 2 * math.cos(yaw), y + length / 2 * math.sin(yaw)
