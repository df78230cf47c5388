"""A classic CAN data frame's bits on the wire, written for the tests from ISO 11898-1's frame
layout (as docs/sil.md cites it), independently of can/vbus_wire.c: SOF, the identifier (11
bits, or 11 + SRR + IDE + 18), RTR, the control bits, the DLC, the data, the CRC-15 (generator
0x4599 over the unstuffed bits from SOF to the end of the data), stuff bits after every five
equal bits from SOF to the end of the CRC (a stuff bit starts the next run), then the CRC
delimiter, the ACK slot and delimiter and 7 EOF bits, never stuffed; 3 bits of intermission
follow before the next frame."""

EFF = 0x80000000  # the extended-ID flag as candump lines and the bus's frames carry it


def crc15(bits):
    crc = 0
    for b in bits:
        nxt = b ^ ((crc >> 14) & 1)
        crc = (crc << 1) & 0x7FFF
        if nxt:
            crc ^= 0x4599
    return crc


def field(value, n):
    return [(value >> (n - 1 - i)) & 1 for i in range(n)]


def unstuffed(can_id, data, extended=False):
    """SOF to the end of the CRC sequence, before stuffing."""
    bits = [0]
    if extended:
        bits += field(can_id >> 18, 11) + [1, 1] + field(can_id & 0x3FFFF, 18) + [0, 0, 0]
    else:
        bits += field(can_id, 11) + [0, 0, 0]  # RTR, IDE, r0
    bits += field(len(data), 4)
    for byte in data:
        bits += field(byte, 8)
    return bits + field(crc15(bits), 15)


def stuffed(bits):
    out, run, last = [], 0, None
    for b in bits:
        out.append(b)
        run = run + 1 if b == last else 1
        last = b
        if run == 5:
            out.append(1 - b)
            last, run = 1 - b, 1
    return out


def frame_bits(can_id, data, extended=False):
    """The frame's bits from SOF to the end of EOF (intermission not included)."""
    return len(stuffed(unstuffed(can_id, data, extended))) + 1 + 1 + 1 + 7


INTERMISSION = 3
