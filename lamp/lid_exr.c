/* SPDX-License-Identifier: MIT */
/*
 * LID files: OpenEXR through OpenEXRCore (docs/lid-files.md). One scanline part, one FLOAT or HALF
 * channel per source ("src0001"...) or one channel "I" for a combined distribution, and the
 * hdlamp:* attributes. Everything is validated; a fault is reported with the file's name.
 */
#include "lamp/lid.h"
#include "lamp/lid_internal.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <openexr.h>

#include "lamp/exr_error.h"

#define SCRATCH_BYTES (16u << 20) /* decode buffer for a batch of channels */

/* Reads a string attribute into buf; 0, -ENOENT (absent), -EBADMSG (wrong type or too long). */
static int get_string(exr_context_t ctxt, const char *name, char *buf, size_t size)
{
	const char *s = NULL;
	int32_t len = 0;
	exr_result_t rv = exr_attr_get_string(ctxt, 0, name, &len, &s);

	if (rv == EXR_ERR_NO_ATTR_BY_NAME)
		return -ENOENT;
	if (rv != EXR_ERR_SUCCESS || len < 0 || (size_t)len >= size)
		return -EBADMSG;
	memcpy(buf, s, len);
	buf[len] = '\0';
	return 0;
}

static int get_range(exr_context_t ctxt, const char *path, const char *name, float *first,
		     float *last, struct hl_lid_error *err)
{
	exr_attr_v2f_t v;
	exr_result_t rv = exr_attr_get_v2f(ctxt, 0, name, &v);

	if (rv == EXR_ERR_NO_ATTR_BY_NAME)
		return hl_exr_fail(
			err, -EBADMSG, path,
			"attribute '%s' (v2f: first and last sample, degrees) is missing", name);
	if (rv != EXR_ERR_SUCCESS)
		return hl_exr_fail(err, -EBADMSG, path, "attribute '%s' must be a v2f", name);
	*first = v.x;
	*last = v.y;
	return 0;
}

/* Channel i of the list must be "src%04d" with number i + 1 (the list is sorted by name). */
static int check_channels(const exr_attr_chlist_t *cl, const char *path, bool *ret_combined,
			  struct hl_lid_error *err)
{
	const int n = cl->num_channels;

	if (n < 1)
		return hl_exr_fail(err, -EBADMSG, path, "no channels");
	*ret_combined = n == 1 && strcmp(cl->entries[0].name.str, "I") == 0;
	if (n > HL_LID_MAX_SOURCES)
		return hl_exr_fail(err, -EBADMSG, path,
				   "%d channels; at most %d sources are supported", n,
				   HL_LID_MAX_SOURCES);
	for (int i = 0; i < n; i++) {
		const exr_attr_chlist_entry_t *e = &cl->entries[i];
		char want[16];

		snprintf(want, sizeof(want), "src%04d", i + 1);
		if (!*ret_combined && strcmp(e->name.str, want) != 0)
			return hl_exr_fail(
				err, -EBADMSG, path,
				"channel '%s' where '%s' was expected (sources are src0001..src%04d, contiguous)",
				e->name.str, want, n);
		if (e->pixel_type != EXR_PIXEL_HALF && e->pixel_type != EXR_PIXEL_FLOAT)
			return hl_exr_fail(err, -EBADMSG, path,
					   "channel '%s' is UINT; expected HALF or FLOAT",
					   e->name.str);
		if (e->x_sampling != 1 || e->y_sampling != 1)
			return hl_exr_fail(err, -EBADMSG, path,
					   "channel '%s' is subsampled (%d, %d); expected 1, 1",
					   e->name.str, e->x_sampling, e->y_sampling);
	}
	return 0;
}

static int read_header(exr_context_t ctxt, const char *path, struct hl_lid_grid *g,
		       struct hl_lid_error *err)
{
	char s[64];
	int rc;

	rc = get_string(ctxt, "hdlamp:angles", s, sizeof(s));
	if (rc == -ENOENT)
		return hl_exr_fail(err, -EBADMSG, path,
				   "attribute 'hdlamp:angles' (string A or B) is missing");
	if (rc < 0 || (strcmp(s, "A") != 0 && strcmp(s, "B") != 0))
		return hl_exr_fail(err, -EBADMSG, path,
				   "attribute 'hdlamp:angles' must be the string A or B");
	g->angles = s[0] == 'A' ? HL_ANGLES_A : HL_ANGLES_B;

	rc = get_string(ctxt, "hdlamp:unit", s, sizeof(s));
	if (rc == -ENOENT)
		return hl_exr_fail(err, -EBADMSG, path,
				   "attribute 'hdlamp:unit' (string cd) is missing");
	if (rc < 0 || strcmp(s, "cd") != 0)
		return hl_exr_fail(err, -EBADMSG, path,
				   "attribute 'hdlamp:unit' must be the string cd");

	rc = get_range(ctxt, path, "hdlamp:h", &g->h_first_deg, &g->h_last_deg, err);
	if (rc < 0)
		return rc;
	rc = get_range(ctxt, path, "hdlamp:v", &g->v_first_deg, &g->v_last_deg, err);
	if (rc < 0)
		return rc;
	if (hl_lid_grid_check(g) < 0)
		return hl_exr_fail(
			err, -EINVAL, path,
			"inconsistent grid: %d x %d samples, hdlamp:h (%g, %g), hdlamp:v (%g, %g); expected at least 2 x 2 samples, first < last, H within ±180°, V within ±90°",
			g->width, g->height, g->h_first_deg, g->h_last_deg, g->v_first_deg,
			g->v_last_deg);
	return 0;
}

static int read_names(exr_context_t ctxt, const char *path, struct hl_lid *lid,
		      struct hl_lid_error *err)
{
	const int n = hl_lid_n_sources(lid);
	const char *s = NULL;
	int32_t len = 0;
	exr_result_t rv = exr_attr_get_string(ctxt, 0, "hdlamp:sourceNames", &len, &s);
	int k = 0, rc;

	if (rv == EXR_ERR_NO_ATTR_BY_NAME)
		return 0;
	if (rv != EXR_ERR_SUCCESS)
		return hl_exr_fail(err, -EBADMSG, path,
				   "attribute 'hdlamp:sourceNames' must be a string");
	for (int32_t i = 0; i <= len; k++) {
		int32_t j = i;
		char name[256];

		while (j < len && s[j] != '\n')
			j++;
		if (k >= n || j - i >= (int32_t)sizeof(name))
			return hl_exr_fail(
				err, -EBADMSG, path,
				"attribute 'hdlamp:sourceNames' must hold %d names of < 256 bytes, one per line",
				n);
		memcpy(name, s + i, j - i);
		name[j - i] = '\0';
		rc = hl_lid_set_name(lid, k, name);
		if (rc < 0)
			return hl_exr_fail(err, rc, path, "cannot store source names");
		i = j + 1;
	}
	if (k != n)
		return hl_exr_fail(err, -EBADMSG, path,
				   "attribute 'hdlamp:sourceNames' holds %d names; %d sources", k,
				   n);
	return 0;
}

/* One pass over the file's chunks; pass 0 validates and finds boxes, pass 1 copies. */
struct reader {
	exr_context_t ctxt;
	const char *path;
	struct hl_lid *lid;
	int y_min; /* data window origin */
	int lines; /* scanlines per chunk */
	float *scratch;
	struct hl_lid_box *boxes;
	float **packed;
	struct hl_exr_msg *msg;
	struct hl_lid_error *err;
};

static int scan_block(struct reader *r, int k, int row0, int nrows, const float *block)
{
	const struct hl_lid_grid *g = hl_lid_grid(r->lid);
	struct hl_lid_box *b = &r->boxes[k];

	for (int y = 0; y < nrows; y++) {
		for (int x = 0; x < g->width; x++) {
			float s = block[(size_t)y * g->width + x];

			if (!isfinite(s) || s < 0.0f)
				return hl_exr_fail(
					r->err, -EBADMSG, r->path,
					"channel %d, sample at H %.2f°, V %.2f° is %g; expected a finite value >= 0 cd",
					k + 1, hl_lid_grid_h_deg(g, x),
					hl_lid_grid_v_deg(g, row0 + y), s);
			if (s == 0.0f)
				continue;
			if (b->x1 == 0) {
				*b = (struct hl_lid_box){ x, row0 + y, x + 1, row0 + y + 1 };
				continue;
			}
			if (x < b->x0)
				b->x0 = x;
			if (x >= b->x1)
				b->x1 = x + 1;
			if (row0 + y >= b->y1)
				b->y1 = row0 + y + 1;
		}
	}
	return 0;
}

static void copy_block(struct reader *r, int k, int row0, int nrows, const float *block)
{
	const int w = hl_lid_grid(r->lid)->width;
	const struct hl_lid_box *b = &r->boxes[k];
	const int bw = b->x1 - b->x0;

	for (int y = row0; y < row0 + nrows; y++) {
		if (y < b->y0 || y >= b->y1)
			continue;
		memcpy(r->packed[k] + (size_t)(y - b->y0) * bw,
		       block + (size_t)(y - row0) * w + b->x0, sizeof(float) * bw);
	}
}

static int read_pass(struct reader *r, int pass)
{
	const struct hl_lid_grid *g = hl_lid_grid(r->lid);
	const int n = hl_lid_n_sources(r->lid);
	const size_t block = (size_t)r->lines * g->width;
	int batch = (int)(SCRATCH_BYTES / (block * sizeof(float)));
	exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
	bool have_dec = false;
	int rc = 0;

	if (batch < 1)
		batch = 1;
	for (int y = 0; y < g->height && rc == 0; y += r->lines) {
		exr_chunk_info_t cinfo;
		exr_result_t rv = exr_read_scanline_chunk_info(r->ctxt, 0, r->y_min + y, &cinfo);

		if (rv == EXR_ERR_SUCCESS)
			rv = have_dec ? exr_decoding_update(r->ctxt, 0, &cinfo, &dec) :
					exr_decoding_initialize(r->ctxt, 0, &cinfo, &dec);
		if (rv != EXR_ERR_SUCCESS) {
			rc = hl_exr_fail(r->err, -EBADMSG, r->path, "chunk at row %d: %s", y,
					 hl_exr_why(rv, r->msg));
			break;
		}
		have_dec = true;
		for (int c0 = 0; c0 < n && rc == 0; c0 += batch) {
			const int c1 = c0 + batch < n ? c0 + batch : n;

			for (int c = 0; c < dec.channel_count; c++) {
				exr_coding_channel_info_t *ch = &dec.channels[c];

				ch->decode_to_ptr = NULL;
				if (c < c0 || c >= c1)
					continue;
				ch->decode_to_ptr =
					(uint8_t *)(r->scratch + (size_t)(c - c0) * block);
				ch->user_pixel_stride = sizeof(float);
				ch->user_line_stride = sizeof(float) * g->width;
				ch->user_bytes_per_element = sizeof(float);
				ch->user_data_type = EXR_PIXEL_FLOAT;
			}
			rv = exr_decoding_choose_default_routines(r->ctxt, 0, &dec);
			/* the chunk is read and decompressed (all channels) by its first batch; the
			 * others only unpack their channels from the decompressed buffer, which
			 * saves decompressing a chunk of 1024 channels four times */
			if (rv == EXR_ERR_SUCCESS && c0 == 0)
				rv = exr_decoding_run(r->ctxt, 0, &dec);
			else if (rv == EXR_ERR_SUCCESS)
				rv = dec.unpack_and_convert_fn(&dec);
			if (rv != EXR_ERR_SUCCESS) {
				rc = hl_exr_fail(r->err, -EBADMSG, r->path, "chunk at row %d: %s",
						 y, hl_exr_why(rv, r->msg));
				break;
			}
			for (int c = c0; c < c1 && rc == 0; c++) {
				const float *blk = r->scratch + (size_t)(c - c0) * block;

				if (pass == 0)
					rc = scan_block(r, c, y, cinfo.height, blk);
				else
					copy_block(r, c, y, cinfo.height, blk);
			}
		}
	}
	if (have_dec)
		exr_decoding_destroy(r->ctxt, &dec);
	return rc;
}

static int read_data(struct reader *r)
{
	const int n = hl_lid_n_sources(r->lid);
	int rc;

	r->boxes = calloc(n, sizeof(*r->boxes));
	r->packed = calloc(n, sizeof(*r->packed));
	r->scratch = malloc(SCRATCH_BYTES > (size_t)r->lines * hl_lid_grid(r->lid)->width *
						    sizeof(float) ?
				    SCRATCH_BYTES :
				    (size_t)r->lines * hl_lid_grid(r->lid)->width * sizeof(float));
	if (!r->boxes || !r->packed || !r->scratch) {
		rc = -ENOMEM;
		goto out;
	}
	rc = read_pass(r, 0);
	if (rc < 0)
		goto out;
	for (int k = 0; k < n; k++) {
		const struct hl_lid_box *b = &r->boxes[k];

		if (b->x1 == 0)
			continue;
		r->packed[k] = malloc(sizeof(float) * (size_t)(b->x1 - b->x0) * (b->y1 - b->y0));
		if (!r->packed[k]) {
			rc = -ENOMEM;
			goto out;
		}
	}
	rc = read_pass(r, 1);
	if (rc < 0)
		goto out;
	for (int k = 0; k < n; k++) {
		hl_lid_adopt_source(r->lid, k, &r->boxes[k], r->packed[k]);
		r->packed[k] = NULL;
	}
out:
	if (r->packed)
		for (int k = 0; k < n; k++)
			free(r->packed[k]);
	free(r->packed);
	free(r->boxes);
	free(r->scratch);
	return rc;
}

int hl_lid_read(const char *path, struct hl_lid **ret, struct hl_lid_error *err)
{
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	struct hl_exr_msg msg = { .text = "" };
	struct reader r = { .path = path, .msg = &msg, .err = err };
	const exr_attr_chlist_t *cl = NULL;
	struct hl_lid_grid grid = { 0 };
	exr_attr_box2i_t dw;
	exr_storage_t storage;
	exr_result_t rv;
	struct stat st;
	int parts = 0, rc;
	bool combined = false;

	if (stat(path, &st) < 0)
		return hl_exr_fail(err, -errno, path, "%s", strerror(errno));
	if (!S_ISREG(st.st_mode))
		return hl_exr_fail(err, -EBADMSG, path, "not a regular file");

	init.error_handler_fn = hl_exr_keep_message;
	init.user_data = &msg;
	init.flags = EXR_CONTEXT_FLAG_SILENT_HEADER_PARSE;
	rv = exr_start_read(&r.ctxt, path, &init);
	if (rv != EXR_ERR_SUCCESS) {
		rc = hl_exr_fail(err, -EBADMSG, path, "not a readable OpenEXR file (%s)",
				 hl_exr_why(rv, &msg));
		goto err_finish;
	}
	if (exr_get_count(r.ctxt, &parts) != EXR_ERR_SUCCESS || parts != 1) {
		rc = hl_exr_fail(err, -EBADMSG, path, "%d parts; expected one scanline part",
				 parts);
		goto err_finish;
	}
	if (exr_get_storage(r.ctxt, 0, &storage) != EXR_ERR_SUCCESS ||
	    storage != EXR_STORAGE_SCANLINE) {
		rc = hl_exr_fail(err, -EBADMSG, path, "tiled or deep image; expected scanlines");
		goto err_finish;
	}
	if (exr_get_data_window(r.ctxt, 0, &dw) != EXR_ERR_SUCCESS ||
	    exr_get_channels(r.ctxt, 0, &cl) != EXR_ERR_SUCCESS ||
	    exr_get_scanlines_per_chunk(r.ctxt, 0, &r.lines) != EXR_ERR_SUCCESS || r.lines < 1) {
		rc = hl_exr_fail(err, -EBADMSG, path, "incomplete header (%s)",
				 hl_exr_why(EXR_ERR_INVALID_ATTR, &msg));
		goto err_finish;
	}
	grid.width = dw.max.x - dw.min.x + 1;
	grid.height = dw.max.y - dw.min.y + 1;
	r.y_min = dw.min.y;
	rc = check_channels(cl, path, &combined, err);
	if (rc < 0)
		goto err_finish;
	rc = read_header(r.ctxt, path, &grid, err);
	if (rc < 0)
		goto err_finish;
	rc = hl_lid_new(cl->num_channels, &grid, combined, &r.lid);
	if (rc < 0) {
		rc = hl_exr_fail(err, rc, path, "cannot hold %d sources", cl->num_channels);
		goto err_finish;
	}
	rc = read_names(r.ctxt, path, r.lid, err);
	if (rc < 0)
		goto err_free;
	rc = read_data(&r);
	if (rc < 0) {
		if (rc == -ENOMEM)
			hl_exr_fail(err, rc, path, "out of memory");
		goto err_free;
	}
	exr_finish(&r.ctxt);
	*ret = r.lid;
	return 0;

err_free:
	hl_lid_free(r.lid);
err_finish:
	exr_finish(&r.ctxt);
	return rc;
}

/* Writing: FLOAT channels, ZIP; rows of sources whose box misses a chunk point at zeros. */
struct writer {
	exr_context_t ctxt;
	const struct hl_lid *lid;
	const float *dense; /* combined distribution, or NULL for the lid's sources */
	const float *zeros;
	float *scratch; /* n_sources * lines * width */
	int lines;
};

static const float *chunk_rows(struct writer *wr, int k, int y0, int nrows)
{
	const struct hl_lid_grid *g = hl_lid_grid(wr->lid);
	struct hl_lid_box b;
	const float *src;
	float *out;
	int bw;

	if (wr->dense)
		return wr->dense + (size_t)y0 * g->width;
	src = hl_lid_source(wr->lid, k, &b);
	if (!src || b.y1 <= y0 || b.y0 >= y0 + nrows)
		return wr->zeros;
	out = wr->scratch + (size_t)k * wr->lines * g->width;
	bw = b.x1 - b.x0;
	memset(out, 0, sizeof(float) * (size_t)nrows * g->width);
	for (int y = y0; y < y0 + nrows; y++)
		if (y >= b.y0 && y < b.y1)
			memcpy(out + (size_t)(y - y0) * g->width + b.x0,
			       src + (size_t)(y - b.y0) * bw, sizeof(float) * bw);
	return out;
}

static exr_result_t write_chunks(struct writer *wr)
{
	const struct hl_lid_grid *g = hl_lid_grid(wr->lid);
	exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
	bool have_enc = false;
	exr_result_t rv = EXR_ERR_SUCCESS;

	for (int y = 0; y < g->height; y += wr->lines) {
		exr_chunk_info_t cinfo;

		rv = exr_write_scanline_chunk_info(wr->ctxt, 0, y, &cinfo);
		if (rv != EXR_ERR_SUCCESS)
			break;
		rv = have_enc ? exr_encoding_update(wr->ctxt, 0, &cinfo, &enc) :
				exr_encoding_initialize(wr->ctxt, 0, &cinfo, &enc);
		if (rv != EXR_ERR_SUCCESS)
			break;
		for (int c = 0; c < enc.channel_count; c++) {
			exr_coding_channel_info_t *ch = &enc.channels[c];

			ch->encode_from_ptr = (const uint8_t *)chunk_rows(wr, c, y, cinfo.height);
			ch->user_pixel_stride = sizeof(float);
			ch->user_line_stride = sizeof(float) * g->width;
			ch->user_bytes_per_element = sizeof(float);
			ch->user_data_type = EXR_PIXEL_FLOAT;
		}
		if (!have_enc)
			rv = exr_encoding_choose_default_routines(wr->ctxt, 0, &enc);
		have_enc = true;
		if (rv == EXR_ERR_SUCCESS)
			rv = exr_encoding_run(wr->ctxt, 0, &enc);
		if (rv != EXR_ERR_SUCCESS)
			break;
	}
	if (have_enc)
		exr_encoding_destroy(wr->ctxt, &enc);
	return rv;
}

static char *joined_names(const struct hl_lid *lid)
{
	const int n = hl_lid_n_sources(lid);
	size_t len = 0;
	bool any = false;
	char *s;

	for (int k = 0; k < n; k++) {
		const char *name = hl_lid_name(lid, k);

		len += (name ? strlen(name) : 0) + 1;
		any |= name != NULL;
	}
	if (!any)
		return NULL;
	s = malloc(len);
	if (!s)
		return NULL;
	s[0] = '\0';
	for (int k = 0, at = 0; k < n; k++) {
		const char *name = hl_lid_name(lid, k);

		at += sprintf(s + at, "%s%s", k ? "\n" : "", name ? name : "");
	}
	return s;
}

static int write_file(const struct hl_lid *lid, const float *dense, const char *path,
		      struct hl_lid_error *err)
{
	const struct hl_lid_grid *g = hl_lid_grid(lid);
	const int n = hl_lid_n_sources(lid);
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	struct hl_exr_msg msg = { .text = "" };
	struct writer wr = { .lid = lid, .dense = dense };
	exr_attr_v2f_t h = { .x = g->h_first_deg, .y = g->h_last_deg };
	exr_attr_v2f_t v = { .x = g->v_first_deg, .y = g->v_last_deg };
	char *names = NULL;
	exr_result_t rv;
	int part, rc = 0;

	init.error_handler_fn = hl_exr_keep_message;
	init.user_data = &msg;
	hl_exr_write_begin(&msg);
	rv = exr_start_write(&wr.ctxt, path, EXR_INTERMEDIATE_TEMP_FILE, &init);
	if (rv != EXR_ERR_SUCCESS) {
		hl_exr_write_end();
		return hl_exr_fail(err, hl_exr_io_rc(&msg), path, "cannot create (%s)",
				   hl_exr_why(rv, &msg));
	}
	rv = exr_add_part(wr.ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
	if (rv == EXR_ERR_SUCCESS)
		rv = exr_initialize_required_attr_simple(wr.ctxt, part, g->width, g->height,
							 EXR_COMPRESSION_ZIP);
	for (int k = 0; k < n && rv == EXR_ERR_SUCCESS; k++) {
		char name[16];

		snprintf(name, sizeof(name), "src%04d", k + 1);
		rv = exr_add_channel(wr.ctxt, part, hl_lid_is_combined(lid) ? "I" : name,
				     EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
	}
	if (rv == EXR_ERR_SUCCESS)
		rv = exr_attr_set_string(wr.ctxt, part, "hdlamp:angles",
					 g->angles == HL_ANGLES_A ? "A" : "B");
	if (rv == EXR_ERR_SUCCESS)
		rv = exr_attr_set_v2f(wr.ctxt, part, "hdlamp:h", &h);
	if (rv == EXR_ERR_SUCCESS)
		rv = exr_attr_set_v2f(wr.ctxt, part, "hdlamp:v", &v);
	if (rv == EXR_ERR_SUCCESS)
		rv = exr_attr_set_string(wr.ctxt, part, "hdlamp:unit", "cd");
	if (rv == EXR_ERR_SUCCESS && !hl_lid_is_combined(lid)) {
		names = joined_names(lid);
		if (names)
			rv = exr_attr_set_string(wr.ctxt, part, "hdlamp:sourceNames", names);
	}
	if (rv == EXR_ERR_SUCCESS)
		rv = exr_write_header(wr.ctxt);
	if (rv == EXR_ERR_SUCCESS)
		rv = exr_get_scanlines_per_chunk(wr.ctxt, part, &wr.lines);
	if (rv != EXR_ERR_SUCCESS) {
		rc = hl_exr_fail(err, hl_exr_io_rc(&msg), path, "cannot write header (%s)",
				 hl_exr_why(rv, &msg));
		goto out;
	}
	wr.zeros = calloc((size_t)wr.lines * g->width, sizeof(float));
	wr.scratch = dense ? NULL : malloc(sizeof(float) * (size_t)n * wr.lines * g->width);
	if (!wr.zeros || (!dense && !wr.scratch)) {
		rc = hl_exr_fail(err, -ENOMEM, path, "out of memory");
		goto out;
	}
	rv = write_chunks(&wr);
	if (rv != EXR_ERR_SUCCESS)
		rc = hl_exr_fail(err, hl_exr_io_rc(&msg), path, "cannot write pixels (%s)",
				 hl_exr_why(rv, &msg));
out:
	free(names);
	free((void *)wr.zeros);
	free(wr.scratch);
	rv = exr_finish(&wr.ctxt);
	if (rc == 0 && rv != EXR_ERR_SUCCESS)
		rc = hl_exr_fail(err, hl_exr_io_rc(&msg), path, "cannot finish (%s)",
				 hl_exr_why(rv, &msg));
	hl_exr_write_end();
	return rc;
}

int hl_lid_write(const struct hl_lid *lid, const char *path, struct hl_lid_error *err)
{
	return write_file(lid, NULL, path, err);
}

int hl_lid_write_combined(const struct hl_lid_grid *grid, const float *dense, const char *path,
			  struct hl_lid_error *err)
{
	struct hl_lid *lid;
	int rc = hl_lid_new(1, grid, true, &lid);

	if (rc < 0)
		return hl_exr_fail(err, rc, path, "invalid grid");
	rc = write_file(lid, dense, path, err);
	hl_lid_free(lid);
	return rc;
}
