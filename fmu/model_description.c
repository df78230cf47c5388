/* SPDX-License-Identifier: MIT */
#include "fmu/model_description.h"

#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <libxml/parser.h>
#include <libxml/tree.h>

struct reader {
	const char *fmu;
	char *err;
	size_t err_size;
};

static int bad(const struct reader *rd, int r, int line, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));

static int bad(const struct reader *rd, int r, int line, const char *fmt, ...)
{
	int at = snprintf(rd->err, rd->err_size, "'%s': modelDescription.xml:%d: ", rd->fmu, line);
	va_list ap;

	if (at < 0 || (size_t)at >= rd->err_size)
		return r;
	va_start(ap, fmt);
	vsnprintf(rd->err + at, rd->err_size - (size_t)at, fmt, ap);
	va_end(ap);
	return r;
}

static int line_of(const xmlNode *n)
{
	return (int)xmlGetLineNo(n);
}

static bool named(const xmlNode *n, const char *name)
{
	return n->type == XML_ELEMENT_NODE && strcmp((const char *)n->name, name) == 0;
}

static const xmlNode *child(const xmlNode *n, const char *name)
{
	for (const xmlNode *c = n->children; c; c = c->next)
		if (named(c, name))
			return c;
	return NULL;
}

/* The attribute's value (malloc'd, the caller frees), or NULL when it is absent. */
static char *attr(const xmlNode *n, const char *name)
{
	return (char *)xmlGetProp(n, (const xmlChar *)name);
}

static int required(const struct reader *rd, const xmlNode *n, const char *name, char **ret)
{
	*ret = attr(n, name);
	if (!*ret || !**ret) {
		xmlFree(*ret);
		*ret = NULL;
		return bad(rd, -EBADMSG, line_of(n), "<%s> has no %s", (const char *)n->name, name);
	}
	return 0;
}

/* value among names[] (NULL-terminated), its index; absent: dflt. -EBADMSG otherwise. */
static int pick(const struct reader *rd, const xmlNode *n, const char *name,
		const char *const *names, int dflt, const char *var)
{
	char *v = attr(n, name);
	int r = dflt;

	if (v) {
		r = -EBADMSG;
		for (int i = 0; names[i]; i++)
			if (strcmp(v, names[i]) == 0)
				r = i;
		if (r < 0)
			bad(rd, r, line_of(n), "variable '%s': %s \"%s\" is not one of FMI 2.0's",
			    var, name, v);
		xmlFree(v);
	}
	return r;
}

/* 2.2.7, in the order of enum hl_fmu_causality */
static const char *const causalities[] = {
	"parameter", "calculatedParameter", "input", "output", "local", "independent", NULL,
};
static const char *const variabilities[] = {
	"constant", "fixed", "tunable", "discrete", "continuous", NULL,
};
/* 2.2.7, in the order of enum hl_fmu_type */
static const char *const types[] = {
	"Real", "Integer", "Boolean", "String", "Enumeration", NULL,
};

static int read_var(const struct reader *rd, const xmlNode *n, struct hl_fmu_var *v)
{
	char *name, *vr, *end;
	unsigned long ul;
	int r, type = -1;

	r = required(rd, n, "name", &name);
	if (r < 0)
		return r;
	v->name = name;
	v->line = line_of(n);
	r = required(rd, n, "valueReference", &vr);
	if (r < 0)
		return r;
	errno = 0;
	ul = strtoul(vr, &end, 10);
	if (vr[0] < '0' || vr[0] > '9' || *end || errno || ul > UINT32_MAX) {
		r = bad(rd, -EBADMSG, v->line,
			"variable '%s': valueReference \"%s\" is not an unsigned 32-bit number",
			name, vr);
		xmlFree(vr);
		return r;
	}
	xmlFree(vr);
	v->vr = (uint32_t)ul;
	r = pick(rd, n, "causality", causalities, HL_FMU_LOCAL, name);
	if (r < 0)
		return r;
	v->causality = (enum hl_fmu_causality)r;
	r = pick(rd, n, "variability", variabilities, 4, name);
	if (r < 0)
		return r;
	for (const xmlNode *c = n->children; c; c = c->next) {
		if (c->type != XML_ELEMENT_NODE)
			continue;
		for (int t = 0; types[t]; t++) {
			if (!named(c, types[t]))
				continue;
			if (type >= 0)
				return bad(rd, -EBADMSG, line_of(c),
					   "variable '%s': a second type element <%s>", name,
					   types[t]);
			type = t;
		}
	}
	if (type < 0)
		return bad(rd, -EBADMSG, v->line,
			   "variable '%s': no type element (Real, Integer, Boolean, String or "
			   "Enumeration)",
			   name);
	v->type = (enum hl_fmu_type)type;
	return 0;
}

static int read_vars(const struct reader *rd, const xmlNode *root, struct hl_fmu_md *md)
{
	const xmlNode *list = child(root, "ModelVariables");
	int n = 0, r;

	if (!list)
		return bad(rd, -EBADMSG, line_of(root), "no <ModelVariables>");
	for (const xmlNode *c = list->children; c; c = c->next)
		n += named(c, "ScalarVariable");
	md->vars = calloc(n ? (size_t)n : 1, sizeof(*md->vars));
	if (!md->vars)
		return -ENOMEM;
	for (const xmlNode *c = list->children; c; c = c->next) {
		if (!named(c, "ScalarVariable"))
			continue;
		r = read_var(rd, c, &md->vars[md->n_vars]);
		md->n_vars++; /* its name is freed with the others even when it failed */
		if (r < 0)
			return r;
		for (int i = 0; i < md->n_vars - 1; i++)
			if (strcmp(md->vars[i].name, md->vars[md->n_vars - 1].name) == 0)
				return bad(rd, -EBADMSG, line_of(c),
					   "variable '%s' declared again (first on line %d)",
					   md->vars[i].name, md->vars[i].line);
	}
	return 0;
}

static int read_root(const struct reader *rd, const xmlNode *root, struct hl_fmu_md *md)
{
	const xmlNode *cs;
	char *version;
	int r;

	if (!root || !named(root, "fmiModelDescription"))
		return bad(rd, -EBADMSG, root ? line_of(root) : 1,
			   "the root element is not <fmiModelDescription>");
	r = required(rd, root, "fmiVersion", &version);
	if (r < 0)
		return r;
	if (strcmp(version, "2.0") != 0) {
		r = bad(rd, -ENOTSUP, line_of(root),
			"fmiVersion \"%s\": only FMI 2.0 (fmiVersion \"2.0\") is supported",
			version);
		xmlFree(version);
		return r;
	}
	xmlFree(version);
	r = required(rd, root, "modelName", &md->model_name);
	if (r < 0)
		return r;
	r = required(rd, root, "guid", &md->guid);
	if (r < 0)
		return r;
	cs = child(root, "CoSimulation");
	if (!cs)
		return bad(rd, -ENOTSUP, line_of(root),
			   "no <CoSimulation>: not an FMU for co-simulation");
	r = required(rd, cs, "modelIdentifier", &md->identifier);
	if (r < 0)
		return r;
	/* it names a file: binaries/linux64/<modelIdentifier>.so */
	if (strchr(md->identifier, '/') || md->identifier[0] == '.')
		return bad(rd, -EBADMSG, line_of(cs), "modelIdentifier \"%s\" is not a file name",
			   md->identifier);
	return read_vars(rd, root, md);
}

int hl_fmu_md_read(const char *path, const char *fmu, struct hl_fmu_md **ret, char *err,
		   size_t err_size)
{
	const struct reader rd = { .fmu = fmu, .err = err, .err_size = err_size };
	struct hl_fmu_md *md;
	xmlParserCtxtPtr ctxt;
	xmlDocPtr doc;
	int r;

	if (access(path, R_OK) < 0) {
		r = -errno;
		snprintf(err, err_size, "'%s': no modelDescription.xml (%s)", fmu, strerror(-r));
		return r;
	}
	md = calloc(1, sizeof(*md));
	ctxt = xmlNewParserCtxt();
	if (!md || !ctxt) {
		r = -ENOMEM;
		goto err_free;
	}
	/* no DTD, no entities substituted, nothing fetched: the file is foreign */
	doc = xmlCtxtReadFile(ctxt, path, NULL,
			      XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
	if (!doc) {
		const xmlError *e = xmlCtxtGetLastError(ctxt);
		size_t len;

		r = bad(&rd, -EBADMSG, e ? e->line : 0, "XML does not parse: %s",
			e && e->message ? e->message : "unknown error");
		len = strlen(err);
		while (len && (err[len - 1] == '\n' || err[len - 1] == ' '))
			err[--len] = '\0';
		goto err_free;
	}
	r = read_root(&rd, xmlDocGetRootElement(doc), md);
	xmlFreeDoc(doc);
	if (r < 0)
		goto err_free;
	xmlFreeParserCtxt(ctxt);
	*ret = md;
	return 0;

err_free:
	if (r == -ENOMEM)
		snprintf(err, err_size, "'%s': modelDescription.xml: out of memory", fmu);
	xmlFreeParserCtxt(ctxt);
	hl_fmu_md_free(md);
	return r;
}

void hl_fmu_md_free(struct hl_fmu_md *md)
{
	if (!md)
		return;
	for (int i = 0; i < md->n_vars; i++)
		xmlFree((char *)md->vars[i].name);
	free(md->vars);
	xmlFree(md->model_name);
	xmlFree(md->guid);
	xmlFree(md->identifier);
	free(md);
}
