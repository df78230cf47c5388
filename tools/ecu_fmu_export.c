/* SPDX-License-Identifier: MIT */
/*
 * The reference ECU packed as an FMI 2.0 co-simulation FMU (tools/ecu_fmu_export.h).
 *
 * The layout is the standard's ZIP of an FMU: modelDescription.xml at the top,
 * binaries/linux64/<modelIdentifier>.so, resources/ (what fmi2Instantiate's fmuResourceLocation
 * points at), every entry deflated, no leading "./" (FMI 2.0 section 2.3 "FMU Distribution";
 * modelica/fmi-guides, fmi-guide/3___packaging.adoc). Byte-identical output for identical inputs:
 * the entries in a fixed order, every DOS time stamp 1980-01-01 00:00, and a guid that is a hash
 * of everything the FMU carries.
 */
#include "tools/ecu_fmu_export.h"

#include <errno.h>
#include <inttypes.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zip.h>

#include "base/json_write.h"
#include "base/share_dir.h"
#include "base/xml_write.h"
#include "ecu/io.h"

#define MODEL_IDENTIFIER "hdlamp_ecu"
#define SO_ENTRY "binaries/linux64/" MODEL_IDENTIFIER ".so"
#define DOS_DATE_1980 ((1 << 5) | 1) /* 1980-01-01: day 1, month 1, year 1980 + 0 */

/* One file of the FMU, its bytes owned here. */
struct entry {
	char name[300];
	char *data;
	size_t size;
	bool executable;
};

struct pack {
	struct entry e[16];
	int n;
};

static int fail(const char *what, const char *detail, int rc)
{
	fprintf(stderr, "hdlamp ecu: --fmu: %s: %s\n", what, detail);
	return rc;
}

static int read_all(const char *path, char **ret, size_t *ret_size)
{
	FILE *f = fopen(path, "rbe");
	char *buf = NULL;
	size_t n = 0, cap = 0;

	if (!f)
		return fail(path, strerror(errno), -errno);
	for (;;) {
		size_t got;

		if (cap - n < 65536) {
			char *nb = realloc(buf, cap + 1048576);

			if (!nb) {
				free(buf);
				fclose(f);
				return -ENOMEM;
			}
			buf = nb;
			cap += 1048576;
		}
		got = fread(buf + n, 1, cap - n, f);
		n += got;
		if (got == 0)
			break;
	}
	if (ferror(f)) {
		free(buf);
		fclose(f);
		return fail(path, "read error", -EIO);
	}
	fclose(f);
	*ret = buf;
	*ret_size = n;
	return 0;
}

static struct entry *add(struct pack *p, const char *name)
{
	struct entry *e = &p->e[p->n++];

	snprintf(e->name, sizeof(e->name), "%s", name);
	return e;
}

static int add_file(struct pack *p, const char *name, const char *path)
{
	struct entry *e = add(p, name);

	return read_all(path, &e->data, &e->size);
}

/* The shared object: ../<libdir>/hdlamp beside the executable's directory (build and install). */
static int so_path(char *buf, size_t size)
{
	return hl_exe_relative(HL_ECU_FMU_RELDIR "/" MODEL_IDENTIFIER ".so", buf, size);
}

/* FNV-1a, 64 bits, from basis h. */
static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
{
	const unsigned char *p = data;

	for (size_t i = 0; i < n; i++) {
		h ^= p[i];
		h *= 0x100000001b3ull;
	}
	return h;
}

/* A guid of everything the FMU carries, as {8-4-4-4-12} hex digits. */
static void make_guid(const struct pack *p, char *buf, size_t size)
{
	uint64_t a = 0xcbf29ce484222325ull, b = 0x84222325cbf29ce4ull;

	for (int i = 0; i < p->n; i++) {
		a = fnv1a(a, p->e[i].name, strlen(p->e[i].name) + 1);
		a = fnv1a(a, p->e[i].data, p->e[i].size);
		b = fnv1a(b, p->e[i].data, p->e[i].size);
		b = fnv1a(b, p->e[i].name, strlen(p->e[i].name) + 1);
	}
	snprintf(buf, size,
		 "{%08" PRIx64 "-%04" PRIx64 "-%04" PRIx64 "-%04" PRIx64 "-%012" PRIx64 "}",
		 a >> 32, (a >> 16) & 0xffff, a & 0xffff, b >> 48, b & UINT64_C(0xffffffffffff));
}

static void mount_json(FILE *f, const struct hl_ecu_mount *m)
{
	const double v[5] = { m->pos_m[0], m->pos_m[1], m->pos_m[2], m->yaw_deg, m->pitch_deg };

	fprintf(f, "[");
	for (int i = 0; i < 5; i++) {
		fprintf(f, "%s", i ? ", " : "");
		hl_json_write_num(f, v[i], "%.17g");
	}
	fprintf(f, "]");
}

static void beam_json(FILE *f, const float *v, int n)
{
	fprintf(f, "[");
	for (int k = 0; k < n; k++) {
		fprintf(f, "%s", k ? ", " : "");
		hl_json_write_num(f, v[k], "%.9g"); /* a float's exact value back */
	}
	fprintf(f, "]");
}

/* resources/ecu.json (read by ecu/fmu/reference_fmu.c), guid NULL for the hash's version. */
static int ecu_json(const struct hl_ecu_config *cfg, const struct hl_ecu_fmu_faults *ff,
		    const char *dbc_name, const struct hl_ecu_fmu_lamp *lamps,
		    const char *const *lid_names, int n_lamps, const char *guid, char **ret,
		    size_t *ret_size)
{
	FILE *f = open_memstream(ret, ret_size);

	if (!f)
		return -ENOMEM;
	fprintf(f, "{\n  \"guid\": ");
	hl_json_write_str(f, guid ? guid : "");
	fprintf(f, ",\n  \"inputs_dbc\": ");
	hl_json_write_str(f, dbc_name);
	fprintf(f, ",\n  \"camera\": ");
	mount_json(f, &cfg->camera);
	fprintf(f,
		",\n  \"window_fraction\": %.17g,\n  \"margin_deg\": %.17g,\n  \"margin_m\": %.17g,\n"
		"  \"min_confidence\": %.17g,\n  \"auto_high_mps\": %.17g,\n",
		cfg->window_fraction, cfg->margin_deg, cfg->margin_m, cfg->min_confidence,
		cfg->auto_high_mps);
	fprintf(f, "  \"vehicle_timeout_ms\": %.17g,\n  \"objects_timeout_ms\": %.17g,\n",
		(double)cfg->vehicle_timeout_ns / 1e6, (double)cfg->objects_timeout_ns / 1e6);
	fprintf(f, "  \"e2e_max_errors\": %d,\n  \"bend\": %s,\n  \"faults\": [",
		cfg->e2e_max_errors, cfg->bend ? "true" : "false");
	if (cfg->faults & HL_ECU_FAULT_IGNORE_OBJECTS)
		fprintf(f, "\"ignore-objects\"%s",
			cfg->faults & HL_ECU_FAULT_NO_FAILSAFE ? ", " : "");
	if (cfg->faults & HL_ECU_FAULT_NO_FAILSAFE)
		fprintf(f, "\"no-failsafe\"");
	fprintf(f, "],\n  \"step_error\": %d,\n  \"step_crash\": %d,\n  \"lamps\": [",
		ff ? ff->step_error : 0, ff ? ff->step_crash : 0);
	for (int l = 0; l < n_lamps; l++) {
		const int n = hl_lid_n_sources(lamps[l].lid);

		fprintf(f, "%s\n    {\"name\": ", l ? "," : "");
		hl_json_write_str(f, lamps[l].name);
		fprintf(f, ", \"lid\": ");
		hl_json_write_str(f, lid_names[l]);
		fprintf(f, ", \"mount\": ");
		mount_json(f, &lamps[l].mount);
		fprintf(f, ",\n     \"low\": ");
		beam_json(f, lamps[l].low, n);
		fprintf(f, ",\n     \"high\": ");
		beam_json(f, lamps[l].high, n);
		fprintf(f, "}");
	}
	fprintf(f, "\n  ]\n}\n");
	return fclose(f) == 0 ? 0 : -ENOMEM;
}

/*
 * modelDescription.xml. Inputs and outputs are variability "discrete": they change only at
 * communication points, and an importer must hold an input between them, not interpolate it.
 */
static int model_description(const struct hl_ecu_io *io, const char *guid, char **ret,
			     size_t *ret_size)
{
	const int n_in = hl_ecu_io_n_inputs(io), n_out = hl_ecu_io_n_outputs(io);
	double *start = calloc((size_t)n_in, sizeof(double));
	FILE *f;

	if (!start)
		return -ENOMEM;
	hl_ecu_io_init_inputs(io, start);
	f = open_memstream(ret, ret_size);
	if (!f) {
		free(start);
		return -ENOMEM;
	}
	fprintf(f,
		"<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
		"<fmiModelDescription fmiVersion=\"2.0\" modelName=\"hdlamp_ecu\" guid=\"%s\"\n"
		"  description=\"hdlamp's reference virtual headlamp ECU (docs/ecu.md)\"\n"
		"  generationTool=\"hdlamp %s\" variableNamingConvention=\"flat\"\n"
		"  numberOfEventIndicators=\"0\">\n"
		"  <CoSimulation modelIdentifier=\"" MODEL_IDENTIFIER "\"\n"
		"    canHandleVariableCommunicationStepSize=\"true\"\n"
		"    canNotUseMemoryManagementFunctions=\"true\"/>\n"
		"  <LogCategories>\n"
		"    <Category name=\"logAll\"/>\n"
		"    <Category name=\"logStatusError\"/>\n"
		"  </LogCategories>\n"
		"  <DefaultExperiment startTime=\"0\" stepSize=\"0.02\"/>\n"
		"  <ModelVariables>\n",
		guid, HL_VERSION);
	for (int i = 0; i < n_in; i++) {
		fprintf(f, "    <ScalarVariable name=\"");
		hl_xml_write_text(f, hl_ecu_io_input_name(io, i));
		fprintf(f,
			"\" valueReference=\"%d\" causality=\"input\" variability=\"discrete\">"
			"<Real start=\"%.17g\"/></ScalarVariable>\n",
			i, start[i]);
	}
	for (int i = 0; i < n_out; i++) {
		fprintf(f, "    <ScalarVariable name=\"");
		hl_xml_write_text(f, hl_ecu_io_output_name(io, i));
		fprintf(f,
			"\" valueReference=\"%d\" causality=\"output\" variability=\"discrete\">"
			"<Real/></ScalarVariable>\n",
			n_in + i);
	}
	fprintf(f, "  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n");
	for (int i = 0; i < n_out; i++)
		fprintf(f, "      <Unknown index=\"%d\"/>\n", n_in + i + 1); /* 1-based */
	fprintf(f, "    </Outputs>\n  </ModelStructure>\n</fmiModelDescription>\n");
	free(start);
	return fclose(f) == 0 ? 0 : -ENOMEM;
}

static int write_zip(const char *out_path, const struct pack *p)
{
	zip_error_t zerr;
	zip_t *z;
	int err = 0;

	z = zip_open(out_path, ZIP_CREATE | ZIP_TRUNCATE, &err);
	if (!z) {
		zip_error_init_with_code(&zerr, err);
		fail(out_path, zip_error_strerror(&zerr), -EIO);
		zip_error_fini(&zerr);
		return -EIO;
	}
	for (int i = 0; i < p->n; i++) {
		const struct entry *e = &p->e[i];
		zip_source_t *src = zip_source_buffer(z, e->data, e->size, 0);
		zip_int64_t idx;

		idx = src ? zip_file_add(z, e->name, src, ZIP_FL_ENC_UTF_8) : -1;
		if (idx < 0) {
			zip_source_free(src);
			goto err_discard;
		}
		if (zip_set_file_compression(z, (zip_uint64_t)idx, ZIP_CM_DEFLATE, 9) < 0 ||
		    zip_file_set_dostime(z, (zip_uint64_t)idx, 0, DOS_DATE_1980, 0) < 0 ||
		    zip_file_set_external_attributes(z, (zip_uint64_t)idx, 0, ZIP_OPSYS_UNIX,
						     (e->executable ? 0100755u : 0100644u) << 16) <
			    0)
			goto err_discard;
	}
	if (zip_close(z) < 0)
		goto err_discard;
	return 0;

err_discard:
	fail(out_path, zip_strerror(z), -EIO);
	zip_discard(z);
	return -EIO;
}

static const char *base_name(const char *path)
{
	const char *s = strrchr(path, '/');

	return s ? s + 1 : path;
}

int hl_ecu_fmu_export(const char *out_path, const struct hl_ecu_config *cfg,
		      const struct hl_ecu_fmu_faults *faults, const char *inputs_dbc_path,
		      const struct hl_inputs_map *map, const struct hl_ecu_fmu_lamp *lamps,
		      int n_lamps)
{
	struct pack p = { .n = 0 };
	const struct hl_lid *lids[HL_ECU_MAX_LAMPS];
	const char *names[HL_ECU_MAX_LAMPS];
	char lid_names[HL_ECU_MAX_LAMPS][64], so[4096], guid[64], msg[256] = "", entry[256];
	const char *lid_refs[HL_ECU_MAX_LAMPS];
	struct hl_ecu_io *io = NULL;
	struct entry *json, *md;
	int rc;

	rc = so_path(so, sizeof(so));
	if (rc < 0)
		return fail("the FMU's shared object", strerror(-rc), rc);
	for (int l = 0; l < n_lamps; l++) {
		lids[l] = lamps[l].lid;
		names[l] = lamps[l].name;
		if (lamps[l].lid_path)
			snprintf(lid_names[l], sizeof(lid_names[l]), "lamp%d_%s.lid.exr", l,
				 lamps[l].name);
		else
			snprintf(lid_names[l], sizeof(lid_names[l]), "builtin:%s",
				 lamps[l].builtin);
		lid_refs[l] = lid_names[l];
	}
	rc = hl_ecu_io_new(map, lids, names, n_lamps, &io, msg, sizeof(msg));
	if (rc < 0) {
		fail("the ECU's inputs and outputs", msg, rc);
		goto out;
	}
	/* the fixed order of the entries; ecu.json and modelDescription.xml filled last */
	md = add(&p, "modelDescription.xml");
	rc = add_file(&p, SO_ENTRY, so);
	if (rc < 0)
		goto out;
	p.e[p.n - 1].executable = true;
	json = add(&p, "resources/ecu.json");
	snprintf(entry, sizeof(entry), "resources/%.200s", base_name(inputs_dbc_path));
	rc = add_file(&p, entry, inputs_dbc_path);
	for (int l = 0; rc == 0 && l < n_lamps; l++) {
		if (!lamps[l].lid_path)
			continue;
		snprintf(entry, sizeof(entry), "resources/%.63s", lid_names[l]);
		rc = add_file(&p, entry, lamps[l].lid_path);
	}
	if (rc < 0)
		goto out;
	/* the guid hashes every entry, ecu.json without its guid and with the variables */
	rc = ecu_json(cfg, faults, base_name(inputs_dbc_path), lamps, lid_refs, n_lamps, NULL,
		      &json->data, &json->size);
	if (rc == 0)
		rc = model_description(io, "", &md->data, &md->size);
	if (rc < 0)
		goto out;
	make_guid(&p, guid, sizeof(guid));
	free(json->data);
	free(md->data);
	json->data = md->data = NULL;
	rc = ecu_json(cfg, faults, base_name(inputs_dbc_path), lamps, lid_refs, n_lamps, guid,
		      &json->data, &json->size);
	if (rc == 0)
		rc = model_description(io, guid, &md->data, &md->size);
	if (rc == 0)
		rc = write_zip(out_path, &p);
out:
	for (int i = 0; i < p.n; i++)
		free(p.e[i].data);
	hl_ecu_io_free(io);
	return rc;
}
