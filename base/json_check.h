/* SPDX-License-Identifier: MIT */
/*
 * Strict checks of JSON read with jansson, with errors that say where: the file, the line and
 * column, the key path ("actors[1].path.waypoints[3].t_s", array indices 0-based) and what was
 * expected. jansson keeps no positions after parsing, so a second pass over the text (which
 * jansson has accepted) records the line and column of every object member's key and every
 * array element by path (struct hl_json_loc).
 *
 * Thread-safety: a location index is built by one thread and read-only afterwards; the checks
 * write only the error they are given.
 */
#ifndef HL_BASE_JSON_CHECK_H
#define HL_BASE_JSON_CHECK_H

#include <stdbool.h>
#include <stddef.h>

#define HL_JSON_PATH_MAX 160

struct json_t; /* jansson's */

/* Where a file is wrong. line and column are 1-based, 0 when unknown. */
struct hl_json_error {
	char file[256];
	int line, column;
	char key[HL_JSON_PATH_MAX]; /* the key path; "" for the whole file */
	char msg[320]; /* what is wrong and what was expected */
};

/* "FILE:LINE:COL: KEY: MESSAGE" (the parts that are unknown left out). Returns buf. */
const char *hl_json_error_format(const struct hl_json_error *err, char *buf, size_t size);

/*
 * The whole file as a NUL-terminated string (*ret malloc'd, the caller frees it). 0, -errno,
 * -EFBIG (over 64 MiB), -EBADMSG (a NUL byte in it); err (may be NULL) says what.
 */
int hl_json_read_file(const char *path, char **ret, struct hl_json_error *err);

struct hl_json_loc;

/* Indexes text, which jansson has accepted. 0, -ENOMEM, -EBADMSG (not JSON after all). */
int hl_json_loc_new(const char *text, struct hl_json_loc **ret);
void hl_json_loc_free(struct hl_json_loc *loc);
/*
 * The line and column of path: of its key for an object member, of the element for an array
 * element, "" for the top value. A path the text does not have (a missing key) gives the place
 * of its nearest ancestor that it has; line 1, column 1 at worst.
 */
void hl_json_loc_find(const struct hl_json_loc *loc, const char *path, int *ret_line,
		      int *ret_column);

/*
 * Parses text (the contents of the file name) with jansson, duplicate keys refused, and indexes
 * it. *ret_root (json_decref() it) and *ret_loc (hl_json_loc_free() it) are the caller's; both
 * untouched on failure. err (may be NULL) is reset to name and, on a syntax error, filled with
 * jansson's line, column and text. 0, -EBADMSG, -ENOMEM.
 */
int hl_json_parse(const char *text, const char *name, struct json_t **ret_root,
		  struct hl_json_loc **ret_loc, struct hl_json_error *err);

/* What the checks need to say where a fault is. */
struct hl_json_ctx {
	const char *name; /* the file */
	const struct hl_json_loc *loc;
	struct hl_json_error *err; /* may be NULL */
};

/* Fills out (a zeroed struct) from root; 0 or -errno (-EBADMSG with the error filled). */
typedef int (*hl_json_struct_fn)(struct hl_json_ctx *c, struct json_t *root, void *out);

/*
 * A file format read into one struct (a scenario, a suite): text parsed as hl_json_parse does,
 * a zeroed struct of size bytes allocated and filled by parse_root. *ret (free() it) is the
 * caller's, untouched on failure. 0, -EBADMSG, -ENOMEM, or parse_root's -errno; err (may be
 * NULL) says where.
 */
int hl_json_parse_struct(const char *text, const char *name, size_t size,
			 hl_json_struct_fn parse_root, void **ret, struct hl_json_error *err);
/* The same from the file path (hl_json_read_file(), then hl_json_parse_struct()). */
int hl_json_read_struct(const char *path, size_t size, hl_json_struct_fn parse_root, void **ret,
			struct hl_json_error *err);

/* Fills the error for path (its place from the index) and returns -EBADMSG. */
__attribute__((format(printf, 3, 4))) int hl_json_fail(const struct hl_json_ctx *c,
						       const char *path, const char *fmt, ...);
/* "an object", "an array", "a string", "a number", "a boolean", "null". */
const char *hl_json_type_name(const struct json_t *j);
/* path.key (key alone at the top), path[i], into buf; return buf. */
const char *hl_json_join(char *buf, size_t size, const char *path, const char *key);
const char *hl_json_index(char *buf, size_t size, const char *path, size_t i);

/* j must be an object whose keys are all in allowed (NULL-terminated). 0 or -EBADMSG. */
int hl_json_check_object(const struct hl_json_ctx *c, const char *path, const struct json_t *j,
			 const char *const *allowed);

/* A range of numbers: [lo, hi], or (lo, hi] with lo_open; unit for messages. */
struct hl_json_range {
	double lo, hi;
	bool lo_open;
	const char *unit;
};

/*
 * The getters read obj.key (path is obj's). An absent key is an error when required, else
 * *ret keeps what it holds (the default). A wrong type or a value out of range is an error.
 * 0 or -EBADMSG.
 */
int hl_json_number(const struct hl_json_ctx *c, const char *path, const struct json_t *j,
		   const struct hl_json_range *r, double *ret);
int hl_json_get_number(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		       const char *key, bool required, const struct hl_json_range *r, double *ret);
/* j (at path) as an integer in [lo, hi]. */
int hl_json_int(const struct hl_json_ctx *c, const char *path, const struct json_t *j, int lo,
		int hi, int *ret);
int hl_json_get_int(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		    const char *key, bool required, int lo, int hi, int *ret);
/* One of names (NULL-terminated): its index. */
int hl_json_get_enum(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		     const char *key, bool required, const char *const *names, int *ret);
/* A non-empty string shorter than size. */
int hl_json_get_string(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		       const char *key, bool required, char *out, size_t size);
/* [x, y, z], component k in r[k]. */
int hl_json_get_vec3(const struct hl_json_ctx *c, const char *path, const struct json_t *obj,
		     const char *key, bool required, const struct hl_json_range r[3],
		     double ret[3]);

#endif
