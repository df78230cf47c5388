/* SPDX-License-Identifier: MIT */
/* EXR frames: read back with OpenEXRCore, pixels, channels and camera/lamp attributes. */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include <cmocka.h>
#include <openexr.h>

#include "render/frame_exr.h"

#define W 20
#define H 10

static const char *tmp_path(const char *name)
{
	static char path[512];
	const char *dir = getenv("HL_TEST_TMPDIR");

	snprintf(path, sizeof(path), "%s/%s", dir ? dir : "/tmp", name);
	return path;
}

static void frame_exr_lux_reads_back_with_camera(void **state)
{
	const struct hl_camera cam = { .pos_m = { -1.8, 0.37, 1.2 },
				       .dir = { 1, 0, -0.03 },
				       .up = { 0, 0, 1 },
				       .fov_y_deg = 36,
				       .width = W,
				       .height = H };
	struct hl_frame_exr_info info = { .camera = &cam, .n_lamps = 2 };
	const char *path = tmp_path("frame_lux.exr");
	float lux[W * H], back[W * H], m[16];
	exr_context_t ctxt;
	exr_attr_m44f_t a;
	exr_attr_v3f_t pos;
	const exr_attr_chlist_t *cl;
	exr_chunk_info_t ci;
	exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
	int lines;

	(void)state;
	hl_lamp_pose_default(0, &info.lamps[0]);
	hl_lamp_pose_default(1, &info.lamps[1]);
	for (int i = 0; i < W * H; i++)
		lux[i] = 0.25f * i;
	assert_int_equal(hl_frame_exr_write_lux(path, W, H, lux, &info, NULL), 0);

	assert_int_equal(exr_start_read(&ctxt, path, NULL), EXR_ERR_SUCCESS);
	assert_int_equal(exr_get_channels(ctxt, 0, &cl), EXR_ERR_SUCCESS);
	assert_int_equal(cl->num_channels, 1);
	assert_string_equal(cl->entries[0].name.str, "E");
	assert_int_equal(cl->entries[0].pixel_type, EXR_PIXEL_FLOAT);
	assert_int_equal(exr_attr_get_m44f(ctxt, 0, "worldToCamera", &a), EXR_ERR_SUCCESS);
	hl_camera_world_to_camera(&cam, m);
	assert_memory_equal(a.m, m, sizeof(m));
	assert_int_equal(exr_attr_get_m44f(ctxt, 0, "worldToNDC", &a), EXR_ERR_SUCCESS);
	hl_camera_world_to_ndc(&cam, m);
	assert_memory_equal(a.m, m, sizeof(m));
	assert_int_equal(exr_attr_get_v3f(ctxt, 0, "hdlamp:rightPosition", &pos), EXR_ERR_SUCCESS);
	assert_float_equal(pos.y, -0.7f, 1e-7);

	/* Pixels, chunk by chunk. */
	assert_int_equal(exr_get_scanlines_per_chunk(ctxt, 0, &lines), EXR_ERR_SUCCESS);
	for (int y = 0; y < H; y += lines) {
		assert_int_equal(exr_read_scanline_chunk_info(ctxt, 0, y, &ci), EXR_ERR_SUCCESS);
		if (y == 0)
			assert_int_equal(exr_decoding_initialize(ctxt, 0, &ci, &dec),
					 EXR_ERR_SUCCESS);
		else
			assert_int_equal(exr_decoding_update(ctxt, 0, &ci, &dec), EXR_ERR_SUCCESS);
		dec.channels[0].decode_to_ptr = (uint8_t *)(back + y * W);
		dec.channels[0].user_pixel_stride = 4;
		dec.channels[0].user_line_stride = 4 * W;
		dec.channels[0].user_bytes_per_element = 4;
		dec.channels[0].user_data_type = EXR_PIXEL_FLOAT;
		if (y == 0)
			assert_int_equal(exr_decoding_choose_default_routines(ctxt, 0, &dec),
					 EXR_ERR_SUCCESS);
		assert_int_equal(exr_decoding_run(ctxt, 0, &dec), EXR_ERR_SUCCESS);
	}
	exr_decoding_destroy(ctxt, &dec);
	exr_finish(&ctxt);
	assert_memory_equal(back, lux, sizeof(lux));
}

static void frame_exr_hdr_is_half_rgba(void **state)
{
	const struct hl_camera cam = {
		.dir = { 1, 0, 0 }, .up = { 0, 0, 1 }, .fov_y_deg = 30, .width = W, .height = H
	};
	struct hl_frame_exr_info info = { .camera = &cam, .n_lamps = 1 };
	const char *path = tmp_path("frame_hdr.exr");
	float rgba[4 * W * H];
	exr_context_t ctxt;
	const exr_attr_chlist_t *cl;
	const char *unit = NULL;
	int32_t len = 0;
	exr_attr_v3f_t pos;

	(void)state;
	hl_lamp_pose_default(0, &info.lamps[0]);
	for (int i = 0; i < 4 * W * H; i++)
		rgba[i] = 0.5f;
	assert_int_equal(hl_frame_exr_write_hdr(path, W, H, rgba, &info, NULL), 0);
	assert_int_equal(exr_start_read(&ctxt, path, NULL), EXR_ERR_SUCCESS);
	assert_int_equal(exr_get_channels(ctxt, 0, &cl), EXR_ERR_SUCCESS);
	assert_int_equal(cl->num_channels, 4);
	for (int c = 0; c < 4; c++)
		assert_int_equal(cl->entries[c].pixel_type, EXR_PIXEL_HALF);
	assert_int_equal(exr_attr_get_string(ctxt, 0, "hdlamp:unit", &len, &unit), EXR_ERR_SUCCESS);
	assert_int_equal(strncmp(unit, "cd/m2", len), 0);
	assert_int_equal(exr_attr_get_v3f(ctxt, 0, "hdlamp:rightPosition", &pos),
			 EXR_ERR_NO_ATTR_BY_NAME);
	exr_finish(&ctxt);
	{
		struct hl_lid_error err;

		/* the open's errno, not a bare -EIO (a capture tells a full disk apart) */
		assert_int_equal(hl_frame_exr_write_hdr("/nonexistent/dir/x.exr", W, H, rgba, &info,
							&err),
				 -ENOENT);
		assert_non_null(strstr(err.msg, "/nonexistent/dir/x.exr"));
		assert_non_null(strstr(err.msg, strerror(ENOENT)));
	}
}

struct limited {
	const float *rgba;
	const struct hl_frame_exr_info *info;
	struct hl_lid_error err;
	int rc;
};

static void *write_limited(void *arg)
{
	struct limited *w = arg;

	w->rc = hl_frame_exr_write_hdr(tmp_path("frame_limited.exr"), W, H, w->rgba, w->info,
				       &w->err);
	return NULL;
}

/*
 * A write that fails in the header (RLIMIT_FSIZE below the header's size: EFBIG) returns with
 * the errno and the file. OpenEXRCore reports it with the write context locked; the error
 * handler used to ask for the user data, which waits on that lock: the writer never returned
 * (a capture on a full disk hung hdlampd's capture for good).
 */
static void frame_exr_header_write_error_returns_errno(void **state)
{
	static float rgba[W * H * 4];
	struct hl_frame_exr_info info = { .n_lamps = 1 };
	struct limited w = { .rgba = rgba, .info = &info, .rc = 1 };
	struct rlimit old, small;
	struct timespec until;
	pthread_t t;
	int joined;

	(void)state;
	signal(SIGXFSZ, SIG_IGN); /* EFBIG rather than the signal */
	assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
	small = old;
	small.rlim_cur = 64; /* bytes: less than any EXR header */
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
	assert_int_equal(pthread_create(&t, NULL, write_limited, &w), 0);
	clock_gettime(CLOCK_REALTIME, &until);
	until.tv_sec += 30; /* a hang, not a speed */
	joined = pthread_timedjoin_np(t, NULL, &until);
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
	assert_int_equal(joined, 0);
	assert_int_equal(w.rc, -EFBIG);
	assert_non_null(strstr(w.err.msg, "frame_limited.exr"));
	assert_non_null(strstr(w.err.msg, strerror(EFBIG)));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(frame_exr_lux_reads_back_with_camera),
		cmocka_unit_test(frame_exr_hdr_is_half_rgba),
		cmocka_unit_test(frame_exr_header_write_error_returns_errno),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
