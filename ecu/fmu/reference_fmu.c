/* SPDX-License-Identifier: MIT */
/*
 * The reference virtual ECU as an FMI 2.0 co-simulation FMU (docs/ecu.md, "The ECU as an FMU"):
 * the shared object binaries/linux64/hdlamp_ecu.so of the FMU `hdlamp ecu --fmu` writes. It
 * reads resources/ecu.json (written by tools/ecu_fmu_export.c: the ECU's options, the input
 * database, each lamp's LID, mount and beams), builds the input map, the named inputs and
 * outputs (ecu/io.h) and the lighting functions (ecu/lighting.h), and runs one ECU cycle per
 * fmi2DoStep.
 *
 * Value references: the inputs of ecu/io.h are 0..n_in-1, the outputs n_in..n_in+n_out-1.
 * fmi2DoStep(t, h) applies the inputs set before it and runs the cycle at t + h: the step's end
 * is the cycle's instant, so after the call the outputs belong to t + h as FMI's outputs do.
 *
 * Only the fmi2* functions are exported (-fvisibility=hidden, HL_FMI2_EXPORT). Every failure is
 * reported through the importer's logger; nothing else is printed.
 */
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "can/inputs.h"
#include "dbc/database.h"
#include "ecu/fmu/fmi2_export.h"
#include "ecu/fmu/reference_fmu.h"
#include "ecu/io.h"
#include "ecu/lighting.h"
#include "lamp/lid.h"
#include "lamp/model.h"

#define GUID_MAX 64
#define MSG_MAX 1024

enum state { INSTANTIATED, INITIALIZING, STEPPING, TERMINATED };

struct instance {
	fmi2CallbackFunctions cb;
	long steps, step_error, step_crash; /* the FMU's own faults (ecu.json), 0: none */
	volatile int *null_page; /* NULL: what step-crash writes through */
	char *name;
	bool logging;
	enum state state;
	char dir[4096]; /* the resources directory */
	struct hl_dbc *db;
	struct hl_inputs_map *map;
	int n_lamps;
	char *lamp_names[HL_ECU_MAX_LAMPS];
	struct hl_lid *lids[HL_ECU_MAX_LAMPS];
	float *beams[HL_ECU_MAX_LAMPS]; /* low then high, n_sources each */
	struct hl_ecu_lamp lamps[HL_ECU_MAX_LAMPS];
	struct hl_ecu_config cfg;
	struct hl_ecu *e;
	struct hl_ecu_io *io;
	struct hl_ecu_io_model model;
	int n_in, n_out;
	double *in, *out;
	double last_time_s;
};

/* The logger's message is a format string: '%' doubled, no arguments. */
static void log_msg(const struct instance *c, fmi2Status status, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
static void log_msg(const struct instance *c, fmi2Status status, const char *fmt, ...)
{
	char msg[MSG_MAX], esc[2 * MSG_MAX];
	size_t j = 0;
	va_list ap;

	if (!c->cb.logger || (status == fmi2OK && !c->logging))
		return;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	for (size_t i = 0; msg[i] && j + 2 < sizeof(esc); i++) {
		if (msg[i] == '%')
			esc[j++] = '%';
		esc[j++] = msg[i];
	}
	esc[j] = '\0';
	c->cb.logger(c->cb.componentEnvironment, c->name, status,
		     status == fmi2OK ? "logAll" : "logStatusError", esc);
}

/* --- resources --- */

static int hexval(char ch)
{
	if (ch >= '0' && ch <= '9')
		return ch - '0';
	if (ch >= 'a' && ch <= 'f')
		return ch - 'a' + 10;
	if (ch >= 'A' && ch <= 'F')
		return ch - 'A' + 10;
	return -1;
}

/*
 * A file: URI to a path: file:///p, file:/p and file://localhost/p, percent-decoded (the FMI 2.0
 * fmuResourceLocation; the standard requires the file scheme with and without the authority).
 */
static int uri_to_path(const char *uri, char *buf, size_t size)
{
	const char *p;
	size_t n = 0;

	if (strncmp(uri, "file:", 5) != 0)
		return -EINVAL;
	p = uri + 5;
	if (strncmp(p, "//", 2) == 0) {
		p += 2;
		if (strncmp(p, "localhost/", 10) == 0)
			p += 9;
		else if (*p != '/')
			return -EINVAL; /* another host */
	}
	if (*p != '/')
		return -EINVAL;
	for (; *p; p++) {
		char ch = *p;

		if (ch == '%') {
			int hi = hexval(p[1]), lo = hi < 0 ? -1 : hexval(p[2]);

			if (hi < 0 || lo < 0)
				return -EINVAL;
			ch = (char)(hi * 16 + lo);
			p += 2;
		}
		if (n + 1 >= size)
			return -ENAMETOOLONG;
		buf[n++] = ch;
	}
	while (n > 1 && buf[n - 1] == '/')
		n--;
	buf[n] = '\0';
	return 0;
}

static void resource(const struct instance *c, const char *name, char *buf, size_t size)
{
	snprintf(buf, size, "%s/%s", c->dir, name);
}

/* A resource's file name: plain, no directories (the exporter writes nothing else). */
static const char *file_name(json_t *obj, const char *key)
{
	const char *s = json_string_value(json_object_get(obj, key));

	return s && s[0] && !strchr(s, '/') ? s : NULL;
}

static int get_num(struct instance *c, json_t *obj, const char *key, double lo, double hi,
		   double *ret)
{
	json_t *v = json_object_get(obj, key);

	if (!json_is_number(v) || !(json_number_value(v) >= lo && json_number_value(v) <= hi)) {
		log_msg(c, fmi2Error, "ecu.json: \"%s\": expected a number in [%g, %g]", key, lo,
			hi);
		return -EINVAL;
	}
	*ret = json_number_value(v);
	return 0;
}

/* [x, y, z, yaw, pitch] (m, deg) */
static int get_mount(struct instance *c, json_t *obj, const char *key, struct hl_ecu_mount *ret)
{
	json_t *a = json_object_get(obj, key);
	double v[5];

	if (!json_is_array(a) || json_array_size(a) != 5)
		goto bad;
	for (size_t i = 0; i < 5; i++) {
		if (!json_is_number(json_array_get(a, i)))
			goto bad;
		v[i] = json_number_value(json_array_get(a, i));
		if (!isfinite(v[i]))
			goto bad;
	}
	*ret = (struct hl_ecu_mount){ .pos_m = { v[0], v[1], v[2] },
				      .yaw_deg = v[3],
				      .pitch_deg = v[4] };
	return 0;
bad:
	log_msg(c, fmi2Error, "ecu.json: \"%s\": expected [x, y, z, yaw, pitch]", key);
	return -EINVAL;
}

static int load_options(struct instance *c, json_t *root)
{
	json_t *faults = json_object_get(root, "faults"), *bend = json_object_get(root, "bend");
	double v;
	size_t i;
	json_t *f;

	hl_ecu_config_default(&c->cfg);
	if (get_mount(c, root, "camera", &c->cfg.camera) < 0 ||
	    get_num(c, root, "window_fraction", 0, 1, &c->cfg.window_fraction) < 0 ||
	    get_num(c, root, "margin_deg", 0, 45, &c->cfg.margin_deg) < 0 ||
	    get_num(c, root, "margin_m", 0, 5, &c->cfg.margin_m) < 0 ||
	    get_num(c, root, "min_confidence", 0, 1, &c->cfg.min_confidence) < 0 ||
	    get_num(c, root, "auto_high_mps", 0, 100, &c->cfg.auto_high_mps) < 0)
		return -EINVAL;
	if (get_num(c, root, "vehicle_timeout_ms", 1, 60000, &v) < 0)
		return -EINVAL;
	c->cfg.vehicle_timeout_ns = llround(v * 1e6);
	if (get_num(c, root, "objects_timeout_ms", 1, 60000, &v) < 0)
		return -EINVAL;
	c->cfg.objects_timeout_ns = llround(v * 1e6);
	if (get_num(c, root, "e2e_max_errors", 1, 1000, &v) < 0)
		return -EINVAL;
	c->cfg.e2e_max_errors = (int)v;
	if (!json_is_boolean(bend)) {
		log_msg(c, fmi2Error, "ecu.json: \"bend\": expected true or false");
		return -EINVAL;
	}
	c->cfg.bend = json_is_true(bend);
	/* the FMU's own faults, for tests of an importer (absent: none) */
	if (json_object_get(root, "step_error") && get_num(c, root, "step_error", 0, 1e9, &v) < 0)
		return -EINVAL;
	c->step_error = json_object_get(root, "step_error") ? (long)v : 0;
	if (json_object_get(root, "step_crash") && get_num(c, root, "step_crash", 0, 1e9, &v) < 0)
		return -EINVAL;
	c->step_crash = json_object_get(root, "step_crash") ? (long)v : 0;
	if (!json_is_array(faults)) {
		log_msg(c, fmi2Error, "ecu.json: \"faults\": expected an array of names");
		return -EINVAL;
	}
	json_array_foreach(faults, i, f)
	{
		const char *s = json_string_value(f);

		if (s && strcmp(s, "ignore-objects") == 0)
			c->cfg.faults |= HL_ECU_FAULT_IGNORE_OBJECTS;
		else if (s && strcmp(s, "no-failsafe") == 0)
			c->cfg.faults |= HL_ECU_FAULT_NO_FAILSAFE;
		else {
			log_msg(c, fmi2Error,
				"ecu.json: \"faults\"[%zu]: expected \"ignore-objects\" or "
				"\"no-failsafe\"",
				i);
			return -EINVAL;
		}
	}
	return 0;
}

static int load_dbc(struct instance *c, json_t *root)
{
	const char *name = file_name(root, "inputs_dbc");
	char path[4200], msg[512] = "";
	struct hl_dbc_error err;
	int rc;

	if (!name) {
		log_msg(c, fmi2Error, "ecu.json: \"inputs_dbc\": expected a file name");
		return -EINVAL;
	}
	resource(c, name, path, sizeof(path));
	rc = hl_dbc_parse_file(path, &c->db, &err);
	if (rc < 0) {
		log_msg(c, fmi2Error, "'%s':%d:%d: %s", path, err.line, err.column, err.msg);
		return rc;
	}
	rc = hl_inputs_map_new(c->db, &c->map, msg, sizeof(msg));
	if (rc < 0)
		log_msg(c, fmi2Error, "'%s': the input database: %s", path, msg);
	return rc;
}

/* "builtin:hd84_left" / "builtin:hd84_right", or a LID file among the resources. */
static int load_lid(struct instance *c, json_t *lamp, int l)
{
	const char *lid = json_string_value(json_object_get(lamp, "lid"));
	char path[4200];
	struct hl_lid_error err;
	int rc;

	if (lid && strcmp(lid, "builtin:hd84_left") == 0)
		return hl_model_hd84(HL_SIDE_LEFT, &c->lids[l]);
	if (lid && strcmp(lid, "builtin:hd84_right") == 0)
		return hl_model_hd84(HL_SIDE_RIGHT, &c->lids[l]);
	lid = file_name(lamp, "lid");
	if (!lid) {
		log_msg(c, fmi2Error,
			"ecu.json: lamps[%d].lid: expected builtin:hd84_left, builtin:hd84_right "
			"or a file name",
			l);
		return -EINVAL;
	}
	resource(c, lid, path, sizeof(path));
	rc = hl_lid_read(path, &c->lids[l], &err);
	if (rc < 0)
		log_msg(c, fmi2Error, "%s", err.msg);
	return rc;
}

static int load_beam(struct instance *c, json_t *lamp, int l, const char *key, float *ret)
{
	json_t *a = json_object_get(lamp, key);
	const int n = hl_lid_n_sources(c->lids[l]);

	if (!json_is_array(a) || json_array_size(a) != (size_t)n)
		goto bad;
	for (int k = 0; k < n; k++) {
		json_t *v = json_array_get(a, (size_t)k);

		if (!json_is_number(v) || !(json_number_value(v) >= 0 && json_number_value(v) <= 1))
			goto bad;
		ret[k] = (float)json_number_value(v);
	}
	return 0;
bad:
	log_msg(c, fmi2Error, "ecu.json: lamps[%d].%s: expected %d numbers in [0, 1]", l, key, n);
	return -EINVAL;
}

static int load_lamps(struct instance *c, json_t *root)
{
	json_t *lamps = json_object_get(root, "lamps");

	if (!json_is_array(lamps) || json_array_size(lamps) < 1 ||
	    json_array_size(lamps) > HL_ECU_MAX_LAMPS) {
		log_msg(c, fmi2Error, "ecu.json: \"lamps\": expected 1..%d lamps",
			HL_ECU_MAX_LAMPS);
		return -EINVAL;
	}
	for (int l = 0; l < (int)json_array_size(lamps); l++) {
		json_t *lamp = json_array_get(lamps, (size_t)l);
		const char *name = json_string_value(json_object_get(lamp, "name"));
		int rc, n;

		if (!name || !name[0]) {
			log_msg(c, fmi2Error, "ecu.json: lamps[%d].name: expected a name", l);
			return -EINVAL;
		}
		c->lamp_names[l] = strdup(name);
		if (!c->lamp_names[l])
			return -ENOMEM;
		c->n_lamps = l + 1;
		rc = load_lid(c, lamp, l);
		if (rc < 0)
			return rc;
		n = hl_lid_n_sources(c->lids[l]);
		c->beams[l] = calloc(2 * (size_t)n, sizeof(float));
		if (!c->beams[l])
			return -ENOMEM;
		rc = load_beam(c, lamp, l, "low", c->beams[l]);
		if (rc == 0)
			rc = load_beam(c, lamp, l, "high", c->beams[l] + n);
		if (rc == 0)
			rc = get_mount(c, lamp, "mount", &c->lamps[l].mount);
		if (rc < 0)
			return rc;
		c->lamps[l].lid = c->lids[l];
		c->lamps[l].low = c->beams[l];
		c->lamps[l].high = c->beams[l] + n;
	}
	return 0;
}

static int load(struct instance *c, const char *guid)
{
	char path[4200];
	json_error_t jerr;
	json_t *root;
	const char *want;
	int rc;

	resource(c, "ecu.json", path, sizeof(path));
	root = json_load_file(path, 0, &jerr);
	if (!root) {
		log_msg(c, fmi2Error, "'%s':%d:%d: %s", path, jerr.line, jerr.column, jerr.text);
		return -EINVAL;
	}
	want = json_string_value(json_object_get(root, "guid"));
	if (!want || !guid || strcmp(want, guid) != 0) {
		log_msg(c, fmi2Error, "'%s': the FMU's guid is \"%s\", the importer passed \"%s\"",
			path, want ? want : "", guid ? guid : "");
		rc = -EINVAL;
		goto out;
	}
	rc = load_options(c, root);
	if (rc == 0)
		rc = load_dbc(c, root);
	if (rc == 0)
		rc = load_lamps(c, root);
out:
	json_decref(root);
	return rc;
}

/* The ECU, its interface and the vectors, from what load() read. */
static int build(struct instance *c)
{
	const char *what = NULL;
	char err[256] = "";
	int rc;

	rc = hl_ecu_new(&c->cfg, c->lamps, c->n_lamps, &c->e, &what);
	if (rc < 0) {
		log_msg(c, fmi2Error, "the ECU: %s", what ? what : strerror(-rc));
		return rc;
	}
	rc = hl_ecu_io_new(c->map, (const struct hl_lid *const *)c->lids,
			   (const char *const *)c->lamp_names, c->n_lamps, &c->io, err,
			   sizeof(err));
	if (rc < 0) {
		log_msg(c, fmi2Error, "the ECU's inputs and outputs: %s", err);
		return rc;
	}
	c->n_in = hl_ecu_io_n_inputs(c->io);
	c->n_out = hl_ecu_io_n_outputs(c->io);
	c->in = calloc((size_t)c->n_in, sizeof(double));
	c->out = calloc((size_t)c->n_out, sizeof(double));
	if (!c->in || !c->out)
		return -ENOMEM;
	hl_ecu_io_init_inputs(c->io, c->in);
	hl_ecu_io_model_init(&c->model);
	return 0;
}

static void instance_free(struct instance *c)
{
	if (!c)
		return;
	free(c->in);
	free(c->out);
	hl_ecu_io_free(c->io);
	hl_ecu_free(c->e);
	for (int l = 0; l < HL_ECU_MAX_LAMPS; l++) {
		hl_lid_free(c->lids[l]);
		free(c->beams[l]);
		free(c->lamp_names[l]);
	}
	hl_inputs_map_free(c->map);
	hl_dbc_free(c->db);
	free(c->name);
	free(c);
}

/* --- the FMI 2.0 functions --- */

HL_FMI2_EXPORT const char *fmi2GetTypesPlatform(void)
{
	return "default";
}

HL_FMI2_EXPORT const char *fmi2GetVersion(void)
{
	return "2.0";
}

HL_FMI2_EXPORT fmi2Component fmi2Instantiate(fmi2String instance_name, fmi2Type type,
					     fmi2String guid, fmi2String resource_location,
					     const fmi2CallbackFunctions *functions,
					     fmi2Boolean visible, fmi2Boolean logging_on)
{
	struct instance *c = calloc(1, sizeof(*c));

	(void)visible;
	if (!c)
		return NULL;
	if (functions)
		c->cb = *functions;
	c->logging = logging_on;
	c->name = strdup(instance_name && instance_name[0] ? instance_name : "hdlamp_ecu");
	if (!c->name)
		goto err_free;
	if (type != fmi2CoSimulation) {
		log_msg(c, fmi2Error, "fmi2Instantiate: only co-simulation is supported");
		goto err_free;
	}
	if (!resource_location || uri_to_path(resource_location, c->dir, sizeof(c->dir)) < 0) {
		log_msg(c, fmi2Error,
			"fmi2Instantiate: fmuResourceLocation \"%s\": expected a file: URI of the "
			"resources directory",
			resource_location ? resource_location : "(null)");
		goto err_free;
	}
	if (load(c, guid) < 0 || build(c) < 0)
		goto err_free;
	log_msg(c, fmi2OK, "instantiated from '%s': %d inputs, %d outputs", c->dir, c->n_in,
		c->n_out);
	return c;

err_free:
	instance_free(c);
	return NULL;
}

HL_FMI2_EXPORT void fmi2FreeInstance(fmi2Component comp)
{
	instance_free(comp);
}

HL_FMI2_EXPORT fmi2Status fmi2SetDebugLogging(fmi2Component comp, fmi2Boolean logging_on,
					      size_t n_categories, const fmi2String categories[])
{
	struct instance *c = comp;

	(void)n_categories;
	(void)categories;
	if (!c)
		return fmi2Error;
	c->logging = logging_on;
	return fmi2OK;
}

HL_FMI2_EXPORT fmi2Status fmi2SetupExperiment(fmi2Component comp, fmi2Boolean tolerance_defined,
					      fmi2Real tolerance, fmi2Real start_time,
					      fmi2Boolean stop_time_defined, fmi2Real stop_time)
{
	struct instance *c = comp;

	(void)tolerance_defined;
	(void)tolerance;
	(void)stop_time_defined;
	(void)stop_time;
	if (!c)
		return fmi2Error;
	c->last_time_s = start_time;
	return fmi2OK;
}

HL_FMI2_EXPORT fmi2Status fmi2EnterInitializationMode(fmi2Component comp)
{
	struct instance *c = comp;

	if (!c || c->state != INSTANTIATED)
		return fmi2Error;
	c->state = INITIALIZING;
	return fmi2OK;
}

HL_FMI2_EXPORT fmi2Status fmi2ExitInitializationMode(fmi2Component comp)
{
	struct instance *c = comp;

	if (!c || c->state != INITIALIZING)
		return fmi2Error;
	c->state = STEPPING;
	return fmi2OK;
}

HL_FMI2_EXPORT fmi2Status fmi2Terminate(fmi2Component comp)
{
	struct instance *c = comp;

	if (!c)
		return fmi2Error;
	c->state = TERMINATED;
	return fmi2OK;
}

/* Back to just after fmi2Instantiate: a new ECU, the inputs' start values, outputs 0. */
HL_FMI2_EXPORT fmi2Status fmi2Reset(fmi2Component comp)
{
	struct instance *c = comp;
	const char *what = NULL;
	struct hl_ecu *e;
	int rc;

	if (!c)
		return fmi2Error;
	rc = hl_ecu_new(&c->cfg, c->lamps, c->n_lamps, &e, &what);
	if (rc < 0) {
		log_msg(c, fmi2Error, "fmi2Reset: the ECU: %s", what ? what : strerror(-rc));
		return fmi2Error;
	}
	hl_ecu_free(c->e);
	c->e = e;
	hl_ecu_io_init_inputs(c->io, c->in);
	hl_ecu_io_model_init(&c->model);
	memset(c->out, 0, (size_t)c->n_out * sizeof(double));
	c->state = INSTANTIATED;
	return fmi2OK;
}

HL_FMI2_EXPORT fmi2Status fmi2SetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
				      const fmi2Real value[])
{
	struct instance *c = comp;

	if (!c)
		return fmi2Error;
	for (size_t i = 0; i < nvr; i++)
		if (vr[i] >= (fmi2ValueReference)c->n_in) {
			log_msg(c, fmi2Error, "fmi2SetReal: value reference %u is no input (0..%d)",
				vr[i], c->n_in - 1);
			return fmi2Error;
		}
	for (size_t i = 0; i < nvr; i++)
		c->in[vr[i]] = value[i];
	return fmi2OK;
}

HL_FMI2_EXPORT fmi2Status fmi2GetReal(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
				      fmi2Real value[])
{
	struct instance *c = comp;

	if (!c)
		return fmi2Error;
	for (size_t i = 0; i < nvr; i++) {
		if (vr[i] >= (fmi2ValueReference)(c->n_in + c->n_out)) {
			log_msg(c, fmi2Error, "fmi2GetReal: no variable has value reference %u",
				vr[i]);
			return fmi2Error;
		}
		value[i] = vr[i] < (fmi2ValueReference)c->n_in ? c->in[vr[i]] :
								 c->out[vr[i] - c->n_in];
	}
	return fmi2OK;
}

HL_FMI2_EXPORT fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real t, fmi2Real h,
				     fmi2Boolean no_set_state_prior)
{
	struct instance *c = comp;
	struct hl_ecu_status st;

	(void)no_set_state_prior;
	if (!c)
		return fmi2Error;
	if (c->state != STEPPING) {
		log_msg(c, fmi2Error, "fmi2DoStep: not after fmi2ExitInitializationMode");
		return fmi2Error;
	}
	if (!isfinite(t) || !(h >= 0) || !isfinite(h)) {
		log_msg(c, fmi2Error, "fmi2DoStep(%g, %g): expected finite times, h >= 0", t, h);
		return fmi2Error;
	}
	c->steps++;
	if (c->steps == c->step_error) {
		log_msg(c, fmi2Error, "fmi2DoStep(%g, %g): the fault step-error=%ld", t, h,
			c->steps);
		return fmi2Error;
	}
	if (c->steps == c->step_crash) {
		log_msg(c, fmi2OK, "fmi2DoStep(%g, %g): the fault step-crash=%ld: crashing", t, h,
			c->steps);
		*(volatile int *)c->null_page =
			1; /* a real segmentation fault, as a bug makes one */
	}
	hl_ecu_io_apply(c->io, &c->model, c->in, c->e);
	hl_ecu_step(c->e, llround((t + h) * 1e9), &st);
	hl_ecu_io_outputs(c->io, c->e, c->out);
	c->last_time_s = t + h;
	return fmi2OK;
}

void hl_refmu_not_supported(fmi2Component comp, const char *fn)
{
	if (comp)
		log_msg(comp, fmi2Error, "%s: not supported", fn);
}
