#!/usr/bin/python3
"""OSI messages from a second encoder: python3-protobuf serializes osi3.GroundTruth and
osi3.SensorView from descriptors built here in code (not world/osi.proto, no protoc), with OSI's
field numbers written out independently (OSI v3.7.0: osi_version.proto, osi_common.proto,
osi_object.proto, osi_lane.proto, osi_groundtruth.proto, osi_sensorview.proto; tail_light from
v3.8.0-rc1), including fields hdlamp does not read, which must be skipped. osi_dump (built from
tests/unit/world/osi_dump.c, path in $OSI_DUMP) decodes each message with world/osi_msg.c and
prints JSON; every value must come back exactly, the doubles bit for bit.
Run by ctest (test_osi_second_encoder, label unit) with Debian's /usr/bin/python3 -m pytest."""
import json
import math
import os
import random
import struct
import subprocess

from google.protobuf import descriptor_pb2, descriptor_pool, message_factory

F = descriptor_pb2.FieldDescriptorProto
OPT, REP = F.LABEL_OPTIONAL, F.LABEL_REPEATED
SCALAR = {"double": F.TYPE_DOUBLE, "uint32": F.TYPE_UINT32, "uint64": F.TYPE_UINT64,
          "int64": F.TYPE_INT64, "bool": F.TYPE_BOOL, "string": F.TYPE_STRING}


def message(parent, name, fields, enums=(), nested=()):
    """Adds message name to parent (a FileDescriptorProto or DescriptorProto). fields:
    (name, number, type, label); type is a scalar name, "enum:.osi3.X" or ".osi3.X"."""
    m = (parent.message_type if hasattr(parent, "message_type") else parent.nested_type).add()
    m.name = name
    for fname, number, ftype, label in fields:
        f = m.field.add(name=fname, number=number, label=label)
        if ftype in SCALAR:
            f.type = SCALAR[ftype]
        elif ftype.startswith("enum:"):
            f.type, f.type_name = F.TYPE_ENUM, ftype[5:]
        else:
            f.type, f.type_name = F.TYPE_MESSAGE, ftype
    for ename, values in enums:
        e = m.enum_type.add(name=ename)
        for vname, number in values:
            e.value.add(name=vname, number=number)
    for build in nested:
        build(m)
    return m


def numbered(prefix, names):
    return [(f"{prefix}_{n}", i) for i, n in enumerate(names)]


def osi_file():
    fd = descriptor_pb2.FileDescriptorProto(name="second_encoder/osi3.proto", package="osi3",
                                            syntax="proto2")
    message(fd, "InterfaceVersion", [("version_major", 1, "uint32", OPT),
                                     ("version_minor", 2, "uint32", OPT),
                                     ("version_patch", 3, "uint32", OPT)])
    message(fd, "Timestamp", [("seconds", 1, "int64", OPT), ("nanos", 2, "uint32", OPT)])
    message(fd, "Identifier", [("value", 1, "uint64", OPT)])
    message(fd, "Vector3d", [(c, i + 1, "double", OPT) for i, c in enumerate("xyz")])
    message(fd, "Vector2d", [(c, i + 1, "double", OPT) for i, c in enumerate("xy")])
    message(fd, "Dimension3d", [(c, i + 1, "double", OPT)
                                for i, c in enumerate(("length", "width", "height"))])
    message(fd, "Orientation3d", [(c, i + 1, "double", OPT)
                                  for i, c in enumerate(("roll", "pitch", "yaw"))])
    message(fd, "MountingPosition", [("position", 1, ".osi3.Vector3d", OPT),
                                     ("orientation", 2, ".osi3.Orientation3d", OPT)])
    message(fd, "BaseStationary", [("dimension", 1, ".osi3.Dimension3d", OPT),
                                   ("position", 2, ".osi3.Vector3d", OPT),
                                   ("orientation", 3, ".osi3.Orientation3d", OPT)])
    message(fd, "BaseMoving", [("dimension", 1, ".osi3.Dimension3d", OPT),
                               ("position", 2, ".osi3.Vector3d", OPT),
                               ("orientation", 3, ".osi3.Orientation3d", OPT),
                               ("velocity", 4, ".osi3.Vector3d", OPT),
                               ("acceleration", 5, ".osi3.Vector3d", OPT),
                               ("orientation_rate", 6, ".osi3.Orientation3d", OPT),
                               ("base_polygon", 7, ".osi3.Vector2d", REP)])
    message(fd, "StationaryObject", [("id", 1, ".osi3.Identifier", OPT),
                                     ("base", 2, ".osi3.BaseStationary", OPT)])
    message(fd, "TrafficSign", [("id", 1, ".osi3.Identifier", OPT)])
    message(fd, "Lane", [("id", 1, ".osi3.Identifier", OPT)])

    ls = ".osi3.MovingObject.VehicleClassification.LightState."
    generic = "enum:" + ls + "GenericLightState"
    light_state = lambda m: message(m, "LightState", [  # noqa: E731
        ("indicator_state", 1, "enum:" + ls + "IndicatorState", OPT),
        ("front_fog_light", 2, generic, OPT), ("rear_fog_light", 3, generic, OPT),
        ("head_light", 4, generic, OPT), ("high_beam", 5, generic, OPT),
        ("reversing_light", 6, generic, OPT),
        ("brake_light_state", 7, "enum:" + ls + "BrakeLightState", OPT),
        ("license_plate_illumination_rear", 8, generic, OPT),
        ("emergency_vehicle_illumination", 9, generic, OPT),
        ("service_vehicle_illumination", 10, generic, OPT), ("tail_light", 11, generic, OPT)],
        enums=[("IndicatorState", numbered("INDICATOR_STATE", [
                   "UNKNOWN", "OTHER", "OFF", "LEFT", "RIGHT", "WARNING"])),
               ("GenericLightState", numbered("GENERIC_LIGHT_STATE", [
                   "UNKNOWN", "OTHER", "OFF", "ON", "FLASHING_BLUE", "FLASHING_BLUE_AND_RED",
                   "FLASHING_AMBER"])),
               ("BrakeLightState", numbered("BRAKE_LIGHT_STATE", [
                   "UNKNOWN", "OTHER", "OFF", "NORMAL", "STRONG"]))])
    vehicle_types = numbered("TYPE", [
        "UNKNOWN", "OTHER", "SMALL_CAR", "COMPACT_CAR", "MEDIUM_CAR", "LUXURY_CAR",
        "DELIVERY_VAN", "HEAVY_TRUCK", "SEMITRAILER", "TRAILER", "MOTORBIKE", "BICYCLE", "BUS",
        "TRAM", "TRAIN", "WHEELCHAIR", "SEMITRACTOR", "STANDUP_SCOOTER"])
    vehicle_types.append(("TYPE_LAND_VEHICLE", 22))  # after v3.7.0: a number we do not name
    classification = lambda m: message(m, "VehicleClassification", [  # noqa: E731
        ("type", 1, "enum:.osi3.MovingObject.VehicleClassification.Type", OPT),
        ("light_state", 2, ".osi3.MovingObject.VehicleClassification.LightState", OPT),
        ("has_trailer", 3, "bool", OPT), ("trailer_id", 4, ".osi3.Identifier", OPT)],
        enums=[("Type", vehicle_types)], nested=[light_state])
    attributes = lambda m: message(m, "VehicleAttributes", [  # noqa: E731
        ("driver_id", 1, ".osi3.Identifier", OPT), ("radius_wheel", 2, "double", OPT),
        ("number_wheels", 3, "uint32", OPT)])
    message(fd, "MovingObject", [
        ("id", 1, ".osi3.Identifier", OPT), ("base", 2, ".osi3.BaseMoving", OPT),
        ("type", 3, "enum:.osi3.MovingObject.Type", OPT),
        ("assigned_lane_id", 4, ".osi3.Identifier", REP),
        ("vehicle_attributes", 5, ".osi3.MovingObject.VehicleAttributes", OPT),
        ("vehicle_classification", 6, ".osi3.MovingObject.VehicleClassification", OPT),
        ("model_reference", 7, "string", OPT)],
        enums=[("Type", numbered("TYPE", ["UNKNOWN", "OTHER", "VEHICLE", "PEDESTRIAN",
                                          "ANIMAL"]))],
        nested=[attributes, classification])

    point = lambda m: message(m, "BoundaryPoint", [  # noqa: E731
        ("position", 1, ".osi3.Vector3d", OPT), ("width", 2, "double", OPT),
        ("height", 3, "double", OPT), ("dash", 4, "enum:.osi3.LaneBoundary.BoundaryPoint.Dash",
                                       OPT)],
        enums=[("Dash", numbered("DASH", ["UNKNOWN", "OTHER", "START", "CONTINUE", "END",
                                          "GAP"]))])
    lb_class = lambda m: message(m, "Classification", [  # noqa: E731
        ("type", 1, "enum:.osi3.LaneBoundary.Classification.Type", OPT),
        ("color", 2, "enum:.osi3.LaneBoundary.Classification.Color", OPT),
        ("limiting_structure_id", 3, ".osi3.Identifier", REP)],
        enums=[("Type", numbered("TYPE", [
                   "UNKNOWN", "OTHER", "NO_LINE", "SOLID_LINE", "DASHED_LINE", "BOTTS_DOTS",
                   "ROAD_EDGE", "SNOW_EDGE", "GRASS_EDGE", "GRAVEL_EDGE", "SOIL_EDGE",
                   "GUARD_RAIL", "CURB", "STRUCTURE", "BARRIER", "SOUND_BARRIER"])),
               ("Color", numbered("COLOR", ["UNKNOWN", "OTHER", "NONE", "WHITE", "YELLOW"]))])
    message(fd, "LaneBoundary", [
        ("id", 1, ".osi3.Identifier", OPT),
        ("boundary_line", 2, ".osi3.LaneBoundary.BoundaryPoint", REP),
        ("classification", 3, ".osi3.LaneBoundary.Classification", OPT)],
        nested=[point, lb_class])

    message(fd, "GroundTruth", [
        ("version", 1, ".osi3.InterfaceVersion", OPT), ("timestamp", 2, ".osi3.Timestamp", OPT),
        ("host_vehicle_id", 3, ".osi3.Identifier", OPT),
        ("stationary_object", 4, ".osi3.StationaryObject", REP),
        ("moving_object", 5, ".osi3.MovingObject", REP),
        ("traffic_sign", 6, ".osi3.TrafficSign", REP),
        ("lane_boundary", 9, ".osi3.LaneBoundary", REP), ("lane", 10, ".osi3.Lane", REP),
        ("country_code", 13, "uint32", OPT), ("proj_string", 14, "string", OPT),
        ("map_reference", 15, "string", OPT)])
    message(fd, "SensorView", [
        ("version", 1, ".osi3.InterfaceVersion", OPT), ("timestamp", 2, ".osi3.Timestamp", OPT),
        ("sensor_id", 3, ".osi3.Identifier", OPT),
        ("mounting_position", 4, ".osi3.MountingPosition", OPT),
        ("mounting_position_rmse", 5, ".osi3.MountingPosition", OPT),
        ("global_ground_truth", 7, ".osi3.GroundTruth", OPT),
        ("host_vehicle_id", 8, ".osi3.Identifier", OPT)])
    return fd


POOL = descriptor_pool.DescriptorPool()
POOL.Add(osi_file())


def cls(name):
    d = POOL.FindMessageTypeByName("osi3." + name)
    if hasattr(message_factory, "GetMessageClass"):
        return message_factory.GetMessageClass(d)
    return message_factory.MessageFactory(POOL).GetPrototype(d)


GroundTruth, SensorView = cls("GroundTruth"), cls("SensorView")
DUMP = os.environ.get("OSI_DUMP", "")
SPECIAL = [0.0, -0.0, 5e-324, -2.2250738585072014e-308, 1.7976931348623157e308, 1.0 / 3.0,
           -math.pi, 1e-9]


def dump(data, kind):
    return subprocess.run([DUMP, "--kind", kind], input=data, capture_output=True)


def decoded(data, kind):
    p = dump(data, kind)
    assert p.returncode == 0, p.stderr.decode()
    return json.loads(p.stdout)


def bits(x):
    return None if x is None else struct.pack("<d", x)


def same(got, want, where):
    """Exact: every key, every number; doubles by their bits."""
    if isinstance(want, dict):
        assert isinstance(got, dict) and sorted(got) == sorted(want), (where, got, want)
        for k in want:
            same(got[k], want[k], f"{where}.{k}")
    elif isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), (where, got, want)
        for i, (g, w) in enumerate(zip(got, want)):
            same(g, w, f"{where}[{i}]")
    elif isinstance(want, float) or isinstance(got, float):
        assert bits(float(got) if got is not None else None) == bits(want), (where, got, want)
    else:
        assert got == want and type(got) is type(want), (where, got, want)


class Doubles:
    """Doubles from random bits (every exponent, no NaN), and the awkward ones."""

    def __init__(self, seed):
        self.rng = random.Random(seed)
        self.special = list(SPECIAL)

    def __call__(self):
        if self.special:
            return self.special.pop()
        while True:
            x = struct.unpack("<d", self.rng.getrandbits(64).to_bytes(8, "little"))[0]
            if math.isfinite(x):
                return x


def fill_vec(msg, names, d, present):
    """Sets the components in present (a set of indexes); returns the expected triple."""
    out = []
    for i, n in enumerate(names):
        if i in present:
            v = d()
            setattr(msg, n, v)
            out.append(v)
        else:
            out.append(None)
    return out


def ground_truth(gt, d, rng):
    """Fills gt with everything we read and more we skip; returns what osi_dump must print
    (without kind, version, t_ns and host_id)."""
    so = gt.stationary_object.add()  # skipped: field 4
    so.id.value = 9
    so.base.position.x = 1.0
    gt.traffic_sign.add().id.value = 10  # skipped: field 6
    gt.lane.add().id.value = 11  # skipped: field 10
    gt.country_code = 276  # skipped: field 13
    gt.proj_string = "+proj=utm +zone=32"  # skipped: field 14
    objects = []
    for i in range(6):
        m = gt.moving_object.add()
        o = {}
        if i != 3:
            m.id.value = [0, 1, 2**64 - 2, 77, 5, 6][i]
            o["id"] = m.id.value
        o["type"] = [2, 3, 4, 0, 1, 2][i]
        if o["type"]:
            m.type = o["type"]
        m.assigned_lane_id.add().value = 100 + i  # skipped
        m.model_reference = "car.glb"  # skipped
        full = {0, 1, 2}
        parts = [full, {0, 2}, set(), full, {1}, full][i]
        if parts:
            o["dim_m"] = fill_vec(m.base.dimension, ("length", "width", "height"), d, parts)
            o["pos_m"] = fill_vec(m.base.position, "xyz", d, parts)
            o["rpy_rad"] = fill_vec(m.base.orientation, ("roll", "pitch", "yaw"), d, parts)
            o["vel_mps"] = fill_vec(m.base.velocity, "xyz", d, parts)
            m.base.acceleration.x = 9.81  # skipped: BaseMoving.acceleration (5)
            m.base.orientation_rate.yaw = 0.5  # skipped
            m.base.base_polygon.add(x=1.0, y=2.0)  # skipped
        else:
            for k in ("dim_m", "pos_m", "rpy_rad", "vel_mps"):
                o[k] = [None, None, None]
        if i in (0, 4, 5):
            m.vehicle_attributes.radius_wheel = 0.3  # skipped: field 5
            c = m.vehicle_classification
            c.has_trailer = True  # skipped
            vt = [4, 0, 0, 0, 22, 16][i]
            if vt:
                c.type = vt
            lights = [(3, 2, 4, 3), (0, 0, 0, 0), (0, 0, 0, 0), (0, 0, 0, 0), (2, 3, 3, 0),
                      (1, 0, 2, 3)][i]
            c.light_state.indicator_state = 3  # skipped
            c.light_state.front_fog_light = 3  # skipped
            c.light_state.reversing_light = 3  # skipped
            for name, v in zip(("head_light", "high_beam", "brake_light_state", "tail_light"),
                               lights):
                if v:
                    setattr(c.light_state, name, v)
            o.update(vehicle_type=vt, head_light=lights[0], high_beam=lights[1],
                     brake_light=lights[2], tail_light=lights[3])
        objects.append(o)
    boundaries = []
    for i in range(4):
        lb = gt.lane_boundary.add()
        b = {"id": [0, 500, 2**64 - 1, 3][i], "type": [3, 0, 12, 15][i], "points": []}
        if i != 0:
            lb.id.value = b["id"]
        if b["type"]:
            lb.classification.type = b["type"]
        lb.classification.color = 3  # skipped
        lb.classification.limiting_structure_id.add().value = 9  # skipped
        for k in range([5, 0, 3, 40][i]):
            p = lb.boundary_line.add()
            present = {0, 1, 2} if (i + k) % 4 else {0, 1}
            pos = fill_vec(p.position, "xyz", d, present)
            if k % 3 == 1:
                width = None
            else:
                width = d()
                p.width = width
            p.height = 0.15  # skipped
            p.dash = 2  # skipped
            b["points"].append({"width_m": width, "pos_m": pos})
        boundaries.append(b)
    return {"objects": objects, "boundaries": boundaries}


def header(msg, seconds, nanos, host, version=(3, 7, 0)):
    msg.version.version_major, msg.version.version_minor, msg.version.version_patch = version
    msg.timestamp.seconds = seconds
    msg.timestamp.nanos = nanos
    msg.host_vehicle_id.value = host


def test_ground_truth_every_value_exact():
    d, rng = Doubles(1), random.Random(2)
    gt = GroundTruth()
    header(gt, 1234, 999999999, 77, version=(3, 6, 1))
    want = ground_truth(gt, d, rng)
    want.update(kind="ground-truth", version=[3, 6, 1], t_ns=1234 * 10**9 + 999999999,
                host_id=77)
    same(decoded(gt.SerializeToString(), "ground-truth"), want, "gt")


def test_sensor_view_reads_its_ground_truth():
    d, rng = Doubles(3), random.Random(4)
    sv = SensorView()
    header(sv, 5, 250, 6)
    sv.sensor_id.value = 99  # skipped: field 3
    sv.mounting_position.position.x = 1.5  # skipped: field 4
    sv.mounting_position_rmse.orientation.yaw = 0.01  # skipped: field 5
    header(sv.global_ground_truth, 4, 1, 77, version=(3, 5, 0))
    want = ground_truth(sv.global_ground_truth, d, rng)
    # The sensor view's own version, timestamp and host win over its ground truth's.
    want.update(kind="sensor-view", version=[3, 7, 0], t_ns=5 * 10**9 + 250, host_id=6)
    same(decoded(sv.SerializeToString(), "sensor-view"), want, "sv")

    # Without its own: the ground truth's.
    sv.ClearField("host_vehicle_id")
    sv.ClearField("timestamp")
    sv.ClearField("version")
    want.update(version=[3, 5, 0], t_ns=4 * 10**9 + 1, host_id=77)
    same(decoded(sv.SerializeToString(), "sensor-view"), want, "sv without its own")


def test_absent_everything():
    same(decoded(GroundTruth().SerializeToString(), "ground-truth"),
         {"kind": "ground-truth", "objects": [], "boundaries": []}, "empty gt")
    sv = SensorView()
    sv.sensor_id.value = 1
    same(decoded(sv.SerializeToString(), "sensor-view"),
         {"kind": "sensor-view", "objects": [], "boundaries": []}, "sv without ground truth")


def test_garbage_is_malformed():
    gt = GroundTruth()
    header(gt, 1, 2, 3)
    gt.moving_object.add().id.value = 4
    whole = gt.SerializeToString()
    for data, kind in ((b"\xff\xff\xff\xff\xff", "ground-truth"),
                       (b"\x0a\x10\x08", "sensor-view"),
                       (whole[:-1], "ground-truth")):
        p = dump(data, kind)
        assert p.returncode == 1, (data, p.returncode, p.stdout)
        assert p.stdout == b""
        assert b"malformed" in p.stderr and b"not a serialized osi3." in p.stderr, p.stderr


def test_too_many_objects():
    gt = GroundTruth()
    for i in range(257):
        gt.moving_object.add().id.value = i
    p = dump(gt.SerializeToString(), "ground-truth")
    assert p.returncode == 1
    assert b"too many: 257 moving objects, more than 256" in p.stderr, p.stderr


def test_usage():
    assert dump(b"", "lane").returncode == 2
    assert subprocess.run([DUMP, "--help"], capture_output=True).returncode == 0
