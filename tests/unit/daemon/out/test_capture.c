/* SPDX-License-Identifier: MIT */
/*
 * Captures: the files of a still and of a moving scene, the metadata attributes' exact text in
 * the EXR headers, each lamp's distribution read back (float noise below zero written as 0), a
 * second capture of the same frame beside the first, a dead daemon's temporary directory
 * replaced, and the refusals: a capture directory that cannot be made (-ENOTDIR) and a frame
 * captured HL_CAPTURE_MAX_SAME_FRAME times (-EEXIST), neither leaving anything behind.
 */
#include <dirent.h>
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "daemon/out/capture.h"
#include "testutil.h"
#include "dir_util.h"

#define W 8
#define H 4
#define N_SOURCES 3

static const struct hl_lid_grid grid = { 6, 3, HL_ANGLES_A, -10.0f, 10.0f, -5.0f, 5.0f };
static const struct hl_camera cam = { .dir = { 1, 0, 0 },
				      .up = { 0, 0, 1 },
				      .fov_y_deg = 30,
				      .width = W,
				      .height = H };

struct fixture {
	char dir[512];
	struct hl_frame f;
	float lux[W * H];
	float dist[2][6 * 3];
	uint8_t dims[2][N_SOURCES];
	struct hl_gbuffer *gb;
	struct hl_capture_scene sc;
};

static int setup(void **state)
{
	struct fixture *fx = calloc(1, sizeof(*fx));

	if (!fx)
		return -1;
	test_path(fx->dir, sizeof(fx->dir), "captures");
	remove_dir(fx->dir);
	fx->f.hdr.seq = 7;
	fx->f.hdr.cycle_seq[0] = 11;
	fx->f.hdr.cycle_seq[1] = 12;
	fx->f.hdr.counter[0] = 3;
	fx->f.hdr.counter[1] = 4;
	fx->f.hdr.flags = HL_FRAME_STALE(0) | HL_FRAME_STALE(1);
	fx->f.hdr.t_cycle_rx_ns = -1;
	fx->f.hdr.t_cycle_done_ns = 123456789012345LL;
	fx->f.hdr.t_render_done_ns = 9;
	fx->f.hdr.width = W;
	fx->f.hdr.height = H;
	fx->f.lux = fx->lux;
	for (int i = 0; i < W * H; i++)
		fx->lux[i] = 0.5f * (float)i;
	for (int l = 0; l < 2; l++) {
		for (int i = 0; i < 6 * 3; i++)
			fx->dist[l][i] = 100.0f * (float)(i + l);
		fx->dist[l][0] = -1e-5f; /* incremental combining's noise where all is off */
		fx->f.dist[l] = fx->dist[l];
		fx->f.dims[l] = fx->dims[l];
	}
	fx->dims[0][0] = 0, fx->dims[0][1] = 63, fx->dims[0][2] = 5;
	fx->dims[1][0] = 1, fx->dims[1][1] = 2, fx->dims[1][2] = 3;
	fx->f.n_sources = N_SOURCES;
	if (hl_gbuffer_new(W, H, &fx->gb) < 0)
		return -1;
	fx->sc = (struct hl_capture_scene){ .gb = fx->gb,
					    .cam = &cam,
					    .n_lamps = 2,
					    .lamp_names = { "left", "right" },
					    .grids = { &grid, &grid } };
	*state = fx;
	return 0;
}

static int teardown(void **state)
{
	struct fixture *fx = *state;

	remove_dir(fx->dir);
	hl_gbuffer_free(fx->gb);
	free(fx);
	return 0;
}

/* The string attribute name of the EXR file path: its value as written ("" when absent). */
static void exr_attribute(const char *path, const char *name, char *out, size_t size)
{
	static char data[1 << 20];
	FILE *f = fopen(path, "rb");
	size_t n;
	const size_t len = strlen(name);

	assert_non_null(f);
	n = fread(data, 1, sizeof(data), f);
	fclose(f);
	out[0] = '\0';
	for (size_t i = 0; i + len + 12 < n; i++) {
		int32_t vlen;

		/* name NUL "string" NUL int32 size, value */
		if (memcmp(data + i, name, len) != 0 || data[i + len] != '\0' ||
		    memcmp(data + i + len + 1, "string", 7) != 0)
			continue;
		memcpy(&vlen, data + i + len + 8, 4);
		assert_true(vlen >= 0 && (size_t)vlen < size);
		memcpy(out, data + i + len + 12, (size_t)vlen);
		out[vlen] = '\0';
		return;
	}
}

static void expect_attribute(const char *path, const char *name, const char *value)
{
	char got[256];

	exr_attribute(path, name, got, sizeof(got));
	if (strcmp(got, value) != 0)
		fail_msg("%s: %s = '%s', expected '%s'", path, name, got, value);
}

static void capture_writes_every_file_with_its_metadata(void **state)
{
	struct fixture *fx = *state;
	char path[1024], err[512] = "", want[1024], files[256], file[1200];
	(void)state;

	assert_int_equal(hl_capture_write(fx->dir, &fx->f, &fx->sc, path, sizeof(path), err,
					  sizeof(err)),
			 0);
	snprintf(want, sizeof(want), "%s/frame-00000007", fx->dir);
	assert_string_equal(path, want);
	assert_string_equal(err, "");
	list_dir(fx->dir, files, sizeof(files));
	assert_string_equal(files, "frame-00000007"); /* no temporary left */
	list_dir(path, files, sizeof(files));
	assert_string_equal(files, "hdr.exr left.lid.exr lux.exr right.lid.exr");
	for (int k = 0; k < 2; k++) {
		snprintf(file, sizeof(file), "%s/%s", path, k ? "hdr.exr" : "lux.exr");
		expect_attribute(file, "hdlamp:frameSeq", "7");
		expect_attribute(file, "hdlamp:cycleSeq", "11,12");
		expect_attribute(file, "hdlamp:counter", "3,4");
		expect_attribute(file, "hdlamp:flags", "0x5");
		expect_attribute(file, "hdlamp:tCycleRxNs", "-1");
		expect_attribute(file, "hdlamp:tCycleDoneNs", "123456789012345");
		expect_attribute(file, "hdlamp:tRenderDoneNs", "9");
		expect_attribute(file, "hdlamp:dims.left", "0,63,5");
		expect_attribute(file, "hdlamp:dims.right", "1,2,3");
		expect_attribute(file, "hdlamp:verdict", ""); /* no verdicts configured */
	}
	/* each lamp's distribution as a combined LID, the noise below zero written as 0 */
	for (int l = 0; l < 2; l++) {
		struct hl_lid *lid;
		struct hl_lid_error lerr;
		float back[6 * 3];

		snprintf(file, sizeof(file), "%s/%s.lid.exr", path, l ? "right" : "left");
		if (hl_lid_read(file, &lid, &lerr) < 0)
			fail_msg("%s", lerr.msg);
		assert_true(hl_lid_is_combined(lid));
		assert_true(hl_lid_grid_equal(hl_lid_grid(lid), &grid));
		hl_lid_source_dense(lid, 0, back);
		assert_true(back[0] == 0.0f);
		for (int i = 1; i < 6 * 3; i++)
			assert_true(back[i] == fx->dist[l][i]);
		hl_lid_free(lid);
	}
}

static void capture_of_a_moving_scene_has_no_hdr_and_the_same_frame_goes_beside(void **state)
{
	struct fixture *fx = *state;
	struct hl_capture_scene moving = fx->sc;
	char path[1024], err[512], want[1024], files[512];

	remove_dir(fx->dir);
	moving.gb = NULL;
	assert_int_equal(hl_capture_write(fx->dir, &fx->f, &moving, path, sizeof(path), err,
					  sizeof(err)),
			 0);
	list_dir(path, files, sizeof(files));
	assert_string_equal(files, "left.lid.exr lux.exr right.lid.exr");
	for (int k = 2; k <= 3; k++) {
		assert_int_equal(hl_capture_write(fx->dir, &fx->f, &moving, path, sizeof(path), err,
						  sizeof(err)),
				 0);
		snprintf(want, sizeof(want), "%s/frame-00000007-%d", fx->dir, k);
		assert_string_equal(path, want);
	}
	list_dir(fx->dir, files, sizeof(files));
	assert_string_equal(files, "frame-00000007 frame-00000007-2 frame-00000007-3");
	/* one lamp only: only its file */
	remove_dir(fx->dir);
	moving.n_lamps = 1;
	assert_int_equal(hl_capture_write(fx->dir, &fx->f, &moving, path, sizeof(path), err,
					  sizeof(err)),
			 0);
	list_dir(path, files, sizeof(files));
	assert_string_equal(files, "left.lid.exr lux.exr");
}

static void capture_replaces_a_dead_daemons_temporary(void **state)
{
	struct fixture *fx = *state;
	char tmp[1024], junk[1200], path[1024], err[512], files[256];
	FILE *f;

	remove_dir(fx->dir);
	assert_int_equal(mkdir(fx->dir, 0755), 0);
	snprintf(tmp, sizeof(tmp), "%s/.tmp-frame-00000007-%d", fx->dir, (int)getpid());
	assert_int_equal(mkdir(tmp, 0755), 0);
	snprintf(junk, sizeof(junk), "%s/lux.exr", tmp);
	f = fopen(junk, "w");
	assert_non_null(f);
	fputs("half written", f);
	fclose(f);
	assert_int_equal(hl_capture_write(fx->dir, &fx->f, &fx->sc, path, sizeof(path), err,
					  sizeof(err)),
			 0);
	list_dir(fx->dir, files, sizeof(files));
	assert_string_equal(files, "frame-00000007");
	assert_int_equal(access(junk, F_OK), -1); /* gone with its directory */
	assert_int_equal(errno, ENOENT);
}

static void capture_refusals_leave_nothing_behind(void **state)
{
	struct fixture *fx = *state;
	char file_dir[1024], path[1024] = "untouched", err[1024], want[1200], sub[1100];
	char files[256];
	FILE *f;

	/* a capture directory under a regular file */
	remove_dir(fx->dir);
	assert_int_equal(mkdir(fx->dir, 0755), 0);
	snprintf(file_dir, sizeof(file_dir), "%s/plain", fx->dir);
	f = fopen(file_dir, "w");
	assert_non_null(f);
	fclose(f);
	strcat(file_dir, "/caps");
	assert_int_equal(hl_capture_write(file_dir, &fx->f, &fx->sc, path, sizeof(path), err,
					  sizeof(err)),
			 -ENOTDIR);
	snprintf(want, sizeof(want), "capture.dir '%s': cannot create: Not a directory", file_dir);
	assert_string_equal(err, want);
	assert_string_equal(path, "untouched");
	*strrchr(file_dir, '/') = '\0';
	unlink(file_dir);
	remove_dir(fx->dir);

	/* frame 9 captured HL_CAPTURE_MAX_SAME_FRAME times already */
	assert_int_equal(mkdir(fx->dir, 0755), 0);
	for (int k = 1; k <= HL_CAPTURE_MAX_SAME_FRAME; k++) {
		if (k == 1)
			snprintf(sub, sizeof(sub), "%s/frame-00000009", fx->dir);
		else
			snprintf(sub, sizeof(sub), "%s/frame-00000009-%d", fx->dir, k);
		assert_int_equal(mkdir(sub, 0755), 0);
	}
	fx->f.hdr.seq = 9;
	assert_int_equal(hl_capture_write(fx->dir, &fx->f, &fx->sc, path, sizeof(path), err,
					  sizeof(err)),
			 -EEXIST);
	fx->f.hdr.seq = 7;
	snprintf(want, sizeof(want), "'%s': 1000 captures of frame 9 exist already", fx->dir);
	assert_string_equal(err, want);
	assert_string_equal(path, "untouched");
	/* no temporary directory left: only the 1000 captures */
	{
		DIR *d = opendir(fx->dir);
		struct dirent *e;
		int n = 0;

		assert_non_null(d);
		while ((e = readdir(d)))
			if (strncmp(e->d_name, ".tmp", 4) == 0)
				fail_msg("left behind: %s", e->d_name);
			else if (e->d_name[0] != '.')
				n++;
		closedir(d);
		assert_int_equal(n, HL_CAPTURE_MAX_SAME_FRAME);
	}
	/* the same directory still takes other frames */
	assert_int_equal(hl_capture_write(fx->dir, &fx->f, &fx->sc, path, sizeof(path), err,
					  sizeof(err)),
			 0);
	snprintf(want, sizeof(want), "%s/frame-00000007", fx->dir);
	assert_string_equal(path, want);
	list_dir(path, files, sizeof(files));
	assert_string_equal(files, "hdr.exr left.lid.exr lux.exr right.lid.exr");
	remove_dir(fx->dir);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(capture_writes_every_file_with_its_metadata),
		cmocka_unit_test(
			capture_of_a_moving_scene_has_no_hdr_and_the_same_frame_goes_beside),
		cmocka_unit_test(capture_replaces_a_dead_daemons_temporary),
		cmocka_unit_test(capture_refusals_leave_nothing_behind),
	};

	return cmocka_run_group_tests(tests, setup, teardown);
}
