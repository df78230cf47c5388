/* SPDX-License-Identifier: MIT */
/*
 * Writes DIR/vbus.log and DIR/vbus.blf from a known set of frames (classic standard and
 * extended, FD with BRS, no data) and DIR/vbus.expected, one line per frame as the bus
 * delivered it: "<ns since the epoch> <id hex> <ext> <fd> <brs> <data hex or ->", for
 * check_vbus_trace.py to compare with what python-can reads back. Exit 0, 1 on failure.
 */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "can/vbus.h"

#define EPOCH_NS 1700000000123456789LL /* not a whole millisecond: BLF's start time is cut */

static void on_rx(void *ctx, const struct hl_vbus_frame *f)
{
	FILE *out = ctx;

	fprintf(out, "%lld %X %d %d %d ", (long long)(EPOCH_NS + f->t_ns),
		f->can_id & ~HL_DBC_EFF_FLAG, !!(f->can_id & HL_DBC_EFF_FLAG), f->fd, f->brs);
	for (int i = 0; i < f->len; i++)
		fprintf(out, "%02X", f->data[i]);
	fprintf(out, "%s\n", f->len ? "" : "-");
}

int main(int argc, char **argv)
{
	static const uint8_t d8[8] = { 0xde, 0xad, 0xbe, 0xef, 0x01, 0x02, 0x03, 0x04 };
	uint8_t d64[64];
	char path[4096];
	struct hl_vbus *b;
	FILE *out;
	int tx, rc;

	if (argc != 2) {
		fprintf(stderr, "usage: vbus_trace_writer DIR\n");
		return 2;
	}
	for (int i = 0; i < 64; i++)
		d64[i] = (uint8_t)(i * 7);
	snprintf(path, sizeof(path), "%s/vbus.expected", argv[1]);
	out = fopen(path, "we");
	if (!out || hl_vbus_new(&(struct hl_vbus_config){ .name = "vbus0" }, &b) < 0)
		return 1;
	tx = hl_vbus_attach(b, "tx", NULL, NULL);
	hl_vbus_attach(b, "rx", on_rx, out);
	for (int k = 0; k < 2; k++) {
		snprintf(path, sizeof(path), "%s/vbus.%s", argv[1], k ? "blf" : "log");
		rc = hl_vbus_trace(b, path, EPOCH_NS);
		if (rc < 0) {
			fprintf(stderr, "vbus_trace_writer: '%s': %s\n", path, strerror(-rc));
			return 1;
		}
	}
	if (hl_vbus_trace(b, path, EPOCH_NS) != -EEXIST)
		return 1;
	hl_vbus_send(b, tx, 1234567, 0x123, d8, 8, false, false);
	hl_vbus_send(b, tx, 1234567, 0x18fef100u | HL_DBC_EFF_FLAG, d8, 3, false, false);
	hl_vbus_send(b, tx, 2000000, 0x456, d64, 64, true, true);
	hl_vbus_send(b, tx, 2000000, 0x1abcdef | HL_DBC_EFF_FLAG, d64, 12, true, false);
	hl_vbus_send(b, tx, 3000001, 0x7ff, NULL, 0, false, false);
	hl_vbus_send(b, tx, 3000001, 0x001, NULL, 0, true, true);
	hl_vbus_run_until(b, 1000000000);
	hl_vbus_free(b);
	return fclose(out) == 0 ? 0 : 1;
}
