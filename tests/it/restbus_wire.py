"""The restbus's wire format and projection as the tests compute them on their own, from
dbc/hd84_inputs.dbc's documented layout and docs/ecu-inputs.md (tests/it/test_restbus.py,
tests/vm/daemon/test_restbus_vcan.py)."""
import math

VEH, INFO, BOX = 0x110, 0x122, 0x121
DATA_ID = {VEH: 0x0110, INFO: 0x0122, BOX: 0x0121}
PERIOD_S = {VEH: 0.020, INFO: 0.040, BOX: 0.040}
CAM = (-1.8, 0.0, 1.3)  # restbus.camera_pos_m default: ego body frame
FOV = (50.0, 30.0)
RANGE_M = 250.0
LANE_W = 3.5
CAR = (4.5, 1.8, 1.45)  # docs/scenarios.md defaults: length, width, height
PED = (0.3, 0.5, 1.75)

SCENARIO = {
    "version": 1, "title": "restbus on vcan", "duration_s": 120,
    "road": {"segments": [{"kind": "straight", "length_m": 1000}],
             "lanes": {"count": 2, "width_m": LANE_W}},
    "ego": {"start_s_m": 0, "lane": 1, "speed_mps": 5},
    "actors": [
        {"id": "oncoming", "kind": "car", "role": "oncoming",
         "path": {"lane": 2, "start_s_m": 140, "speed_mps": 5}},
        {"id": "ahead", "kind": "car", "role": "preceding",
         "path": {"lane": 1, "start_s_m": 40, "speed_mps": 5}},
        {"id": "walker", "kind": "pedestrian", "role": "roadside",
         "path": {"waypoints": [{"t_s": 0, "x_m": 90, "y_m": -5}], "heading_deg": 90}},
    ],
}


def crc8_j1850(data):
    """CRC-8 SAE J1850: poly 0x1D, init 0xFF, final XOR 0xFF, not reflected."""
    crc = 0xFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc ^ 0xFF


def bits(data, start, length, signed=False):
    """An Intel signal: length bits from start bit (LSB first) of the payload."""
    v = (int.from_bytes(bytes(data), "little") >> start) & ((1 << length) - 1)
    if signed and v >> (length - 1):
        v -= 1 << length
    return v


def world_at(t):
    """(ego pose, [(kind, size, pose)]) of SCENARIO at t: straight road along +x, lane 1 at
    y = -1.75, lane 2 at +1.75; a pose is (x, y, heading)."""
    ego = (0 + 5 * t, -LANE_W / 2, 0.0)
    users = [("car", CAR, (140 - 5 * t, LANE_W / 2, math.pi)),
             ("car", CAR, (40 + 5 * t, -LANE_W / 2, 0.0)),
             ("pedestrian", PED, (90.0, -5.0, math.pi / 2))]
    return ego, users


def project(t):
    """{id: (cls, h_left, h_right, v_bottom, v_top, distance)} the camera sees at t, as
    docs/ecu-inputs.md defines it: type A angles of the body box's corners from the camera,
    not sent when behind, beyond range or outside the field of view, clipped to it."""
    ego, users = world_at(t)
    c, s = math.cos(ego[2]), math.sin(ego[2])
    cam = (ego[0] + CAM[0] * c - CAM[1] * s, ego[1] + CAM[0] * s + CAM[1] * c, CAM[2])
    out = {}
    for i, (kind, (length, width, height), (x, y, h)) in enumerate(users):
        ch, sh = math.cos(h), math.sin(h)
        hs, vs = [], []
        behind = False
        for bx in (-length, 0.0):
            for by in (-width / 2, width / 2):
                for bz in (0.0, height):
                    px, py = x + bx * ch - by * sh, y + bx * sh + by * ch
                    dx, dy, dz = px - cam[0], py - cam[1], bz - cam[2]
                    f = dx * c + dy * s
                    r = -(-dx * s + dy * c)
                    behind |= f <= 0
                    hs.append(math.degrees(math.atan2(r, f)))
                    vs.append(math.degrees(math.atan2(dz, math.hypot(r, f))))
        # nearest point of the box to the camera, in the body frame
        lx = (cam[0] - x) * ch + (cam[1] - y) * sh
        ly = -(cam[0] - x) * sh + (cam[1] - y) * ch
        lz = cam[2]
        dist = math.sqrt((lx - min(max(lx, -length), 0)) ** 2 +
                         (ly - min(max(ly, -width / 2), width / 2)) ** 2 +
                         (lz - min(max(lz, 0), height)) ** 2)
        hh, hv = FOV[0] / 2, FOV[1] / 2
        if behind or dist > RANGE_M or max(hs) < -hh or min(hs) > hh or max(vs) < -hv \
                or min(vs) > hv:
            continue
        cos_d = math.cos(h - ego[2])
        cls = 3 if kind == "pedestrian" else 1 if cos_d <= -math.sqrt(0.5) else \
            2 if cos_d >= math.sqrt(0.5) else 0
        out[i + 1] = (cls, max(min(hs), -hh), min(max(hs), hh), max(min(vs), -hv),
                      min(max(vs), hv), dist)
    return out
