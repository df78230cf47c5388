/* SPDX-License-Identifier: MIT */
/* LID files: round trips (FLOAT and HALF input) and every validation fault. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include <openexr.h>

#include "lamp/lid.h"
#include "testutil.h"

/* A hand-made EXR file, written with OpenEXRCore directly, to produce every fault. */
struct fake_file {
	int n;
	const char *channels[4];
	exr_pixel_type_t type;
	int w, h;
	const char *angles; /* NULL: attribute absent */
	const char *unit;
	bool no_h, no_v;
	float hr[2], vr[2];
	const char *source_names;
	int bad_channel; /* 0-based channel holding bad_value at pixel (1, 1), -1 for none */
	float bad_value;
};

static const struct fake_file good = {
	.n = 2,
	.channels = { "src0001", "src0002" },
	.type = EXR_PIXEL_FLOAT,
	.w = 6,
	.h = 4,
	.angles = "A",
	.unit = "cd",
	.hr = { -1.0f, 1.5f },
	.vr = { -0.6f, 0.6f },
	.bad_channel = -1,
};

/* Value of channel c at (x, y): exact in half precision. */
static float fake_value(int c, int x, int y)
{
	if ((x + y + c) % 3 == 0)
		return 0.0f;
	return (float)(c + 1) * 100.0f + (float)x * 4.0f + (float)y * 0.25f;
}

static uint16_t to_half(float f)
{
	/* Exact for the normal values above (few mantissa bits), and for 0 / NaN / inf. */
	uint32_t b;
	memcpy(&b, &f, 4);
	uint32_t sign = (b >> 16) & 0x8000u, exp = (b >> 23) & 0xffu, man = b & 0x7fffffu;

	if (exp == 0xffu)
		return (uint16_t)(sign | 0x7c00u | (man ? 0x200u : 0));
	if (exp == 0)
		return (uint16_t)sign;
	return (uint16_t)(sign | ((exp - 127 + 15) << 10) | (man >> 13));
}

static void write_fake(const char *path, const struct fake_file *f)
{
	exr_context_t ctxt;
	exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
	exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
	const size_t bpe = f->type == EXR_PIXEL_HALF ? 2 : 4;
	uint8_t *data = calloc((size_t)f->n * f->w * f->h, bpe);
	int part, lines;

	assert_non_null(data);
	for (int c = 0; c < f->n; c++)
		for (int y = 0; y < f->h; y++)
			for (int x = 0; x < f->w; x++) {
				float v = fake_value(c, x, y);
				size_t i = ((size_t)c * f->h + y) * f->w + x;

				if (c == f->bad_channel && x == 1 && y == 1)
					v = f->bad_value;
				if (f->type == EXR_PIXEL_HALF) {
					uint16_t hv = to_half(v);
					memcpy(data + i * 2, &hv, 2);
				} else if (f->type == EXR_PIXEL_UINT) {
					uint32_t u = (uint32_t)v;
					memcpy(data + i * 4, &u, 4);
				} else {
					memcpy(data + i * 4, &v, 4);
				}
			}
	assert_int_equal(exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init), 0);
	assert_int_equal(exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part), 0);
	assert_int_equal(exr_initialize_required_attr_simple(ctxt, part, f->w, f->h,
							     EXR_COMPRESSION_ZIP),
			 0);
	for (int c = 0; c < f->n; c++)
		assert_int_equal(exr_add_channel(ctxt, part, f->channels[c], f->type,
						 EXR_PERCEPTUALLY_LINEAR, 1, 1),
				 0);
	if (f->angles)
		assert_int_equal(exr_attr_set_string(ctxt, part, "hdlamp:angles", f->angles), 0);
	if (f->unit)
		assert_int_equal(exr_attr_set_string(ctxt, part, "hdlamp:unit", f->unit), 0);
	if (!f->no_h) {
		exr_attr_v2f_t h = { .x = f->hr[0], .y = f->hr[1] };
		assert_int_equal(exr_attr_set_v2f(ctxt, part, "hdlamp:h", &h), 0);
	}
	if (!f->no_v) {
		exr_attr_v2f_t v = { .x = f->vr[0], .y = f->vr[1] };
		assert_int_equal(exr_attr_set_v2f(ctxt, part, "hdlamp:v", &v), 0);
	}
	if (f->source_names)
		assert_int_equal(
			exr_attr_set_string(ctxt, part, "hdlamp:sourceNames", f->source_names), 0);
	assert_int_equal(exr_write_header(ctxt), 0);
	assert_int_equal(exr_get_scanlines_per_chunk(ctxt, part, &lines), 0);
	for (int y = 0; y < f->h; y += lines) {
		exr_chunk_info_t cinfo;

		assert_int_equal(exr_write_scanline_chunk_info(ctxt, part, y, &cinfo), 0);
		if (y == 0)
			assert_int_equal(exr_encoding_initialize(ctxt, part, &cinfo, &enc), 0);
		else
			assert_int_equal(exr_encoding_update(ctxt, part, &cinfo, &enc), 0);
		for (int c = 0; c < enc.channel_count; c++) {
			enc.channels[c].encode_from_ptr =
				data + (((size_t)c * f->h + y) * f->w) * bpe;
			enc.channels[c].user_pixel_stride = (int32_t)bpe;
			enc.channels[c].user_line_stride = (int32_t)(bpe * f->w);
			enc.channels[c].user_bytes_per_element = (int16_t)bpe;
			enc.channels[c].user_data_type = (uint16_t)f->type;
		}
		if (y == 0)
			assert_int_equal(exr_encoding_choose_default_routines(ctxt, part, &enc), 0);
		assert_int_equal(exr_encoding_run(ctxt, part, &enc), 0);
	}
	exr_encoding_destroy(ctxt, &enc);
	assert_int_equal(exr_finish(&ctxt), 0);
	free(data);
}

static void check_fake_values(const struct hl_lid *lid, const struct fake_file *f)
{
	float *dense = malloc(sizeof(float) * f->w * f->h);

	assert_non_null(dense);
	for (int c = 0; c < f->n; c++) {
		hl_lid_source_dense(lid, c, dense);
		for (int y = 0; y < f->h; y++)
			for (int x = 0; x < f->w; x++)
				assert_true(dense[y * f->w + x] == fake_value(c, x, y));
	}
	free(dense);
}

static void lid_exr_reads_float_channels(void **state)
{
	char path[512];
	struct hl_lid *lid;
	struct hl_lid_error err;
	(void)state;

	write_fake(test_path(path, sizeof(path), "float.lid.exr"), &good);
	assert_int_equal(hl_lid_read(path, &lid, &err), 0);
	assert_int_equal(hl_lid_n_sources(lid), 2);
	assert_int_equal(hl_lid_grid(lid)->width, 6);
	assert_int_equal(hl_lid_grid(lid)->height, 4);
	assert_int_equal(hl_lid_grid(lid)->angles, HL_ANGLES_A);
	assert_true(hl_lid_grid(lid)->h_first_deg == -1.0f && hl_lid_grid(lid)->h_last_deg == 1.5f);
	assert_true(hl_lid_grid(lid)->v_first_deg == -0.6f && hl_lid_grid(lid)->v_last_deg == 0.6f);
	assert_false(hl_lid_is_combined(lid));
	check_fake_values(lid, &good);
	hl_lid_free(lid);
	unlink(path);
}

static void lid_exr_reads_half_channels(void **state)
{
	struct fake_file f = good;
	char path[512];
	struct hl_lid *lid;
	struct hl_lid_error err;
	(void)state;

	f.type = EXR_PIXEL_HALF;
	f.angles = "B";
	write_fake(test_path(path, sizeof(path), "half.lid.exr"), &f);
	assert_int_equal(hl_lid_read(path, &lid, &err), 0);
	assert_int_equal(hl_lid_grid(lid)->angles, HL_ANGLES_B);
	check_fake_values(lid, &f);
	hl_lid_free(lid);
	unlink(path);
}

static void lid_exr_box_is_nonzero_extent(void **state)
{
	struct hl_lid_grid g = { 20, 10, HL_ANGLES_A, -2.0f, 1.8f, -1.0f, 0.8f };
	float dense[200] = { 0 };
	struct hl_lid *lid, *back;
	struct hl_lid_box b;
	struct hl_lid_error err;
	const float *s;
	char path[512];
	(void)state;

	assert_int_equal(hl_lid_new(3, &g, false, &lid), 0);
	dense[3 * 20 + 5] = 7.0f;
	dense[6 * 20 + 11] = 2.5f;
	assert_int_equal(hl_lid_set_source(lid, 1, dense), 0);
	assert_int_equal(hl_lid_set_name(lid, 1, "spot"), 0);
	s = hl_lid_source(lid, 1, &b);
	assert_int_equal(b.x0, 5);
	assert_int_equal(b.x1, 12);
	assert_int_equal(b.y0, 3);
	assert_int_equal(b.y1, 7);
	assert_true(s[0] == 7.0f && s[3 * 7 + 6] == 2.5f);
	assert_true(hl_lid_peak_cd(lid, 1) == 7.0f);
	assert_null(hl_lid_source(lid, 0, &b));
	assert_int_equal(b.x1 - b.x0, 0);

	/* Round trip through a file: boxes, values, names and grid come back exactly. */
	assert_int_equal(hl_lid_write(lid, test_path(path, sizeof(path), "box.lid.exr"), &err), 0);
	assert_int_equal(hl_lid_read(path, &back, &err), 0);
	assert_int_equal(hl_lid_n_sources(back), 3);
	s = hl_lid_source(back, 1, &b);
	assert_int_equal(b.x0, 5);
	assert_int_equal(b.x1, 12);
	assert_int_equal(b.y0, 3);
	assert_int_equal(b.y1, 7);
	assert_true(s[0] == 7.0f && s[3 * 7 + 6] == 2.5f);
	assert_string_equal(hl_lid_name(back, 1), "spot");
	assert_string_equal(hl_lid_name(back, 0), "");
	assert_null(hl_lid_source(back, 2, &b));
	assert_memory_equal(hl_lid_grid(back), &g, sizeof(g));
	hl_lid_free(back);
	hl_lid_free(lid);
	unlink(path);
}

/*
 * More channels than the reader decodes in one batch (16 MB of 16-line blocks: 128 channels of
 * 2048 samples): the later batches of a chunk unpack from the chunk decompressed by the first.
 * Every source's box and values come back exactly.
 */
static void lid_exr_many_channels_round_trip(void **state)
{
	enum { W = 2048, H = 20, N = 300 };
	struct hl_lid_grid g = { W, H, HL_ANGLES_A, -60.0f, 62.0f, -1.0f, 0.9f };
	static float dense[W * H];
	struct hl_lid *lid, *back;
	struct hl_lid_error err;
	char path[512];
	(void)state;

	g.h_last_deg = g.h_first_deg + (W - 1) * 0.05f;
	g.v_last_deg = g.v_first_deg + (H - 1) * 0.1f;
	assert_int_equal(hl_lid_new(N, &g, false, &lid), 0);
	for (int k = 0; k < N; k++) {
		const int x = (k * 37) % (W - 3), y = k % (H - 4);

		memset(dense, 0, sizeof(dense));
		dense[y * W + x] = (float)(k + 1);
		dense[(y + 3) * W + x + 2] = 0.5f * (float)(k + 1);
		assert_int_equal(hl_lid_set_source(lid, k, dense), 0);
	}
	assert_int_equal(hl_lid_write(lid, test_path(path, sizeof(path), "many.lid.exr"), &err), 0);
	assert_int_equal(hl_lid_read(path, &back, &err), 0);
	assert_int_equal(hl_lid_n_sources(back), N);
	for (int k = 0; k < N; k++) {
		const int x = (k * 37) % (W - 3), y = k % (H - 4);
		struct hl_lid_box b;
		const float *s = hl_lid_source(back, k, &b);

		assert_non_null(s);
		assert_int_equal(b.x0, x);
		assert_int_equal(b.x1, x + 3);
		assert_int_equal(b.y0, y);
		assert_int_equal(b.y1, y + 4);
		assert_true(s[0] == (float)(k + 1));
		assert_true(s[3 * 3 + 2] == 0.5f * (float)(k + 1));
		assert_true(s[1] == 0.0f && s[3 * 3 + 1] == 0.0f);
	}
	hl_lid_free(back);
	hl_lid_free(lid);
	unlink(path);
}

static void lid_exr_combined_round_trip(void **state)
{
	struct hl_lid_grid g = { 8, 5, HL_ANGLES_B, -4.0f, 3.0f, -2.0f, 2.0f };
	float dense[40];
	struct hl_lid *back;
	struct hl_lid_error err;
	char path[512];
	float out[40];
	(void)state;

	for (int i = 0; i < 40; i++)
		dense[i] = (float)(i * i) * 1.5f;
	assert_int_equal(
		hl_lid_write_combined(&g, dense, test_path(path, sizeof(path), "L.exr"), &err), 0);
	assert_int_equal(hl_lid_read(path, &back, &err), 0);
	assert_true(hl_lid_is_combined(back));
	assert_int_equal(hl_lid_n_sources(back), 1);
	hl_lid_source_dense(back, 0, out);
	assert_memory_equal(out, dense, sizeof(dense));
	hl_lid_free(back);
	unlink(path);
}

/* Each fault: the exact -errno, and a message naming the file and the fault. */
static void expect_fault(const struct fake_file *f, const char *name, int want, const char *needle)
{
	char path[512];
	struct hl_lid *lid = NULL;
	struct hl_lid_error err = { "" };

	write_fake(test_path(path, sizeof(path), name), f);
	assert_int_equal(hl_lid_read(path, &lid, &err), want);
	assert_null(lid);
	assert_non_null(strstr(err.msg, path));
	if (!strstr(err.msg, needle))
		fail_msg("message '%s' lacks '%s'", err.msg, needle);
	unlink(path);
}

static void lid_exr_rejects_missing_and_foreign_files(void **state)
{
	char path[512];
	struct hl_lid *lid = NULL;
	struct hl_lid_error err;
	FILE *f;
	(void)state;

	test_path(path, sizeof(path), "absent.lid.exr");
	assert_int_equal(hl_lid_read(path, &lid, &err), -ENOENT);
	assert_non_null(strstr(err.msg, path));
	assert_non_null(strstr(err.msg, "No such file"));

	f = fopen(test_path(path, sizeof(path), "text.lid.exr"), "w");
	assert_non_null(f);
	fputs("this is not an OpenEXR file\n", f);
	fclose(f);
	assert_int_equal(hl_lid_read(path, &lid, &err), -EBADMSG);
	assert_non_null(strstr(err.msg, path));
	assert_non_null(strstr(err.msg, "not a readable OpenEXR file"));
	unlink(path);
	assert_null(lid);
}

static void lid_exr_rejects_channel_faults(void **state)
{
	struct fake_file f = good;
	(void)state;

	f.channels[1] = "src0003";
	expect_fault(&f, "gap.exr", -EBADMSG, "channel 'src0003' where 'src0002' was expected");
	f = good;
	f.channels[0] = "R";
	f.channels[1] = "G";
	expect_fault(&f, "rgb.exr", -EBADMSG, "channel 'G' where 'src0001' was expected");
	f = good;
	f.type = EXR_PIXEL_UINT;
	expect_fault(&f, "uint.exr", -EBADMSG, "channel 'src0001' is UINT; expected HALF or FLOAT");
}

static void lid_exr_rejects_attribute_faults(void **state)
{
	struct fake_file f = good;
	(void)state;

	f.angles = NULL;
	expect_fault(&f, "noangles.exr", -EBADMSG, "'hdlamp:angles' (string A or B) is missing");
	f = good;
	f.angles = "C";
	expect_fault(&f, "anglesC.exr", -EBADMSG, "'hdlamp:angles' must be the string A or B");
	f = good;
	f.unit = NULL;
	expect_fault(&f, "nounit.exr", -EBADMSG, "'hdlamp:unit' (string cd) is missing");
	f = good;
	f.unit = "lm";
	expect_fault(&f, "lumen.exr", -EBADMSG, "'hdlamp:unit' must be the string cd");
	f = good;
	f.no_h = true;
	expect_fault(&f, "noh.exr", -EBADMSG,
		     "'hdlamp:h' (v2f: first and last sample, degrees) is missing");
	f = good;
	f.no_v = true;
	expect_fault(&f, "nov.exr", -EBADMSG,
		     "'hdlamp:v' (v2f: first and last sample, degrees) is missing");
	f = good;
	f.source_names = "only one";
	expect_fault(&f, "names.exr", -EBADMSG, "'hdlamp:sourceNames' holds 1 names; 2 sources");
}

static void lid_exr_rejects_inconsistent_grid(void **state)
{
	struct fake_file f = good;
	(void)state;

	f.hr[0] = 2.0f; /* first after last */
	expect_fault(&f, "hrev.exr", -EINVAL,
		     "inconsistent grid: 6 x 4 samples, hdlamp:h (2, 1.5)");
	f = good;
	f.vr[1] = 95.0f;
	expect_fault(&f, "vbig.exr", -EINVAL, "inconsistent grid");
	f = good;
	f.h = 1;
	expect_fault(&f, "oneline.exr", -EINVAL, "inconsistent grid: 6 x 1 samples");
}

static void lid_exr_rejects_bad_values(void **state)
{
	struct fake_file f = good;
	(void)state;

	f.bad_channel = 1;
	f.bad_value = NAN;
	/* pixel (1, 1): H = -1 + 1 * 0.5, V = 0.6 - 1 * 0.4 */
	expect_fault(
		&f, "nan.exr", -EBADMSG,
		"channel 2, sample at H -0.50°, V 0.20° is nan; expected a finite value >= 0 cd");
	f.bad_value = -3.0f;
	expect_fault(&f, "neg.exr", -EBADMSG, "channel 2, sample at H -0.50°, V 0.20° is -3;");
	f.type = EXR_PIXEL_HALF;
	f.bad_value = INFINITY;
	expect_fault(&f, "inf.exr", -EBADMSG, "is inf;");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(lid_exr_reads_float_channels),
		cmocka_unit_test(lid_exr_reads_half_channels),
		cmocka_unit_test(lid_exr_box_is_nonzero_extent),
		cmocka_unit_test(lid_exr_many_channels_round_trip),
		cmocka_unit_test(lid_exr_combined_round_trip),
		cmocka_unit_test(lid_exr_rejects_missing_and_foreign_files),
		cmocka_unit_test(lid_exr_rejects_channel_faults),
		cmocka_unit_test(lid_exr_rejects_attribute_faults),
		cmocka_unit_test(lid_exr_rejects_inconsistent_grid),
		cmocka_unit_test(lid_exr_rejects_bad_values),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
