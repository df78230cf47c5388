#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Writes dbc/hd84.dbc and dbc/hd84_fd.dbc, the HD84 lamp pair's CAN databases, and with
--sources N the CAN FD database of a pixel lamp pair of N sources per lamp (dbc/pixelN_fd.dbc).

The .dbc files are the data the daemon reads; this script only keeps their signal and attribute
lines consistent. Run it from the source tree:
  tools/gen_hd84_dbc.py                   hd84.dbc and hd84_fd.dbc
  tools/gen_hd84_dbc.py --sources 1024    pixel1024_fd.dbc (--out FILE to write elsewhere)
"""
import argparse
import math
import os
import sys

N_SOURCES = 95  # per lamp: 84 matrix LEDs (3 rows of 28) + 11 further sources (docs/design.md §1)
FACTOR = repr(1 / 63)  # 0.015873015873015872: reads back as exactly the double 1/63
LAMPS = (("L", "left", "HL_L"), ("R", "right", "HL_R"))
# The beam mode each cycle is driven in (SG_ attribute HdlBeamMode, docs/dbc.md): 0 must mean
# "not said", so that a log written before the signal existed (those bits zero) keeps meaning
# every regulation set on every frame.
MODES = ((0, "unset"), (1, "low"), (2, "high"), (3, "glarefree"))
MODE_BITS = 6  # the slot after the last source, as wide as one

HEADER = '''VERSION "hdlamp {version}"


NS_ :
	NS_DESC_
	CM_
	BA_DEF_
	BA_
	VAL_
	BA_DEF_DEF_
	SIG_VALTYPE_
	SG_MUL_VAL_
	BO_TX_BU_

BS_:

BU_: ECU HL_L HL_R

'''

ATTR_DEFS = '''BA_DEF_  "BusType" STRING ;
BA_DEF_ BO_  "GenMsgCycleTime" INT 0 10000;
BA_DEF_ BO_  "VFrameFormat" ENUM  "StandardCAN","ExtendedCAN","reserved","reserved","reserved","reserved","reserved","reserved","reserved","reserved","reserved","reserved","reserved","reserved","StandardCAN_FD","ExtendedCAN_FD";
BA_DEF_ BO_  "HdlLamp" STRING ;
BA_DEF_ BO_  "HdlE2E" STRING ;
BA_DEF_ SG_  "HdlSource" INT 0 4096;
BA_DEF_DEF_  "BusType" "CAN";
BA_DEF_DEF_  "GenMsgCycleTime" 0;
BA_DEF_DEF_  "VFrameFormat" "StandardCAN";
BA_DEF_DEF_  "HdlLamp" "";
BA_DEF_DEF_  "HdlE2E" "none";
BA_DEF_DEF_  "HdlSource" 0;
'''
# hd84.dbc and hd84_fd.dbc only (the pixel databases carry no beam mode)
MODE_ATTR_DEF = 'BA_DEF_ SG_  "HdlBeamMode" INT 0 1;'
MODE_ATTR_DEF_DEF = 'BA_DEF_DEF_  "HdlBeamMode" 0;'

CLASSIC_NOTE = '''hd84.dbc - the HD84 headlamp pair on classic CAN (hdlamp, docs/dbc.md).

Every 20 ms the ECU sends the 6-bit dimming value v_k of each of the 95 sources of each lamp;
the relative current is i_k = v_k / 63, which is the physical value of every LED_nnn signal
(factor 1/63, offset 0). Each lamp has one multiplexed 8-byte message:
  HL_Dim_L 0x320 (800), lamp left;  HL_Dim_R 0x321 (801), lamp right.

Byte 0       CRC-8 SAE J1850 (poly 0x1D, init 0xFF, final XOR 0xFF) over the data ID (low
             byte, high byte: HdlE2E P1 dataid) and bytes 1..7 - the E2E profile 1 layout.
Byte 1 0..3  alive counter 0..14, one step per cycle: the 12 pages of one cycle carry the
             same value (a receiver completes a cycle when every page of one counter value
             has arrived); wraps 14 -> 0, 15 is never sent.
Byte 1 4..7  page index 0..11, the multiplexor.
Bytes 2..7   8 sources x 6 bits, Intel: slot j (0..7) at start bit 16 + 6 j holds source
             8 page + j + 1, signal LED_nnn with attribute HdlSource nnn.

Page 11     bits 58..63: HL_Mode_L / HL_Mode_R, the beam mode of the cycle (HdlBeamMode):
             0 unset (not said), 1 low, 2 high, 3 glarefree.

A cycle is pages 0..11 in order, 12 frames per lamp, 24 per 20 ms (about 30 percent of a
500 kbit/s bus). 12 x 8 = 96 slots carry 95 sources and the beam mode in the last slot (page
11, bits 58..63). A log written before the mode signal existed has zeros there: unset.

Attributes: HdlLamp (BO_, string) names the lamp of the daemon's configuration; HdlSource
(SG_, int) is the 1-based source index, 0 for signals that carry no source; HdlBeamMode (SG_,
int) 1 marks the signal that tells the beam mode, its VAL_ descriptions name the modes;
HdlE2E (BO_, string) is the E2E profile and data ID; GenMsgCycleTime is the cycle, 20 ms.'''

FD_NOTE = '''hd84_fd.dbc - the HD84 headlamp pair on CAN FD (hdlamp, docs/dbc.md).

The same 95 sources per lamp as hd84.dbc, 6 bits each, physical value i_k = v_k / 63, but in
two CAN FD frames per lamp and cycle, without multiplexing:
  HL_DimA_L 0x330 (816), 64 bytes: sources 1..80    HL_DimB_L 0x331 (817), 16 bytes: 81..95
  HL_DimA_R 0x332 (818), 64 bytes: sources 1..80    HL_DimB_R 0x333 (819), 16 bytes: 81..95

Bytes 0..1   CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF), little endian, over bytes
             2..len-1 and then the data ID low and high byte (HdlE2E P5 dataid).
Byte 2       counter 0..255, one step per cycle; A and B of one cycle carry the same value,
             which is how a receiver pairs them.
Bytes 3..    the sources, 6 bits each, Intel: source k of the frame at start bit 24 + 6 (k - 1).
             A: 80 x 6 = 480 bits end at bit 503, byte 63 is reserved (zero).
             B: 15 x 6 = 90 bits end at bit 113.
B 114..119   HL_Mode_L / HL_Mode_R, the beam mode of the cycle (HdlBeamMode): 0 unset (not
             said), 1 low, 2 high, 3 glarefree. Bits 120..127 of B are reserved (zero).

E2E: AUTOSAR profile 5, not a profile 2 style CRC-8. With 64-byte payloads an 8-bit CRC is
too weak: the CRC8H2F polynomial keeps Hamming distance 4 only up to 119 data bits and every
CRC-8 lets 1 in 256 random corruptions through, while CRC-16/CCITT keeps Hamming distance 4 up
to 32751 bits and lets 1 in 65536 through. Profile 5 is the profile AUTOSAR defines for such
frames (static data ID, not sent; 8-bit counter), and two bytes of CRC are cheap in a 64-byte
frame.

Attributes as hd84.dbc: HdlLamp, HdlSource, HdlBeamMode, HdlE2E, GenMsgCycleTime.'''


def source_attrs(msg_id, names_first, digits=3):
    return [f'BA_ "HdlSource" SG_ {msg_id} LED_{k:0{digits}d} {k};' for k in names_first]


def mode_signal(suffix, node, start, mux=""):
    """The beam-mode signal of a lamp (the SG_ line) and its VAL_ line's descriptions."""
    sg = f' SG_ HL_Mode_{suffix}{mux} : {start}|{MODE_BITS}@1+ (1,0) [0|{MODES[-1][0]}] "" {node}'
    return sg, " ".join(f'{v} "{name}"' for v, name in MODES)


def mode_lines(msg_id, suffix, where):
    cm = f'CM_ SG_ {msg_id} HL_Mode_{suffix} "Beam mode of the cycle ({where}): 0 unset (not said), 1 low, 2 high, 3 glarefree.";'
    ba = f'BA_ "HdlBeamMode" SG_ {msg_id} HL_Mode_{suffix} 1;'
    return cm, ba


def attr_defs():
    """ATTR_DEFS with HdlBeamMode's definition and default beside HdlSource's."""
    lines = ATTR_DEFS.rstrip("\n").split("\n")
    at = lines.index('BA_DEF_ SG_  "HdlSource" INT 0 4096;') + 1
    lines.insert(at, MODE_ATTR_DEF)
    lines.append(MODE_ATTR_DEF_DEF)
    return "\n".join(lines)


def classic():
    out = [HEADER.format(version="HD84 1.0")]
    ba, cm, val = [], [], []
    for i, (suffix, lamp, node) in enumerate(LAMPS):
        msg_id = 0x320 + i
        out.append(f"BO_ {msg_id} HL_Dim_{suffix}: 8 ECU")
        out.append(f' SG_ HL_CRC_{suffix} : 0|8@1+ (1,0) [0|255] "" {node}')
        out.append(f' SG_ HL_Alive_{suffix} : 8|4@1+ (1,0) [0|14] "" {node}')
        out.append(f' SG_ HL_Page_{suffix} M : 12|4@1+ (1,0) [0|11] "" {node}')
        for k in range(1, N_SOURCES + 1):
            page, slot = divmod(k - 1, 8)
            out.append(f' SG_ LED_{k:03d} m{page} : {16 + 6 * slot}|6@1+ ({FACTOR},0) [0|1] "" {node}')
        # the slot after the last source: page 11, slot 7
        page, slot = divmod(N_SOURCES, 8)
        sg, modes = mode_signal(suffix, node, 16 + 6 * slot, f" m{page}")
        out.append(sg)
        out.append("")
        cm.append(f'CM_ BO_ {msg_id} "Dimming of the {lamp} lamp: page HL_Page_{suffix} carries sources 8 page + 1 .. 8 page + 8.";')
        cm.append(f'CM_ SG_ {msg_id} HL_CRC_{suffix} "CRC-8 SAE J1850 over data ID (low, high) and bytes 1..7 (E2E P1 layout).";')
        cm.append(f'CM_ SG_ {msg_id} HL_Alive_{suffix} "Alive counter 0..14, +1 per cycle (all pages of a cycle carry it), wraps to 0.";')
        cm.append(f'CM_ SG_ {msg_id} HL_Page_{suffix} "Page 0..11: which 8 sources bytes 2..7 carry.";')
        mode_cm, mode_ba = mode_lines(msg_id, suffix, f"page {page}, bits {16 + 6 * slot}..{16 + 6 * slot + MODE_BITS - 1}")
        cm.append(mode_cm)
        ba.append(f'BA_ "GenMsgCycleTime" BO_ {msg_id} 20;')
        ba.append(f'BA_ "VFrameFormat" BO_ {msg_id} 0;')
        ba.append(f'BA_ "HdlLamp" BO_ {msg_id} "{lamp}";')
        ba.append(f'BA_ "HdlE2E" BO_ {msg_id} "P1 dataid=0x{msg_id:04X}";')
        ba.extend(source_attrs(msg_id, range(1, N_SOURCES + 1)))
        ba.append(mode_ba)
        pages = " ".join(f'{p} "sources {8 * p + 1}-{min(8 * p + 8, N_SOURCES)}"' for p in range(12))
        val.append(f"VAL_ {msg_id} HL_Page_{suffix} {pages} ;")
        val.append(f"VAL_ {msg_id} HL_Mode_{suffix} {modes} ;")
    out.append("")
    out.append(f'CM_ "{CLASSIC_NOTE}";')
    out.extend(cm)
    out.append(attr_defs())
    out.append('BA_ "BusType" "CAN";')
    out.extend(ba)
    out.extend(val)
    return "\n".join(out) + "\n"


def fd():
    out = [HEADER.format(version="HD84 FD 1.0")]
    ba, cm, val = [], [], []
    for i, (suffix, lamp, node) in enumerate(LAMPS):
        for part, (size, first, last) in zip("AB", ((64, 1, 80), (16, 81, N_SOURCES))):
            msg_id = 0x330 + 2 * i + (part == "B")
            name = f"HL_Dim{part}_{suffix}"
            out.append(f"BO_ {msg_id} {name}: {size} ECU")
            out.append(f' SG_ HL_CRC_{part}_{suffix} : 0|16@1+ (1,0) [0|65535] "" {node}')
            out.append(f' SG_ HL_Counter_{part}_{suffix} : 16|8@1+ (1,0) [0|255] "" {node}')
            for k in range(first, last + 1):
                out.append(f' SG_ LED_{k:03d} : {24 + 6 * (k - first)}|6@1+ ({FACTOR},0) [0|1] "" {node}')
            if part == "B":  # the slot after the last source
                mode_start = 24 + 6 * (last - first + 1)
                sg, modes = mode_signal(suffix, node, mode_start)
                out.append(sg)
            out.append("")
            cm.append(f'CM_ BO_ {msg_id} "Dimming of the {lamp} lamp, sources {first}..{last} ({size}-byte CAN FD frame {part} of 2).";')
            cm.append(f'CM_ SG_ {msg_id} HL_CRC_{part}_{suffix} "CRC-16/CCITT-FALSE over bytes 2..{size - 1} and the data ID (E2E P5), little endian.";')
            cm.append(f'CM_ SG_ {msg_id} HL_Counter_{part}_{suffix} "Counter 0..255, +1 per cycle; equal in frames A and B of a cycle.";')
            ba.append(f'BA_ "GenMsgCycleTime" BO_ {msg_id} 20;')
            ba.append(f'BA_ "VFrameFormat" BO_ {msg_id} 14;')
            ba.append(f'BA_ "HdlLamp" BO_ {msg_id} "{lamp}";')
            ba.append(f'BA_ "HdlE2E" BO_ {msg_id} "P5 dataid=0x{msg_id:04X}";')
            ba.extend(source_attrs(msg_id, range(first, last + 1)))
            if part == "B":
                mode_cm, mode_ba = mode_lines(msg_id, suffix, f"bits {mode_start}..{mode_start + MODE_BITS - 1}")
                cm.append(mode_cm)
                ba.append(mode_ba)
                val.append(f"VAL_ {msg_id} HL_Mode_{suffix} {modes} ;")
    out.append("")
    out.append(f'CM_ "{FD_NOTE}";')
    out.extend(cm)
    out.append(attr_defs())
    out.append('BA_ "BusType" "CAN FD";')
    out.extend(ba)
    out.extend(val)
    return "\n".join(out) + "\n"


# Pixel lamps: one multiplexed 64-byte CAN FD message per lamp, PIXEL_PER_PAGE sources a page.
PIXEL_IDS = (0x340, 0x341)
PIXEL_FIRST_BIT = 32  # bytes 0..1 CRC, 2 counter, 3 page
PIXEL_PER_PAGE = (8 * 64 - PIXEL_FIRST_BIT) // 6  # 80
MAX_PAGES = 64  # HL_ASM_MAX_PARTS (can/assembler.h): parts of one lamp's cycle
MAX_SIGNALS = 4096  # HL_DBC_MAX_SIGNALS (dbc/database.h): signals of one message
NOMINAL_BPS = 500000
DATA_BPS = (2000000, 5000000)
FRAME_GAP_US = 400  # hdlamp scenario's spacing of the frames of one cycle

PIXEL_NOTE = '''{name} - a pixel headlamp pair of {n} sources per lamp on CAN FD (hdlamp, docs/dbc.md).

Written by tools/gen_hd84_dbc.py --sources {n} for the lamps of hdlamp model --sources {n}
(pixel{n}_left.lid.exr, pixel{n}_right.lid.exr: {n} sources in rows by increasing H, row 1 at
the top). Every 20 ms the ECU sends the 6-bit dimming value v_k of every source of each lamp;
the relative current is i_k = v_k / 63, the physical value of every LED_{k_digits} signal (factor 1/63).
Each lamp has one multiplexed 64-byte CAN FD message (bit rate switch), {pages} pages a cycle:
  HL_Pix_L 0x{id_l:03X} ({id_l}), lamp left;  HL_Pix_R 0x{id_r:03X} ({id_r}), lamp right.

Bytes 0..1   CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF), little endian, over bytes 2..63
             and then the data ID low and high byte (HdlE2E P5 dataid, as hd84_fd.dbc).
Byte 2       counter 0..255, one step per cycle; every page of one cycle carries the same
             value (a receiver completes a cycle when every page of one counter has arrived).
Byte 3       page index 0..{last_page}, the multiplexor.
Bytes 4..63  {per_page} sources x 6 bits, Intel: slot j (0..{last_slot}) at start bit {first_bit} + 6 j holds
             source {per_page} page + j + 1, signal LED_nnnn with attribute HdlSource nnnn.
             Page {last_page} carries {last_n} sources; its bits {last_end}..511 are reserved (zero).

A cycle is pages 0..{last_page} of both lamps, {frames} frames per 20 ms. One frame (base ID, 64
bytes, CRC-21) is {nom} bits at the nominal rate (arbitration, CRC delimiter, ACK, EOF,
intermission) and {data} bits at the data rate (ESI, DLC, data, stuff count, CRC, fixed stuff
bits), plus at most {stuff} dynamic stuff bits. At {nom_kbps} kbit/s nominal:
{load}
hdlamp scenario spaces the frames of a cycle {gap} us apart (a frame's time at 2 Mbit/s with a
few stuff bits), so a cycle's frames take {span:.1f} ms of the 20 ms period.

Attributes as hd84_fd.dbc: HdlLamp (BO_, string) names the lamp of the daemon's configuration;
HdlSource (SG_, int) is the 1-based source index, 0 for signals that carry no source; HdlE2E
(BO_, string) is the E2E profile and data ID; GenMsgCycleTime is the cycle, 20 ms.'''


def fd_frame_bits(size):
    """One CAN FD frame, base ID, bit rate switch (ISO 11898-1:2015): bits at the nominal rate
    and at the data rate, and the most dynamic stuff bits (one per 4 bits from SOF to the end
    of the data) in each phase."""
    arbitration = 1 + 11 + 1 + 1 + 1 + 1 + 1  # SOF, ID, RRS, IDE, FDF, res, BRS
    tail = 1 + 1 + 1 + 7 + 3  # CRC delimiter, ACK slot, ACK delimiter, EOF, intermission
    crc = 21 if size > 16 else 17
    fixed_stuff = math.ceil((4 + crc) / 4)  # before the stuff count, then every 4 bits
    data = 1 + 4 + 8 * size + 4 + crc + fixed_stuff  # ESI, DLC, data, stuff count, CRC
    stuff = (arbitration + 1 + 4 + 8 * size - 1) // 4
    stuff_nominal = (arbitration - 1) // 4
    return arbitration + tail, data, stuff_nominal, stuff - stuff_nominal


def bus_load(frames):
    """Lines: the time the frames of one cycle take on the bus at each data rate."""
    nom, data, stuff_nom, stuff_data = fd_frame_bits(64)
    lines = []
    for bps in DATA_BPS:
        t = nom / NOMINAL_BPS + data / bps
        worst = t + stuff_nom / NOMINAL_BPS + stuff_data / bps
        lines.append(f"  {bps // 1000000} Mbit/s data: {1e6 * t:.1f} us a frame ({1e6 * worst:.1f} with the most "
                     f"stuff bits), {frames} frames {1e3 * frames * t:.2f} ms = bus load "
                     f"{100 * frames * t / 0.020:.1f} % ({100 * frames * worst / 0.020:.1f} % at most)")
    return "\n".join(lines)


def pixel(n, name):
    pages = math.ceil(n / PIXEL_PER_PAGE)
    if n < 1 or pages > MAX_PAGES or n + 3 > MAX_SIGNALS:
        raise ValueError(f"--sources {n}: expected 1..{MAX_SIGNALS - 3}")
    digits = max(4, len(str(n)))
    last_n = n - PIXEL_PER_PAGE * (pages - 1)
    nom, data, stuff_nom, stuff_data = fd_frame_bits(64)
    note = PIXEL_NOTE.format(
        name=name, n=n, k_digits="n" * digits, pages=pages, id_l=PIXEL_IDS[0], id_r=PIXEL_IDS[1],
        last_page=pages - 1, per_page=PIXEL_PER_PAGE, last_slot=PIXEL_PER_PAGE - 1,
        first_bit=PIXEL_FIRST_BIT, last_n=last_n, last_end=PIXEL_FIRST_BIT + 6 * last_n,
        frames=2 * pages, nom=nom, data=data, stuff=stuff_nom + stuff_data, nom_kbps=NOMINAL_BPS // 1000,
        load=bus_load(2 * pages), gap=FRAME_GAP_US, span=2 * pages * FRAME_GAP_US / 1000)
    out = [HEADER.format(version=f"pixel{n} FD 1.0")]
    ba, cm, val = [], [], []
    for i, (suffix, lamp, node) in enumerate(LAMPS):
        msg_id = PIXEL_IDS[i]
        out.append(f"BO_ {msg_id} HL_Pix_{suffix}: 64 ECU")
        out.append(f' SG_ HL_CRC_{suffix} : 0|16@1+ (1,0) [0|65535] "" {node}')
        out.append(f' SG_ HL_Counter_{suffix} : 16|8@1+ (1,0) [0|255] "" {node}')
        out.append(f' SG_ HL_Page_{suffix} M : 24|8@1+ (1,0) [0|{pages - 1}] "" {node}')
        for k in range(1, n + 1):
            page, slot = divmod(k - 1, PIXEL_PER_PAGE)
            out.append(f' SG_ LED_{k:0{digits}d} m{page} : {PIXEL_FIRST_BIT + 6 * slot}|6@1+ ({FACTOR},0) [0|1] "" {node}')
        out.append("")
        cm.append(f'CM_ BO_ {msg_id} "Dimming of the {lamp} lamp: page HL_Page_{suffix} carries sources {PIXEL_PER_PAGE} page + 1 .. {PIXEL_PER_PAGE} page + {PIXEL_PER_PAGE}.";')
        cm.append(f'CM_ SG_ {msg_id} HL_CRC_{suffix} "CRC-16/CCITT-FALSE over bytes 2..63 and the data ID (E2E P5), little endian.";')
        cm.append(f'CM_ SG_ {msg_id} HL_Counter_{suffix} "Counter 0..255, +1 per cycle; equal in every page of a cycle.";')
        cm.append(f'CM_ SG_ {msg_id} HL_Page_{suffix} "Page 0..{pages - 1}: which {PIXEL_PER_PAGE} sources bytes 4..63 carry.";')
        ba.append(f'BA_ "GenMsgCycleTime" BO_ {msg_id} 20;')
        ba.append(f'BA_ "VFrameFormat" BO_ {msg_id} 14;')
        ba.append(f'BA_ "HdlLamp" BO_ {msg_id} "{lamp}";')
        ba.append(f'BA_ "HdlE2E" BO_ {msg_id} "P5 dataid=0x{msg_id:04X}";')
        ba.extend(source_attrs(msg_id, range(1, n + 1), digits))
        descs = " ".join(f'{p} "sources {PIXEL_PER_PAGE * p + 1}-{min(PIXEL_PER_PAGE * (p + 1), n)}"' for p in range(pages))
        val.append(f"VAL_ {msg_id} HL_Page_{suffix} {descs} ;")
    out.append("")
    out.append(f'CM_ "{note}";')
    out.extend(cm)
    out.append(ATTR_DEFS.rstrip("\n"))
    out.append('BA_ "BusType" "CAN FD";')
    out.extend(ba)
    out.extend(val)
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description="Writes hdlamp's CAN databases (see the top of this file).")
    ap.add_argument("--sources", type=int, help=f"a pixel lamp pair of N sources per lamp (1..{MAX_SIGNALS - 3})")
    ap.add_argument("--out", help="with --sources: the file to write (default dbc/pixelN_fd.dbc)")
    args = ap.parse_args()
    top = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    if args.sources is None:
        if args.out:
            ap.error("--out needs --sources")
        for name, text in (("hd84.dbc", classic()), ("hd84_fd.dbc", fd())):
            with open(os.path.join(top, "dbc", name), "w") as f:
                f.write(text)
        return 0
    out = args.out or os.path.join(top, "dbc", f"pixel{args.sources}_fd.dbc")
    try:
        text = pixel(args.sources, f"pixel{args.sources}_fd.dbc")
    except ValueError as e:
        ap.error(str(e))
    with open(out, "w") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
