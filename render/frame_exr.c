/* SPDX-License-Identifier: MIT */
#include "render/frame_exr.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

#include "lamp/exr_error.h"
#include "render/pixel.h"

/* What a context's user data points to: the last message, and the memory sink if any. */
struct exr_msg {
	struct hl_exr_msg m; /* first: hl_exr_keep_message writes here */
	struct mem_sink *mem;
};

struct mem_sink {
	uint8_t *data;
	size_t size, cap;
};

struct channel {
	const char *name;
	exr_pixel_type_t type;
	const void *data; /* interleaved: stride bytes between pixels */
	int stride;
};

static exr_result_t set_attributes(exr_context_t ctxt, int part,
				   const struct hl_frame_exr_info *info, const char *unit)
{
	static const char *const side[2] = { "left", "right" };
	exr_attr_m44f_t m;
	exr_result_t rv;
	float f[16];

	rv = exr_attr_set_string(ctxt, part, "hdlamp:unit", unit);
	if (!info)
		return rv;
	if (info->camera && rv == EXR_ERR_SUCCESS) {
		hl_camera_world_to_camera(info->camera, f);
		memcpy(m.m, f, sizeof(m.m));
		rv = exr_attr_set_m44f(ctxt, part, "worldToCamera", &m);
		hl_camera_world_to_ndc(info->camera, f);
		memcpy(m.m, f, sizeof(m.m));
		if (rv == EXR_ERR_SUCCESS)
			rv = exr_attr_set_m44f(ctxt, part, "worldToNDC", &m);
	}
	for (int k = 0; k < info->n_lamps && rv == EXR_ERR_SUCCESS; k++) {
		const struct hl_lamp_pose *p = &info->lamps[k];
		exr_attr_v3f_t pos = { .x = (float)p->pos_m[0],
				       .y = (float)p->pos_m[1],
				       .z = (float)p->pos_m[2] };
		exr_attr_v2f_t aim = { .x = (float)p->yaw_deg, .y = (float)p->pitch_deg };
		char name[64];

		snprintf(name, sizeof(name), "hdlamp:%sPosition", side[k]);
		rv = exr_attr_set_v3f(ctxt, part, name, &pos);
		snprintf(name, sizeof(name), "hdlamp:%sAim", side[k]);
		if (rv == EXR_ERR_SUCCESS)
			rv = exr_attr_set_v2f(ctxt, part, name, &aim);
	}
	for (int k = 0; k < info->n_meta && k < HL_FRAME_EXR_MAX_META && rv == EXR_ERR_SUCCESS; k++)
		rv = exr_attr_set_string(ctxt, part, info->meta_names[k], info->meta_values[k]);
	return rv;
}

static exr_result_t write_chunks(exr_context_t ctxt, int width, int height,
				 const struct channel *ch, int n_ch)
{
	exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
	bool have_enc = false;
	exr_result_t rv = EXR_ERR_SUCCESS;
	int lines = 1;

	rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines);
	for (int y = 0; rv == EXR_ERR_SUCCESS && y < height; y += lines) {
		exr_chunk_info_t cinfo;

		rv = exr_write_scanline_chunk_info(ctxt, 0, y, &cinfo);
		if (rv != EXR_ERR_SUCCESS)
			break;
		rv = have_enc ? exr_encoding_update(ctxt, 0, &cinfo, &enc) :
				exr_encoding_initialize(ctxt, 0, &cinfo, &enc);
		if (rv != EXR_ERR_SUCCESS)
			break;
		/* The library sorts channels by name; match them back by name. */
		for (int c = 0; c < enc.channel_count; c++) {
			exr_coding_channel_info_t *e = &enc.channels[c];

			for (int j = 0; j < n_ch; j++) {
				const int bytes = ch[j].type == EXR_PIXEL_HALF ? 2 : 4;

				if (strcmp(e->channel_name, ch[j].name) != 0)
					continue;
				e->encode_from_ptr = (const uint8_t *)ch[j].data +
						     (size_t)y * width * ch[j].stride;
				e->user_pixel_stride = ch[j].stride;
				e->user_line_stride = ch[j].stride * width;
				e->user_bytes_per_element = bytes;
				e->user_data_type = ch[j].type;
			}
		}
		if (!have_enc)
			rv = exr_encoding_choose_default_routines(ctxt, 0, &enc);
		have_enc = true;
		if (rv == EXR_ERR_SUCCESS)
			rv = exr_encoding_run(ctxt, 0, &enc);
	}
	if (have_enc)
		exr_encoding_destroy(ctxt, &enc);
	(void)height;
	return rv;
}

/* The write stream of a memory sink: the library writes at offsets, mostly appending. */
static int64_t mem_write(exr_const_context_t ctxt, void *userdata, const void *buffer, uint64_t sz,
			 uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
	struct mem_sink *m = ((struct exr_msg *)userdata)->mem;
	const size_t end = (size_t)offset + (size_t)sz;

	if (end > m->cap) {
		size_t cap = m->cap ? m->cap : 65536;
		uint8_t *d;

		while (cap < end)
			cap *= 2;
		d = realloc(m->data, cap);
		if (!d) {
			error_cb(ctxt, EXR_ERR_OUT_OF_MEMORY, "out of memory");
			return -1;
		}
		m->data = d;
		m->cap = cap;
	}
	if (offset > m->size)
		memset(m->data + m->size, 0, (size_t)offset - m->size);
	memcpy(m->data + offset, buffer, (size_t)sz);
	if (end > m->size)
		m->size = end;
	return (int64_t)sz;
}

/* To path, or into mem when it is not NULL (path then only names it in messages). */
static int write_file(const char *path, int width, int height, const struct channel *ch, int n_ch,
		      const struct hl_frame_exr_info *info, const char *unit,
		      struct hl_lid_error *err, struct mem_sink *mem)
{
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	struct exr_msg msg = { .m = { .text = "" }, .mem = mem };
	exr_context_t ctxt;
	exr_result_t rv;
	int part, rc = 0;

	if (width < 1 || height < 1 || (info && (info->n_lamps < 0 || info->n_lamps > 2)))
		return hl_exr_fail(err, -EINVAL, path, "bad image size or lamp count");
	init.error_handler_fn = hl_exr_keep_message;
	init.user_data = &msg;
	if (mem)
		init.write_fn = mem_write;
	hl_exr_write_begin(&msg.m);
	rv = exr_start_write(&ctxt, path,
			     mem ? EXR_WRITE_FILE_DIRECTLY : EXR_INTERMEDIATE_TEMP_FILE, &init);
	if (rv != EXR_ERR_SUCCESS) {
		hl_exr_write_end();
		return hl_exr_fail(err, hl_exr_io_rc(&msg.m), path, "cannot create (%s)",
				   hl_exr_why(rv, &msg.m));
	}
	rv = exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
	if (rv == EXR_ERR_SUCCESS)
		rv = exr_initialize_required_attr_simple(ctxt, part, width, height,
							 EXR_COMPRESSION_ZIP);
	for (int c = 0; c < n_ch && rv == EXR_ERR_SUCCESS; c++)
		rv = exr_add_channel(ctxt, part, ch[c].name, ch[c].type, EXR_PERCEPTUALLY_LINEAR, 1,
				     1);
	if (rv == EXR_ERR_SUCCESS)
		rv = set_attributes(ctxt, part, info, unit);
	if (rv == EXR_ERR_SUCCESS)
		rv = exr_write_header(ctxt);
	if (rv == EXR_ERR_SUCCESS)
		rv = write_chunks(ctxt, width, height, ch, n_ch);
	if (rv != EXR_ERR_SUCCESS)
		rc = hl_exr_fail(err, hl_exr_io_rc(&msg.m), path, "cannot write (%s)",
				 hl_exr_why(rv, &msg.m));
	rv = exr_finish(&ctxt);
	if (rc == 0 && rv != EXR_ERR_SUCCESS)
		rc = hl_exr_fail(err, hl_exr_io_rc(&msg.m), path, "cannot finish (%s)",
				 hl_exr_why(rv, &msg.m));
	hl_exr_write_end();
	return rc;
}

int hl_frame_exr_write_hdr(const char *path, int width, int height, const float *rgba,
			   const struct hl_frame_exr_info *info, struct hl_lid_error *err)
{
	const size_t n = (size_t)width * height * 4;
	uint16_t *half = malloc(sizeof(uint16_t) * (n ? n : 1));
	struct channel ch[4];
	static const char *const names[4] = { "R", "G", "B", "A" };
	int rc;

	if (!half)
		return hl_exr_fail(err, -ENOMEM, path, "out of memory");
	for (size_t i = 0; i < n; i++)
		half[i] = hl_pixel_half_from_float(rgba[i]);
	for (int c = 0; c < 4; c++)
		ch[c] = (struct channel){ names[c], EXR_PIXEL_HALF, half + c, 8 };
	rc = write_file(path, width, height, ch, 4, info, "cd/m2", err, NULL);
	free(half);
	return rc;
}

int hl_frame_exr_write_lux(const char *path, int width, int height, const float *lux,
			   const struct hl_frame_exr_info *info, struct hl_lid_error *err)
{
	const struct channel ch = { "E", EXR_PIXEL_FLOAT, lux, 4 };

	return write_file(path, width, height, &ch, 1, info, "lx", err, NULL);
}

int hl_frame_exr_encode_lux(int width, int height, const float *lux,
			    const struct hl_frame_exr_info *info, uint8_t **ret_data,
			    size_t *ret_size, struct hl_lid_error *err)
{
	const struct channel ch = { "E", EXR_PIXEL_FLOAT, lux, 4 };
	struct mem_sink mem = { 0 };
	int rc;

	rc = write_file("(memory)", width, height, &ch, 1, info, "lx", err, &mem);
	if (rc < 0) {
		free(mem.data);
		return rc;
	}
	*ret_data = mem.data;
	*ret_size = mem.size;
	return 0;
}
