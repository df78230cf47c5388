/* SPDX-License-Identifier: MIT */
/*
 * Presets: the ECU's raw 6-bit dimming values for both lamps, as JSON
 * {"left": [v1, ..., vK], "right": [...]} with integers 0..63 (docs/design.md §1: i_k = v_k / 63).
 * Read with jansson and checked by base/json_check.h: an error names the line and column and
 * leads its message with the key path ("left[3]: ...").
 */
#ifndef HL_TOOLS_PRESET_H
#define HL_TOOLS_PRESET_H

#include <stdint.h>

#define HL_DIM_MAX 63 /* largest 6-bit dimming value */
#define HL_PRESET_MAX_SOURCES 4096 /* per lamp */

enum hl_side {
	HL_SIDE_LEFT,
	HL_SIDE_RIGHT,
};

struct hl_preset {
	int n_sources;
	uint8_t *dim[2]; /* indexed by enum hl_side, n_sources values each */
};

struct hl_preset_error {
	int line, column; /* 1-based; 0 when the fault has no place (e.g. file missing) */
	char msg[512]; /* "KEY: " and what was expected */
};

/* All zero, n_sources per lamp. 0, -EINVAL, -ENOMEM. */
int hl_preset_new(int n_sources, struct hl_preset **ret);
void hl_preset_free(struct hl_preset *p);

/*
 * 0, -ENOENT/-errno (cannot open; err->line 0), -EBADMSG (malformed; err says line, column, key
 * path and what was expected), -ENOMEM.
 */
int hl_preset_read(const char *path, struct hl_preset **ret, struct hl_preset_error *err);
int hl_preset_parse(const char *text, struct hl_preset **ret, struct hl_preset_error *err);
/* 0 or -errno. */
int hl_preset_write(const struct hl_preset *p, const char *path);

/* "left" / "right" to a side; -EINVAL for anything else. */
int hl_side_from_name(const char *name);
const char *hl_side_name(enum hl_side side);

/* Relative currents i_k = v_k / 63 of one lamp into i (n_sources floats). */
void hl_preset_intensities(const struct hl_preset *p, enum hl_side side, float *i);

#endif
