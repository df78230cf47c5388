/* SPDX-License-Identifier: MIT */
/*
 * A test suite of the ADB lab (docs/lab.md): a track procedure as data — which scenarios to
 * drive (generated from a table's parameters), where the photometers sit on the stimulus
 * vehicles, the limit table by range bin, the rounding of a bin's maximum, and the documented
 * defaults used where the official text was not found. Every value carries its source.
 *
 * Files: suites/NAME.json (installed to /usr/share/hdlamp/suites), read with jansson and checked
 * strictly (an unknown key, a wrong type, a value out of range is refused with the file, line,
 * column and key path, base/json_check.h):
 *
 *   {
 *     "version": 1,
 *     "name": "fmvss108-adb",                  the file's name without .json
 *     "title": "...",
 *     "procedure": "fmvss108-adb" | "iihs" | "r149-adb",
 *     "source": "...",                          the document the suite follows
 *     "rounding": {"decimals": 1, "rule": "half-even" | "half-up", "source": "..."},   optional
 *     "bins": [                                 fmvss108-adb: Table XXI, one row per bin
 *       {"role": "oncoming" | "preceding", "from_m": 15.0, "to_m": 29.9,
 *        "max_lx": 3.1 | null, "source": "..."}, ...],
 *     "photometers": [                          on a stimulus vehicle of this role, its body frame
 *       {"id": "driver", "role": "oncoming", "pos_m": [x, y, z], "normal": [x, y, z],
 *        "source": "..."}, ...],
 *     "scenarios": [
 *       {"id": "oncoming-straight", "title": "...", "role": "oncoming" | "preceding" | "none",
 *        "road": "straight" | "left" | "right",
 *        "speed_mph": [lo, hi], "radius_m": [lo, hi] (curves only), "range_m": [lo, hi],
 *        "source": "..."}, ...],
 *     "iihs": {"visibility_lx": 5.0, "visibility_height_m": 0.25, "glare_height_m": 1.1,
 *              "source": "..."},            iihs only
 *     "glare_set": "unece-r149-01-adb-glare",    r149-adb only: the regulation set judged
 *     "defaults": [{"what": "...", "value": "...", "why": "..."}, ...]
 *   }
 *
 * Thread-safety: a suite is read by one thread and read-only afterwards.
 */
#ifndef HL_VERDICT_SUITE_H
#define HL_VERDICT_SUITE_H

#include <stdbool.h>
#include <stddef.h>

#include "base/json_check.h"
#include "world/scenario.h"

#define HL_SUITE_MAX_BINS 16
#define HL_SUITE_MAX_PHOTOMETERS 8
#define HL_SUITE_MAX_SCENARIOS 16
#define HL_SUITE_MAX_DEFAULTS 24
#define HL_SUITE_ID_MAX 48
#define HL_SUITE_TEXT_MAX 512

enum hl_suite_procedure { HL_SUITE_FMVSS108_ADB, HL_SUITE_IIHS, HL_SUITE_R149_ADB };
enum hl_suite_road { HL_SUITE_STRAIGHT, HL_SUITE_LEFT, HL_SUITE_RIGHT };
enum hl_suite_rounding { HL_SUITE_HALF_EVEN, HL_SUITE_HALF_UP };

/* One row of a limit table: the bin [from_m, to_m] as written in the table. */
struct hl_suite_bin {
	enum hl_actor_role role;
	double from_m, to_m;
	double max_lx; /* NAN: no limit in this bin (reported only) */
	char source[HL_SUITE_TEXT_MAX];
};

/* A photometer on every stimulus vehicle of a role, in that vehicle's body frame (ISO 8855). */
struct hl_suite_photometer {
	char id[HL_SUITE_ID_MAX];
	enum hl_actor_role role;
	double pos_m[3];
	double normal[3]; /* unit length (normalised on reading) */
	char source[HL_SUITE_TEXT_MAX];
};

struct hl_suite_scenario {
	char id[HL_SUITE_ID_MAX];
	char title[HL_SUITE_TEXT_MAX];
	bool has_role; /* false: "none", an empty road (IIHS) */
	enum hl_actor_role role;
	enum hl_suite_road road;
	double speed_mph[2];
	double radius_m[2]; /* 0, 0 on a straight */
	double range_m[2];
	char source[HL_SUITE_TEXT_MAX];
};

struct hl_suite_default {
	char what[160];
	char value[160];
	char why[HL_SUITE_TEXT_MAX];
};

struct hl_suite {
	char name[HL_SUITE_ID_MAX];
	char title[HL_SUITE_TEXT_MAX];
	enum hl_suite_procedure procedure;
	char source[HL_SUITE_TEXT_MAX];
	bool has_rounding;
	int decimals;
	enum hl_suite_rounding rounding;
	char rounding_source[HL_SUITE_TEXT_MAX];
	int n_bins;
	struct hl_suite_bin bin[HL_SUITE_MAX_BINS];
	int n_photometers;
	struct hl_suite_photometer photometer[HL_SUITE_MAX_PHOTOMETERS];
	int n_scenarios;
	struct hl_suite_scenario scenario[HL_SUITE_MAX_SCENARIOS];
	/* iihs */
	double visibility_lx, visibility_height_m, glare_height_m;
	char iihs_source[HL_SUITE_TEXT_MAX];
	/* r149-adb */
	char glare_set[HL_SUITE_ID_MAX];
	int n_defaults;
	struct hl_suite_default def[HL_SUITE_MAX_DEFAULTS];
};

/*
 * Reads and checks one file. 0, -errno (cannot open), -EBADMSG (malformed, err says where),
 * -ENOMEM. *ret is the caller's, freed with hl_suite_free().
 */
int hl_suite_read(const char *path, struct hl_suite **ret, struct hl_json_error *err);
int hl_suite_parse(const char *text, const char *name, struct hl_suite **ret,
		   struct hl_json_error *err);
void hl_suite_free(struct hl_suite *s);
/* The shipped suites' directory: hl_share_dir("suites"). 0 or -errno. */
int hl_suite_default_dir(char *buf, size_t size);

const char *hl_suite_procedure_name(enum hl_suite_procedure p);
const char *hl_suite_road_name(enum hl_suite_road r);

#endif
