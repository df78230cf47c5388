/* SPDX-License-Identifier: MIT */
/*
 * A regulation set as data (docs/regulations.md): the requirements one regulation version puts
 * on one beam class, read from a JSON file of regulations/ with jansson. The evaluator
 * (verdict/verdict.h) knows the requirement kinds, never a regulation.
 *
 * Angles: degrees, H positive right, V positive up, right-hand traffic (left-hand traffic is
 * mirrored by the evaluator). In files they are written as the regulations write them:
 * "3.43L", "0.57U", "V", "H", or a bare number with that sign convention; "L" and "R" alone
 * are open ends (as far as the distribution reaches, FMVSS 108's "1.5L to L").
 *
 * Thread-safety: a regulation is built by one thread and read-only afterwards.
 */
#ifndef HL_VERDICT_REGULATION_H
#define HL_VERDICT_REGULATION_H

#include <stdbool.h>
#include <stddef.h>

#include "lamp/lid.h"

#define HL_REG_ID_MAX 48
#define HL_REG_TEXT_MAX 256
#define HL_REG_MAX_REQUIREMENTS 128
#define HL_REG_MAX_VERTICES 16 /* zone polygon corners, sum points */
#define HL_REG_OPEN_LEFT (-1.0e9) /* an open end "L": the distribution's left edge */
#define HL_REG_OPEN_RIGHT (1.0e9) /* an open end "R": its right edge */
#define HL_REG_OPEN_DOWN (-1.0e9)
#define HL_REG_OPEN_UP (1.0e9)

enum hl_req_kind {
	HL_REQ_POINT, /* the receiver's mean at (h, v) */
	HL_REQ_SEGMENT, /* the receiver's mean along a line (h0, v0)-(h1, v1), horizontal or vertical */
	HL_REQ_ZONE, /* the receiver's mean over a polygon (edges included) */
	HL_REQ_SUM, /* the sum of the receiver's means at several points */
	HL_REQ_IMAX, /* the highest sample of the whole distribution */
};

/* Which distribution a set applies to. */
enum hl_reg_applies {
	HL_REG_EACH_LAMP, /* each headlamp on its own (R149 photometry) */
	HL_REG_PAIR_HALF, /* half the sum of the pair (R123 / R149 ADB glare table) */
};

enum hl_receiver_shape {
	HL_RECEIVER_SQUARE, /* side size_deg */
	HL_RECEIVER_CIRCLE, /* diameter size_deg */
};

/*
 * The beam a set is written for (its optional key "beam"): with a beam-mode signal in the
 * lamps' database the daemon checks it only on frames of that beam (docs/live-verdicts.md).
 */
enum hl_reg_beam {
	HL_REG_BEAM_NONE, /* no "beam": the set applies in every mode */
	HL_REG_BEAM_PASSING, /* "passing": the low beam */
	HL_REG_BEAM_DRIVING, /* "driving": the high beam */
	HL_REG_BEAM_ADB, /* "adb": the adaptive (glare-free) driving beam */
};

/* How the regulation aims a beam before measuring (used with --aim regulation). */
enum hl_reg_aim {
	HL_REG_AIM_NONE, /* measured as mounted (driving beams, ADB glare limits) */
	HL_REG_AIM_CUTOFF, /* the cut-off's inflection point on a vertical scan at scan_h to cutoff_v */
};

/*
 * A limit: absent, an absolute value in cd, or factor times the value of an earlier requirement
 * of the same set (of >= 0: its index; "of": "Imax" is the usual case).
 */
struct hl_req_limit {
	bool set;
	int of; /* -1: absolute cd */
	double cd; /* absolute value, when of < 0 */
	double factor; /* when of >= 0 */
};

struct hl_requirement {
	char id[HL_REG_ID_MAX]; /* as the regulation names it: "B50L", "Zone III", "Segment 25" */
	enum hl_req_kind kind;
	/* point: pts[0]; segment: pts[0] to pts[1]; zone: polygon pts[0..n_pts-1]; sum: points */
	double pts[HL_REG_MAX_VERTICES][2]; /* h, v degrees; may hold HL_REG_OPEN_* */
	int n_pts;
	struct hl_req_limit min, max;
	char source[HL_REG_TEXT_MAX]; /* citation: document, table, row or page */
	int line; /* where it is in the file */
};

struct hl_regulation {
	char id[HL_REG_ID_MAX]; /* "unece-r149-01-passing-c" */
	char title[HL_REG_TEXT_MAX];
	char source[HL_REG_TEXT_MAX]; /* the document the set comes from */
	enum hl_reg_applies applies;
	enum hl_reg_beam beam;
	enum hl_angles angles; /* the goniometer system the angles are given in */
	enum hl_receiver_shape receiver;
	double receiver_deg; /* square side or circle diameter */
	enum hl_reg_aim aim;
	double aim_scan_h_deg; /* HL_REG_AIM_CUTOFF: where the vertical scan runs (-2.5) */
	double aim_cutoff_v_deg; /* where the inflection point goes (-0.57) */
	double aim_linearity_h_deg[2]; /* the other scans of the linearity check (-1.5, -3.5) */
	double aim_linearity_max_deg; /* largest spread of the three inflection points (0.2) */
	double aim_g_min, aim_g_max; /* the sharpness limits of G (0.13, 0.40); no max: inf */
	int n_requirements;
	struct hl_requirement req[HL_REG_MAX_REQUIREMENTS];
};

/* Where a regulation file is wrong: line and column are 1-based, 0 when unknown. */
struct hl_regulation_error {
	int line, column;
	char msg[512]; /* names the file, the line, the key and what was expected */
};

/*
 * Reads and validates one file. 0, -ENOENT/-errno (cannot open), -EBADMSG (malformed JSON, an
 * unknown or missing key, a wrong type, an angle or limit that makes no sense, a relative limit
 * naming no earlier requirement), -ENOMEM. err says where.
 */
int hl_regulation_read(const char *path, struct hl_regulation **ret,
		       struct hl_regulation_error *err);
/* The same from text; name stands for the file in messages. */
int hl_regulation_parse(const char *text, const char *name, struct hl_regulation **ret,
			struct hl_regulation_error *err);
void hl_regulation_free(struct hl_regulation *reg);

/*
 * Loads the set with this id from dir (the file dir/ID.json). 0, -ENOENT (no such set),
 * or as hl_regulation_read.
 */
int hl_regulation_load(const char *dir, const char *id, struct hl_regulation **ret,
		       struct hl_regulation_error *err);

/*
 * The shipped sets' directory: hl_share_dir("regulations") (base/share_dir.h), e.g.
 * /usr/bin/hdlamp -> /usr/share/hdlamp/regulations. 0 or -errno.
 */
int hl_regulation_default_dir(char *buf, size_t size);

/*
 * The ids of every set in dir, sorted, into a NULL-terminated array the caller frees with
 * hl_regulation_list_free(). 0, -errno.
 */
int hl_regulation_list(const char *dir, char ***ret);
void hl_regulation_list_free(char **ids);

/* Index of the requirement with this id, or -ENOENT. */
int hl_regulation_find(const struct hl_regulation *reg, const char *id);

const char *hl_req_kind_name(enum hl_req_kind kind);
/* "passing", "driving", "adb", or NULL for HL_REG_BEAM_NONE (as the files write them). */
const char *hl_reg_beam_name(enum hl_reg_beam beam);

/*
 * Parses an angle as the files write it: "3.43L", "0.57U", "V", "H", "L"/"R"/"U"/"D" (open
 * ends), or a number. axis 'h' accepts L/R/V, axis 'v' accepts U/D/H. 0 or -EINVAL.
 */
int hl_regulation_angle(const char *s, char axis, double *ret_deg);

#endif
