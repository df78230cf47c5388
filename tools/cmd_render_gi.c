/* SPDX-License-Identifier: MIT */
/*
 * hdlamp render --gi sensor: the indirect light by sensor-based lighting on the CPU or GLES
 * sensors, and the files it writes beside the still. Apart from cmd_render.c because it is a
 * pipeline of its own (choosing and timing the sensor backend, five output files).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/egl.h"
#include "render/frame_exr.h"
#include "render/gi.h"
#include "render/gl_sensor.h"
#include "render/plot.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "render/scene_mesh.h"
#include "render/view.h"
#include "tools/cmd_render.h"

static void gi_progress(void *userdata, size_t done, size_t estimated)
{
	(void)userdata;
	fprintf(stderr, "\rhdlamp render: gi: sensors %zu / ~%zu", done, estimated);
}

/* BASE-suffix from --out BASE.png. */
static void derived(const char *out, const char *suffix, char *buf, size_t size)
{
	snprintf(buf, size, "%.*s-%s", (int)(strlen(out) - 4), out, suffix);
}

static int write_exr_luminance(const char *path, const struct hl_gbuffer *gb, const float *lux,
			       struct hl_frame_exr_info *info, float *rgba)
{
	struct hl_lid_error err;
	int rc;

	hl_view_hdr(gb, lux, rgba);
	rc = hl_frame_exr_write_hdr(path, gb->width, gb->height, rgba, info, &err);
	if (rc < 0)
		fprintf(stderr, "hdlamp render: %s\n", err.msg);
	return rc;
}

static int write_png(const char *path, const uint8_t *rgb, int w, int h)
{
	const int rc = hl_png_write_rgb(path, rgb, w, h);

	if (rc < 0)
		fprintf(stderr, "hdlamp render: '%s': %s\n", path, strerror(-rc));
	return rc;
}

/* The GLES sensors over the scene's mesh; NULL with the reason in log when they cannot run. */
static struct hl_gl_sensor *gles_sensors(const struct options *o, const struct hl_egl *egl,
					 const struct hl_scene *scene,
					 const struct hl_sensor_scene *field, char *log,
					 size_t log_size)
{
	struct hl_gl_sensor_config gcfg;
	struct hl_scene_mesh *mesh;
	struct hl_gl_sensor *gs = NULL;
	int rc = hl_scene_mesh_new(scene, &mesh);

	if (rc < 0) {
		snprintf(log, log_size, "no scene mesh: %s", strerror(-rc));
		return NULL;
	}
	hl_gl_sensor_config_for(egl, o->gi_cfg.sensor_size, o->gi_cfg.aa_samples,
				o->sensor_batch ? o->sensor_batch : GLES_SENSOR_BATCH, &gcfg);
	rc = hl_gl_sensor_new(egl, mesh, field->n_lamps, field->lamps, &gcfg, &gs, log, log_size);
	hl_scene_mesh_free(mesh);
	for (int k = 0; rc == 0 && k < field->n_lamps; k++)
		rc = hl_gl_sensor_upload(gs, k, field->dense[k]);
	if (rc < 0) {
		if (gs)
			snprintf(log, log_size, "cannot upload the distributions");
		hl_gl_sensor_free(gs);
		return NULL;
	}
	return gs;
}

/*
 * --gi sensor: the indirect illuminance of the G-buffer's points by sensor-based lighting, then
 * the total (direct + indirect) as the display view and the files beside it.
 */
int run_gi(struct options *o, const struct hl_egl *egl, const struct hl_scene *scene,
	   const struct hl_camera *cam, const struct hl_gbuffer *gb, struct hl_renderer *r,
	   const float *direct, int n_lamps)
{
	struct hl_gi_sensors cpu = { .fn = hl_sensor_scene_radiance };
	struct hl_gi_sensors gles = { .batch = hl_gl_sensor_gi_batch };
	const struct hl_gi_sensors *sensors = &cpu;
	struct hl_gi_config cpu_cfg, gles_cfg;
	const struct hl_gi_config *cfg = &cpu_cfg;
	struct hl_gl_sensor *gs = NULL;
	enum hl_backend backend = o->sensor_backend;
	char log[1024] = "", how[96];
	const size_t n = (size_t)gb->width * gb->height;
	struct hl_capsule thin[HL_SCENE_MAX_THIN];
	struct hl_sensor_scene field = { .scene = scene, .n_lamps = n_lamps };
	struct hl_frame_exr_info info = { .camera = cam, .n_lamps = n_lamps };
	struct hl_gi_stats st;
	struct hl_view_lux_opts diff_opts;
	char path[4096], gi_desc[160];
	float *ind = malloc(sizeof(float) * n), *total = malloc(sizeof(float) * n);
	float *rgba = malloc(sizeof(float) * 4 * n);
	uint8_t *rgb = malloc(3 * n);
	int rc = -ENOMEM;

	if (!ind || !total || !rgba || !rgb) {
		fprintf(stderr, "hdlamp render: out of memory\n");
		goto out;
	}
	for (int k = 0; k < n_lamps; k++) {
		field.lamps[k] = (struct hl_headlight_lamp){ o->poses[k], *hl_renderer_grid(r, k) };
		field.dense[k] = hl_renderer_distribution(r, k);
		if (!field.dense[k]) {
			rc = -EIO;
			goto out;
		}
	}
	o->gi_cfg.thin = thin;
	o->gi_cfg.n_thin = hl_scene_thin_objects(scene, thin, HL_SCENE_MAX_THIN);
	o->gi_cfg.progress = gi_progress;
	cpu.field = &field;
	cpu_cfg = o->gi_cfg;
	cpu_cfg.batch = o->sensor_batch ? o->sensor_batch : GI_DEFAULTS.batch;
	gles_cfg = o->gi_cfg;
	gles_cfg.batch = o->sensor_batch ? o->sensor_batch : GLES_SENSOR_BATCH;
	if (backend != HL_BACKEND_CPU) {
		gs = gles_sensors(o, egl, scene, &field, log, sizeof(log));
		if (!gs && backend == HL_BACKEND_GLES) {
			fprintf(stderr,
				"hdlamp render: --sensor-backend gles: no GLES sensors: %s\n", log);
			rc = -ENOTSUP;
			goto out;
		}
		if (!gs) {
			fprintf(stderr, "hdlamp render: gi: no GLES sensors (%s): sensors on cpu\n",
				log);
			backend = HL_BACKEND_CPU;
		}
		gles.userdata = gs;
	}
	if (backend == HL_BACKEND_AUTO) {
		struct hl_gi_config tc = cpu_cfg, tg = gles_cfg;
		double ms_cpu = 0.0, ms_gles = 0.0;

		tc.progress = tg.progress = NULL;
		rc = hl_gi_time_batch(&tc, &cpu, gb, &ms_cpu);
		if (rc == 0)
			rc = hl_gi_time_batch(&tg, &gles, gb, &ms_gles);
		if (rc < 0) {
			fprintf(stderr, "hdlamp render: gi: timing the sensors failed: %s\n",
				strerror(-rc));
			goto out;
		}
		backend = ms_gles < ms_cpu ? HL_BACKEND_GLES : HL_BACKEND_CPU;
		fprintf(stderr,
			"hdlamp render: gi: one batch: cpu %.3f ms per sensor (%d threads, batch %d), "
			"gles %.3f ms per sensor (batch %d): sensors on %s\n",
			ms_cpu, cpu_cfg.threads, cpu_cfg.batch, ms_gles, gles_cfg.batch,
			hl_backend_name(backend));
	}
	if (backend == HL_BACKEND_GLES) {
		struct hl_gl_sensor_config gcfg;

		sensors = &gles;
		cfg = &gles_cfg;
		hl_gl_sensor_config_for(egl, cfg->sensor_size, cfg->aa_samples, cfg->batch, &gcfg);
		snprintf(how, sizeof(how), "gles, batch %d, %d samples x %dx%d sub-texels",
			 cfg->batch, gcfg.msaa, gcfg.supersample, gcfg.supersample);
	} else {
		snprintf(how, sizeof(how), "cpu, %d threads", cfg->threads);
	}
	rc = hl_gi_run_sensors(cfg, sensors, gb, ind, &st);
	fputc('\n', stderr);
	if (rc < 0) {
		fprintf(stderr, "hdlamp render: gi failed: %s\n", strerror(-rc));
		goto out;
	}
	fprintf(stderr,
		"hdlamp render: gi: %zu sensors for %zu surface pixels (%.1fx fewer than one per "
		"pixel), %d passes, %zu batches, %dx%d hemicube (%d texels, aa %d), %.3f ms per "
		"sensor (%s), sensors %.0f ms, total %.0f ms\n",
		st.sensors, st.surface_pixels,
		st.sensors ? (double)st.surface_pixels / st.sensors : 0.0, st.levels, st.batches,
		cfg->sensor_size, cfg->sensor_size, 3 * cfg->sensor_size * cfg->sensor_size,
		cfg->aa_samples, st.sensors ? st.sensor_ms / st.sensors : 0.0, how, st.sensor_ms,
		st.total_ms);
	for (size_t i = 0; i < n; i++)
		total[i] = direct[i] + ind[i];

	memcpy(info.lamps, o->poses, sizeof(info.lamps));
	snprintf(gi_desc, sizeof(gi_desc),
		 "sensor size=%d tile=%d dradiance=%g aa=%d sensors=%zu backend=%s",
		 o->gi_cfg.sensor_size, o->gi_cfg.tile, o->gi_cfg.dradiance, o->gi_cfg.aa_samples,
		 st.sensors, hl_backend_name(backend));
	info.n_meta = 2;
	info.meta_names[0] = "hdlamp:gi";
	info.meta_values[0] = gi_desc;
	info.meta_names[1] = "hdlamp:component";
	{
		static const char *const comp[] = { "direct", "indirect", "total" };
		const float *src[] = { direct, ind, total };

		for (int c = 0; c < 3; c++) {
			char name[32];

			snprintf(name, sizeof(name), "%s.exr", comp[c]);
			derived(o->out, name, path, sizeof(path));
			info.meta_values[1] = comp[c];
			rc = write_exr_luminance(path, gb, src[c], &info, rgba);
			if (rc < 0)
				goto out;
		}
	}
	hl_view_display(gb, direct, o->exposure_ev, rgb);
	derived(o->out, "direct.png", path, sizeof(path));
	if ((rc = write_png(path, rgb, gb->width, gb->height)) < 0)
		goto out;
	/* The difference total - direct is the indirect illuminance: false colour, lux. */
	hl_view_lux_defaults(&diff_opts);
	diff_opts.min_lx = 0.001;
	diff_opts.max_lx = 10.0;
	diff_opts.n_iso = 0;
	for (size_t i = 0; i < n; i++)
		rgba[i] = total[i] - direct[i];
	hl_view_lux(gb, rgba, &diff_opts, rgb);
	derived(o->out, "diff.png", path, sizeof(path));
	if ((rc = write_png(path, rgb, gb->width, gb->height)) < 0)
		goto out;
	hl_view_display(gb, total, o->exposure_ev, rgb);
	rc = write_png(o->out, rgb, gb->width, gb->height);
out:
	hl_gl_sensor_free(gs);
	free(ind);
	free(total);
	free(rgba);
	free(rgb);
	return rc;
}
