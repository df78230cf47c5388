/* SPDX-License-Identifier: MIT */
/*
 * The reference ECU's FMU shared object (ecu/fmu/reference_fmu.c), dlopen'ed from the build
 * (HL_ECU_FMU_SO) with resources written here: 100 cycles of masking, an E2E error run and a
 * vehicle timeout give bitwise the outputs of the in-process reference ECU fed through ecu/io;
 * instantiation failures are logged and return NULL; unsupported functions fail.
 */
#include <dlfcn.h>
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "ecu/beams.h"
#include "ecu/fmu/fmi2_export.h"
#include "ecu/io.h"
#include "ecu/lighting.h"
#include "inputs_fixture.h"
#include "lamp/model.h"

#define MS 1000000LL
#define GUID "{test-guid}"
#define N_IN 74
#define N_OUT (2 * HL_HD84_SOURCES)

typedef fmi2Component (*instantiate_fn)(fmi2String, fmi2Type, fmi2String, fmi2String,
					const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean);
typedef fmi2Status (*component_fn)(fmi2Component);
typedef fmi2Status (*setup_fn)(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean,
			       fmi2Real);
typedef fmi2Status (*set_real_fn)(fmi2Component, const fmi2ValueReference[], size_t,
				  const fmi2Real[]);
typedef fmi2Status (*get_real_fn)(fmi2Component, const fmi2ValueReference[], size_t, fmi2Real[]);
typedef fmi2Status (*do_step_fn)(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean);
typedef void (*free_fn)(fmi2Component);
typedef const char *(*string_fn)(void);

struct fmu_fixture {
	void *inputs; /* inputs_fixture.h's */
	void *so;
	char dir[512], uri[600];
	struct hl_lid *lid[2];
	float low[2][HL_HD84_SOURCES], high[2][HL_HD84_SOURCES];
	struct hl_ecu_lamp lamps[2];
	struct hl_ecu_config cfg;
};

static char last_log[1024];
static int n_errors_logged;

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
		   fmi2String category, fmi2String message, ...)
{
	va_list ap;

	(void)env, (void)name, (void)category;
	va_start(ap, message);
	vsnprintf(last_log, sizeof(last_log), message, ap);
	va_end(ap);
	if (status == fmi2Error)
		n_errors_logged++;
}

static const fmi2CallbackFunctions callbacks = { .logger = logger };

static void *sym(struct fmu_fixture *f, const char *name)
{
	void *p = dlsym(f->so, name);

	if (!p)
		fail_msg("%s: %s", name, dlerror());
	return p;
}

static void write_beam(FILE *o, const float *v)
{
	fprintf(o, "[");
	for (int k = 0; k < HL_HD84_SOURCES; k++)
		fprintf(o, "%s%.9g", k ? "," : "", v[k]);
	fprintf(o, "]");
}

static void write_config(struct fmu_fixture *f, const char *guid)
{
	char path[600];
	FILE *o;

	snprintf(path, sizeof(path), "%s/ecu.json", f->dir);
	o = fopen(path, "w");
	assert_non_null(o);
	fprintf(o,
		"{\"guid\": \"%s\", \"inputs_dbc\": \"hd84_inputs.dbc\", "
		"\"camera\": [-1.8, 0, 1.3, 0, 0], \"window_fraction\": 0.05, \"margin_deg\": 0.5, "
		"\"margin_m\": 0.2, "
		"\"min_confidence\": 0.5, \"auto_high_mps\": %.17g, \"vehicle_timeout_ms\": 60, "
		"\"objects_timeout_ms\": 120, \"e2e_max_errors\": 3, \"bend\": true, "
		"\"faults\": [], \"lamps\": [",
		guid, 40 / 3.6);
	for (int s = 0; s < 2; s++) {
		const struct hl_ecu_mount *m = &f->lamps[s].mount;

		fprintf(o, "%s{\"name\": \"%s\", \"lid\": \"builtin:hd84_%s\", ", s ? "," : "",
			s ? "right" : "left", s ? "right" : "left");
		fprintf(o, "\"mount\": [%.17g, %.17g, %.17g, %.17g, %.17g], \"low\": ", m->pos_m[0],
			m->pos_m[1], m->pos_m[2], m->yaw_deg, m->pitch_deg);
		write_beam(o, f->low[s]);
		fprintf(o, ", \"high\": ");
		write_beam(o, f->high[s]);
		fprintf(o, "}");
	}
	fprintf(o, "]}\n");
	assert_int_equal(fclose(o), 0);
}

static int fmu_setup(void **state)
{
	struct fmu_fixture *f = calloc(1, sizeof(*f));
	char dbc[600], src[600];

	if (!f || setup(&f->inputs) != 0)
		return -1;
	f->so = dlopen(HL_ECU_FMU_SO, RTLD_NOW | RTLD_LOCAL);
	if (!f->so)
		fail_msg("%s", dlerror());
	snprintf(f->dir, sizeof(f->dir), "%s/ecu_fmu_XXXXXX",
		 getenv("HL_TEST_TMPDIR") ? getenv("HL_TEST_TMPDIR") : "/tmp");
	assert_non_null(mkdtemp(f->dir));
	snprintf(f->uri, sizeof(f->uri), "file://%s", f->dir);
	snprintf(dbc, sizeof(dbc), "%s/hd84_inputs.dbc", f->dir);
	snprintf(src, sizeof(src), "%s/dbc/hd84_inputs.dbc", getenv("HL_SOURCE_DIR"));
	assert_int_equal(symlink(src, dbc), 0);
	hl_ecu_config_default(&f->cfg);
	f->cfg.vehicle_timeout_ns = 60 * MS;
	f->cfg.objects_timeout_ns = 120 * MS;
	f->cfg.auto_high_mps = 40 / 3.6;
	for (int s = 0; s < 2; s++) {
		if (hl_model_hd84(s, &f->lid[s]) < 0 ||
		    hl_ecu_beams_default(f->lid[s], s, 0.05, f->low[s], f->high[s]) < 0)
			return -1;
		f->lamps[s] = (struct hl_ecu_lamp){
			.lid = f->lid[s],
			.mount = { .pos_m = { 0.0, s == 0 ? 0.7 : -0.7, 0.65 },
				   .pitch_deg = atan(-0.01) * 180 / M_PI },
			.low = f->low[s],
			.high = f->high[s],
		};
	}
	write_config(f, GUID);
	*state = f;
	return 0;
}

static int fmu_teardown(void **state)
{
	struct fmu_fixture *f = *state;
	char path[600];

	snprintf(path, sizeof(path), "%s/ecu.json", f->dir);
	unlink(path);
	snprintf(path, sizeof(path), "%s/hd84_inputs.dbc", f->dir);
	unlink(path);
	rmdir(f->dir);
	dlclose(f->so);
	hl_lid_free(f->lid[0]);
	hl_lid_free(f->lid[1]);
	teardown(&f->inputs);
	free(f);
	return 0;
}

static fmi2Component instantiate(struct fmu_fixture *f, const char *guid, const char *uri)
{
	instantiate_fn inst = (instantiate_fn)sym(f, "fmi2Instantiate");

	return inst("ecu", fmi2CoSimulation, guid, uri, &callbacks, fmi2False, fmi2False);
}

static void ecu_fmu_reports_platform_and_version(void **state)
{
	struct fmu_fixture *f = *state;

	assert_string_equal(((string_fn)sym(f, "fmi2GetTypesPlatform"))(), "default");
	assert_string_equal(((string_fn)sym(f, "fmi2GetVersion"))(), "2.0");
}

static void ecu_fmu_instantiate_failures_log_and_return_null(void **state)
{
	struct fmu_fixture *f = *state;

	n_errors_logged = 0;
	assert_null(instantiate(f, "{another}", f->uri));
	assert_int_equal(n_errors_logged, 1);
	assert_non_null(strstr(last_log, "guid"));
	assert_null(instantiate(f, GUID, "http://example.org/resources"));
	assert_non_null(strstr(last_log, "fmuResourceLocation"));
	assert_null(instantiate(f, GUID, "file:///nonexistent/resources"));
	assert_non_null(strstr(last_log, "ecu.json"));
	assert_int_equal(n_errors_logged, 3);
}

static void ecu_fmu_unsupported_functions_fail(void **state)
{
	struct fmu_fixture *f = *state;
	fmi2Component c = instantiate(f, GUID, f->uri);
	fmi2Status st;

	assert_non_null(c);
	assert_int_equal(((component_fn)sym(f, "fmi2CancelStep"))(c), fmi2Error);
	assert_non_null(strstr(last_log, "fmi2CancelStep: not supported"));
	assert_int_equal(((fmi2Status(*)(fmi2Component, fmi2StatusKind, fmi2Status *))sym(
				 f, "fmi2GetStatus"))(c, fmi2DoStepStatus, &st),
			 fmi2Error);
	((free_fn)sym(f, "fmi2FreeInstance"))(c);
}

/* Vehicle every cycle, camera every other; E2E failures at 40..49, no vehicle at 70..79. */
static void host_cycle(const struct hl_ecu_io *io, int cyc, int64_t now, double *in)
{
	const struct hl_vehicle_state s = {
		.speed_mps = 22 + 0.113 * cyc,
		.yaw_rate_rad_s = 0.02 * sin(cyc * 0.13),
		.steering_rad = 0.04 * cos(cyc * 0.05),
		.light_switch = HL_SWITCH_AUTO,
		.adb_enable = true,
	};
	struct hl_camera_objects o = { .n = 2 };

	o.obj[0] = (struct hl_camera_object){
		5, HL_OBJECT_ONCOMING, -5 + 0.06 * cyc, -4 + 0.06 * cyc, -0.4, 0.5, 150 - cyc, 0.9
	};
	o.obj[1] =
		(struct hl_camera_object){ 8, HL_OBJECT_PEDESTRIAN, 2.2, 2.9, -1.0, 0.3, 35, 0.7 };
	if (cyc < 70 || cyc >= 80)
		hl_ecu_io_set_vehicle(io, &s, now - 2 * MS, in);
	if (cyc % 2 == 0) {
		if (cyc >= 40 && cyc < 50)
			hl_ecu_io_set_e2e_error(io, HL_ECU_INPUT_OBJECTS, in);
		else
			hl_ecu_io_set_objects(io, &o, now - 5 * MS, in);
	}
}

static void ecu_fmu_matches_the_in_process_reference(void **state)
{
	struct fmu_fixture *f = *state;
	const struct hl_lid *lids[2] = { f->lid[0], f->lid[1] };
	const char *const names[2] = { "left", "right" };
	set_real_fn set_real = (set_real_fn)sym(f, "fmi2SetReal");
	get_real_fn get_real = (get_real_fn)sym(f, "fmi2GetReal");
	do_step_fn do_step = (do_step_fn)sym(f, "fmi2DoStep");
	struct hl_ecu_io *io;
	struct hl_ecu_io_model m;
	struct hl_ecu *e;
	fmi2Component c;
	fmi2ValueReference vr_in[N_IN], vr_out[N_OUT];
	double in[N_IN], ref[N_OUT], got[N_OUT], back[N_IN];
	int masked = 0, failsafe = 0;
	char err[256] = "";

	if (hl_ecu_io_new(((struct fixture *)f->inputs)->map, lids, names, 2, &io, err,
			  sizeof(err)) < 0)
		fail_msg("%s", err);
	assert_int_equal(hl_ecu_io_n_inputs(io), N_IN);
	assert_int_equal(hl_ecu_io_n_outputs(io), N_OUT);
	assert_int_equal(hl_ecu_new(&f->cfg, f->lamps, 2, &e, NULL), 0);
	hl_ecu_io_init_inputs(io, in);
	hl_ecu_io_model_init(&m);
	for (int i = 0; i < N_IN; i++)
		vr_in[i] = (fmi2ValueReference)i;
	for (int i = 0; i < N_OUT; i++)
		vr_out[i] = (fmi2ValueReference)(N_IN + i);

	c = instantiate(f, GUID, f->uri);
	assert_non_null(c);
	assert_int_equal(((setup_fn)sym(f, "fmi2SetupExperiment"))(c, fmi2False, 0, 0, fmi2False,
								   0),
			 fmi2OK);
	assert_int_equal(do_step(c, 0, 0.02, fmi2True), fmi2Error); /* not initialized */
	assert_int_equal(((component_fn)sym(f, "fmi2EnterInitializationMode"))(c), fmi2OK);
	assert_int_equal(((component_fn)sym(f, "fmi2ExitInitializationMode"))(c), fmi2OK);
	for (int cyc = 0; cyc < 100; cyc++) {
		const int64_t now = 1000 * MS + cyc * 20 * MS;
		struct hl_ecu_status st;

		host_cycle(io, cyc, now, in);
		/* in process */
		hl_ecu_io_apply(io, &m, in, e);
		hl_ecu_step(e, now, &st);
		hl_ecu_io_outputs(io, e, ref);
		/* the FMU: the cycle at `now` is the step that ends there */
		assert_int_equal(set_real(c, vr_in, N_IN, in), fmi2OK);
		assert_int_equal(do_step(c, (double)now / 1e9 - 0.02, 0.02, fmi2True), fmi2OK);
		assert_int_equal(get_real(c, vr_out, N_OUT, got), fmi2OK);
		assert_memory_equal(ref, got, sizeof(ref));
		assert_int_equal(get_real(c, vr_in, N_IN, back), fmi2OK);
		assert_memory_equal(in, back, sizeof(in));
		masked += st.masked[0] > 0;
		failsafe += st.failsafe != 0;
	}
	/* the run shows what it claims to: masking and fail-safes */
	assert_true(masked > 40);
	assert_true(failsafe > 10);
	assert_int_equal(set_real(c, (fmi2ValueReference[]){ N_IN }, 1, (double[]){ 1 }),
			 fmi2Error);
	assert_int_equal(get_real(c, (fmi2ValueReference[]){ N_IN + N_OUT }, 1, got), fmi2Error);
	assert_int_equal(((component_fn)sym(f, "fmi2Terminate"))(c), fmi2OK);
	((free_fn)sym(f, "fmi2FreeInstance"))(c);
	hl_ecu_free(e);
	hl_ecu_io_free(io);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(ecu_fmu_reports_platform_and_version),
		cmocka_unit_test(ecu_fmu_instantiate_failures_log_and_return_null),
		cmocka_unit_test(ecu_fmu_unsupported_functions_fail),
		cmocka_unit_test(ecu_fmu_matches_the_in_process_reference),
	};

	return cmocka_run_group_tests(tests, fmu_setup, fmu_teardown);
}
