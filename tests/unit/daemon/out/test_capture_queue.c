/* SPDX-License-Identifier: MIT */
/*
 * The capture queue against a real frame pool and real files: captures of one frame get their
 * own directories, queued captures hold no pool frame, a request beyond the slots is refused,
 * a failed capture leaves nothing.
 */
#include <dirent.h>
#include <errno.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "daemon/out/capture_queue.h"
#include "render/scene.h"
#include "testutil.h"
#include "dir_util.h"

#define W 16
#define H 8

struct fixture {
	struct hl_frame_pool *pool;
	struct hl_gbuffer *gb;
	struct hl_camera cam;
	struct hl_lid_grid grid;
	struct hl_capture_queue *q;
	char dir[512];
};

/* Publishes a frame with some light in it. */
static void publish(struct fixture *fx)
{
	struct hl_frame *f = hl_frame_pool_acquire(fx->pool);

	assert_non_null(f);
	for (int i = 0; i < W * H; i++)
		f->lux[i] = (float)i;
	for (int l = 0; l < 2; l++) {
		for (int i = 0; i < fx->grid.width * fx->grid.height; i++)
			f->dist[l][i] = 100.0f * (float)(i + l);
		memset(f->dims[l], 63, 3);
	}
	hl_frame_pool_publish(fx->pool, f);
}

static struct fixture *start(int pool_frames, int slots, bool run)
{
	const struct hl_frame_shape shape = { .width = W,
					      .height = H,
					      .format = HL_PIXEL_RGB8,
					      .n_lamps = 2,
					      .n_sources = 3,
					      .dist_width = 8,
					      .dist_height = 4 };
	struct fixture *fx = calloc(1, sizeof(*fx));
	struct hl_capture_queue_config cfg = { .slots = slots, .log = stderr };

	assert_non_null(fx);
	fx->grid = (struct hl_lid_grid){ 8, 4, HL_ANGLES_A, -10.0f, 10.0f, -5.0f, 5.0f };
	fx->cam = (struct hl_camera){
		.dir = { 1, 0, 0 }, .up = { 0, 0, 1 }, .fov_y_deg = 30, .width = W, .height = H
	};
	test_path(fx->dir, sizeof(fx->dir), "captures");
	remove_dir(fx->dir);
	assert_int_equal(hl_frame_pool_new(pool_frames, &shape, &fx->pool), 0);
	assert_int_equal(hl_gbuffer_new(W, H, &fx->gb), 0);
	cfg.dir = fx->dir;
	cfg.pool = fx->pool;
	cfg.scene = (struct hl_capture_scene){ .gb = fx->gb,
					       .cam = &fx->cam,
					       .n_lamps = 2,
					       .lamp_names = { "left", "right" },
					       .grids = { &fx->grid, &fx->grid } };
	assert_int_equal(hl_capture_queue_new(&cfg, &fx->q), 0);
	if (run)
		assert_int_equal(hl_capture_queue_start(fx->q), 0);
	publish(fx);
	return fx;
}

static void stop(struct fixture *fx)
{
	hl_capture_queue_free(fx->q);
	hl_gbuffer_free(fx->gb);
	hl_frame_pool_free(fx->pool);
	remove_dir(fx->dir);
	free(fx);
}

static void check_counts(struct fixture *fx, uint64_t written, uint64_t failed, uint64_t refused)
{
	struct hl_capture_queue_counts c;

	hl_capture_queue_counts(fx->q, &c);
	assert_int_equal(c.written, written);
	assert_int_equal(c.failed, failed);
	assert_int_equal(c.refused, refused);
}

static void check_capture(const char *dir, const char *name)
{
	char path[1024], files[256];

	snprintf(path, sizeof(path), "%s/%s", dir, name);
	list_dir(path, files, sizeof(files));
	assert_string_equal(files, "hdr.exr left.lid.exr lux.exr right.lid.exr");
}

/* Two captures of the same frame: frame-00000001 and frame-00000001-2, neither overwritten. */
static void capture_queue_same_frame_two_directories(void **state)
{
	struct fixture *fx = start(4, 2, true);
	char msg[4200], want[1100], names[256];

	(void)state;
	assert_int_equal(hl_capture_queue_submit(fx->q, 30000, msg, sizeof(msg)), 0);
	snprintf(want, sizeof(want), "%s/frame-00000001", fx->dir);
	assert_string_equal(msg, want);
	assert_int_equal(hl_capture_queue_submit(fx->q, 30000, msg, sizeof(msg)), 0);
	snprintf(want, sizeof(want), "%s/frame-00000001-2", fx->dir);
	assert_string_equal(msg, want);
	list_dir(fx->dir, names, sizeof(names));
	assert_string_equal(names, "frame-00000001 frame-00000001-2");
	check_capture(fx->dir, "frame-00000001");
	check_capture(fx->dir, "frame-00000001-2");
	check_counts(fx, 2, 0, 0);
	stop(fx);
}

/*
 * With the writer not started, two requests fill the two slots and a third is refused; the
 * queued captures hold no pool frame: in a pool of two, the renderer gets the frame they were
 * taken of as soon as a newer one is published.
 */
static void capture_queue_refuses_beyond_its_slots_and_holds_no_frame(void **state)
{
	struct fixture *fx = start(2, 2, false);
	char msg[4200], names[256];
	struct hl_frame *f;

	(void)state;
	assert_int_equal(hl_capture_queue_submit(fx->q, 0, msg, sizeof(msg)), 0);
	assert_int_equal(hl_capture_queue_submit(fx->q, 0, msg, sizeof(msg)), 0);
	assert_int_equal(hl_capture_queue_submit(fx->q, 0, msg, sizeof(msg)), -EBUSY);
	assert_string_equal(msg, "2 captures are queued (capture.queue); try again");
	check_counts(fx, 0, 0, 1);
	publish(fx); /* frame 2: frame 1 is no longer the newest */
	f = hl_frame_pool_acquire(fx->pool);
	assert_non_null(f); /* frame 1's memory: nobody holds it */
	hl_frame_pool_discard(fx->pool, f);
	assert_int_equal(hl_capture_queue_start(fx->q), 0);
	hl_capture_queue_stop(fx->q); /* writes what is queued */
	check_counts(fx, 2, 0, 1);
	list_dir(fx->dir, names, sizeof(names));
	assert_string_equal(names, "frame-00000001 frame-00000001-2");
	assert_int_equal(hl_capture_queue_submit(fx->q, 0, msg, sizeof(msg)), -ESHUTDOWN);
	stop(fx);
}

/*
 * A capture that cannot be written (RLIMIT_FSIZE below an EXR header: EFBIG) says which file
 * and why, leaves nothing in the capture directory (no frame-*, no .tmp-*) and is counted; the
 * next one, with the limit lifted, is complete.
 */
static void capture_queue_failed_capture_leaves_nothing(void **state)
{
	struct fixture *fx = start(4, 2, true);
	char msg[4200], want[1100], names[256];
	struct rlimit old, small;

	(void)state;
	signal(SIGXFSZ, SIG_IGN);
	assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
	small = old;
	small.rlim_cur = 64; /* bytes */
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &small), 0);
	assert_int_equal(hl_capture_queue_submit(fx->q, 30000, msg, sizeof(msg)), -EFBIG);
	assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
	snprintf(want, sizeof(want), "'%s/.tmp-frame-00000001-%d/hdr.exr'", fx->dir, (int)getpid());
	assert_non_null(strstr(msg, want));
	assert_non_null(strstr(msg, strerror(EFBIG)));
	list_dir(fx->dir, names, sizeof(names));
	assert_string_equal(names, "");
	check_counts(fx, 0, 1, 0);
	assert_int_equal(hl_capture_queue_submit(fx->q, 30000, msg, sizeof(msg)), 0);
	check_capture(fx->dir, "frame-00000001");
	check_counts(fx, 1, 1, 0);
	stop(fx);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(capture_queue_same_frame_two_directories),
		cmocka_unit_test(capture_queue_refuses_beyond_its_slots_and_holds_no_frame),
		cmocka_unit_test(capture_queue_failed_capture_leaves_nothing),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
