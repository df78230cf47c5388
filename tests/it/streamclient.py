"""A client of hdlampd's frame stream (docs/daemon.md): header + pixels per frame."""
import socket
import struct

HEADER = struct.Struct("<IHHQIIIIII5q2Q2BB5x2qB3xII6fIfBB2xd16x")
MAGIC = 0x524C4448
FIELDS = ("magic", "version", "header_size", "seq", "width", "height", "stride", "pixel_format",
          "payload_size", "flags", "t_cycle_rx_ns", "t_cycle_done_ns", "t_render_start_ns",
          "t_render_done_ns", "t_sent_ns", "cycle_seq_left", "cycle_seq_right", "counter_left",
          "counter_right", "n_lamps", "t_lamp_done_left", "t_lamp_done_right", "n_sets",
          "sets_evaluated", "sets_failed", "centre_range_1_m", "centre_range_2_m",
          "edge_range_1_m", "edge_range_2_m", "width_1_m", "width_2_m", "glare_failed",
          "eye_lux_max", "n_actors", "scene_source", "scene_t_s")
VERSION = 3
SCENE_SOURCES = {0: "none", 1: "clock", 2: "log", 3: "pose", 4: "osi"}
assert HEADER.size == 192


def recv_exact(sock, n):
    buf = bytearray()
    while len(buf) < n:
        chunk = sock.recv(n - len(buf))
        if not chunk:
            return None
        buf += chunk
    return bytes(buf)


def read_frame(sock):
    """The next (header dict, pixels), or None when the daemon closed the stream."""
    raw = recv_exact(sock, HEADER.size)
    if raw is None:
        return None
    h = dict(zip(FIELDS, HEADER.unpack(raw)))
    assert h["magic"] == MAGIC and h["version"] == VERSION and h["header_size"] == HEADER.size, h
    pixels = recv_exact(sock, h["payload_size"])
    return (h, pixels) if pixels is not None else None


def connect(port, timeout=10):
    s = socket.create_connection(("127.0.0.1", port), timeout=timeout)
    return s
