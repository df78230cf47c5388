"""The classic frames' bit strings of tests/unit/can/test_vbus_wire.c, recounted with the
tests' own bit-level model (canwire.py, written apart from can/vbus_wire.c): the same bits, the
same stuff bits, for the frame with the most stuffing, a plain one, one without data and an
extended one."""
import os
import re

import canwire
from scenario import SOURCE_DIR

SRC = os.path.join(SOURCE_DIR, "tests", "unit", "can", "test_vbus_wire.c")


def classic_cases():
    text = open(SRC).read()
    # assert_classic("..." "...", ID, DATA, LEN, CRC): the string pieces, the ID, the data's name
    for m in re.finditer(r'assert_classic\(((?:\s*"[^"]*")+),\s*([^,]+),\s*([^,]+),\s*(\d+),', text):
        bits = "".join(re.findall(r'"([^"]*)"', m.group(1)))
        # the data array is the one declared last before the call
        yield bits, m.group(2).strip(), m.group(3).strip(), int(m.group(4)), text[:m.start()]


def data_of(name, length, text):
    if name == "NULL":
        return b""
    ms = list(re.finditer(r"static const uint8_t %s\[[^\]]*\](?:\s*=\s*\{([^}]*)\})?;" % name,
                          text))
    assert ms, name
    m = ms[-1]
    if m.group(1) is None:
        return bytes(length)
    return bytes(int(v, 0) for v in m.group(1).split(","))


def test_the_written_bit_strings_are_the_models():
    n = 0
    for bits, can_id, data, length, text in classic_cases():
        extended = "HL_DBC_EFF_FLAG" in can_id
        ident = int(can_id.split("|")[0].strip().rstrip("u"), 16)
        payload = data_of(data, length, text)
        want = "".join(c for c in bits if c in "01")
        got = "".join(map(str, canwire.stuffed(canwire.unstuffed(ident, payload, extended))))
        assert want == got, (can_id, want, got)
        assert bits.count("[") == len(got) - len(canwire.unstuffed(ident, payload, extended))
        n += 1
    assert n == 4
