/* SPDX-License-Identifier: MIT */
#include "verdict/record.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "base/json_write.h"

struct hl_record {
	struct hl_record_summary s;
	bool in_stretch;
	double stretch_t0_s;
	/* the recent strip: a ring of HL_RECORD_STRIP cells, head the next to write */
	struct hl_record_cellinfo strip[HL_RECORD_STRIP];
	size_t strip_head, strip_n;
	/* the whole run */
	struct hl_record_run *runs;
	size_t n_runs, max_runs;
};

int hl_record_new(size_t max_runs, struct hl_record **ret)
{
	struct hl_record *r;

	if (max_runs == 0)
		return -EINVAL;
	r = calloc(1, sizeof(*r));
	if (!r)
		return -ENOMEM;
	r->runs = calloc(max_runs, sizeof(*r->runs));
	if (!r->runs) {
		free(r);
		return -ENOMEM;
	}
	r->max_runs = max_runs;
	hl_record_reset(r);
	*ret = r;
	return 0;
}

void hl_record_free(struct hl_record *r)
{
	if (!r)
		return;
	free(r->runs);
	free(r);
}

void hl_record_reset(struct hl_record *r)
{
	memset(&r->s, 0, sizeof(r->s));
	r->s.now_req = r->s.now_part = -1;
	r->s.worst_req = r->s.worst_part = -1;
	r->in_stretch = false;
	r->strip_head = r->strip_n = 0;
	r->n_runs = 0;
}

static void end_stretch(struct hl_record *r, double t_s)
{
	const double len = t_s - r->stretch_t0_s;

	if (len > r->s.longest_failing_s) {
		r->s.longest_failing_s = len;
		r->s.longest_failing_from_s = r->stretch_t0_s;
	}
}

static void add_run(struct hl_record *r, const struct hl_record_frame *f, int req, int part)
{
	struct hl_record_run *last = r->n_runs ? &r->runs[r->n_runs - 1] : NULL;

	if (last && last->cell == (char)f->cell && last->req == req && last->part == part &&
	    last->frames < UINT32_MAX) {
		last->frames++;
		return;
	}
	if (r->n_runs == r->max_runs) {
		r->s.frames_unstripped++;
		return;
	}
	r->runs[r->n_runs++] = (struct hl_record_run){ .t0_s = f->t_s,
						       .frames = 1,
						       .cell = (char)f->cell,
						       .req = (int16_t)req,
						       .part = (int8_t)part };
}

void hl_record_add(struct hl_record *r, const struct hl_record_frame *f)
{
	struct hl_record_summary *s = &r->s;
	const bool fail = f->cell == HL_RECORD_FAIL;
	const int req = fail ? f->req : -1, part = fail ? f->part : -1;

	/* once the whole-run strip ran out, every later frame is one it does not show */
	if (s->frames_unstripped)
		s->frames_unstripped++;
	else
		add_run(r, f, req, part);
	s->frames++;
	s->now = (char)f->cell;
	s->now_t_s = f->t_s;
	s->now_req = f->cell == HL_RECORD_NA ? -1 : f->req;
	s->now_part = f->cell == HL_RECORD_NA ? -1 : f->part;
	if (f->cell == HL_RECORD_NA) {
		s->not_applicable++;
	} else {
		s->evaluated++;
		if (!isnan(f->margin) && (!s->has_worst || f->margin < s->worst_margin)) {
			s->has_worst = 1;
			s->worst_margin = f->margin;
			s->worst_req = f->req;
			s->worst_part = f->part;
			s->worst_t_s = f->t_s;
		}
	}
	if (fail) {
		s->failed++;
		if (!r->in_stretch) {
			r->in_stretch = true;
			r->stretch_t0_s = f->t_s;
		}
		end_stretch(r, f->t_s); /* while it lasts: to the newest frame */
	} else if (r->in_stretch) {
		r->in_stretch = false;
		end_stretch(r, f->t_s);
	}
	r->strip[r->strip_head] = (struct hl_record_cellinfo){
		.cell = (char)f->cell,
		.part = (int8_t)part,
		.req = (int16_t)req,
		.mode = (int16_t)(f->mode > INT16_MAX ? INT16_MAX :
				  f->mode < 0	      ? -1 :
							f->mode),
	};
	r->strip_head = (r->strip_head + 1) % HL_RECORD_STRIP;
	if (r->strip_n < HL_RECORD_STRIP)
		r->strip_n++;
}

void hl_record_summary(const struct hl_record *r, struct hl_record_summary *ret)
{
	*ret = r->s;
}

size_t hl_record_strip(const struct hl_record *r, struct hl_record_cellinfo *buf, size_t max)
{
	const size_t n = r->strip_n < max ? r->strip_n : max;
	size_t at = (r->strip_head + HL_RECORD_STRIP - n) % HL_RECORD_STRIP;

	for (size_t i = 0; i < n; i++) {
		buf[i] = r->strip[at];
		at = (at + 1) % HL_RECORD_STRIP;
	}
	return n;
}

size_t hl_record_runs(const struct hl_record *r, const struct hl_record_run **ret)
{
	*ret = r->runs;
	return r->n_runs;
}

const char *hl_record_cell_word(char cell)
{
	switch (cell) {
	case HL_RECORD_PASS:
		return "pass";
	case HL_RECORD_FAIL:
		return "FAIL";
	case HL_RECORD_NA:
		return "not applicable";
	default:
		return "no frame yet";
	}
}

const char *hl_record_so_far_word(const struct hl_record_summary *s)
{
	if (s->failed)
		return "FAIL";
	return s->evaluated ? "pass" : "not evaluated";
}

static void write_name(const char *const *names, int i, FILE *out)
{
	if (i < 0 || !names)
		fputs("null", out);
	else
		hl_json_write_str(out, names[i]);
}

void hl_record_json_summary(const struct hl_record_summary *s, const char *const *req_ids,
			    const char *const *part_names, FILE *out)
{
	fputs("\"now\":{\"result\":", out);
	hl_json_write_str(out, hl_record_cell_word(s->now));
	fputs(",\"t_s\":", out);
	hl_json_write_num(out, s->now ? s->now_t_s : NAN, "%.4f");
	fputs(",\"requirement\":", out);
	write_name(req_ids, s->now ? s->now_req : -1, out);
	fputs(",\"part\":", out);
	write_name(part_names, s->now ? s->now_part : -1, out);
	fputs("},\"so_far\":{\"result\":", out);
	hl_json_write_str(out, hl_record_so_far_word(s));
	fprintf(out,
		",\"frames\":%llu,\"evaluated\":%llu,\"failed\":%llu,\"not_applicable\":%llu,"
		"\"longest_failing_s\":",
		(unsigned long long)s->frames, (unsigned long long)s->evaluated,
		(unsigned long long)s->failed, (unsigned long long)s->not_applicable);
	hl_json_write_num(out, s->longest_failing_s, "%.4f");
	fputs(",\"longest_failing_from_s\":", out);
	hl_json_write_num(out, s->failed ? s->longest_failing_from_s : NAN, "%.4f");
	fputs(",\"worst\":", out);
	if (!s->has_worst) {
		fputs("null", out);
	} else {
		fputs("{\"margin\":", out);
		hl_json_write_num(out, s->worst_margin, "%.6g");
		fputs(",\"requirement\":", out);
		write_name(req_ids, s->worst_req, out);
		fputs(",\"part\":", out);
		write_name(part_names, s->worst_part, out);
		fputs(",\"t_s\":", out);
		hl_json_write_num(out, s->worst_t_s, "%.4f");
		fputc('}', out);
	}
	fprintf(out, ",\"frames_unstripped\":%llu}", (unsigned long long)s->frames_unstripped);
}

static void json_modes(const struct hl_record_cellinfo *cells, size_t n,
		       hl_record_mode_name_fn mode_name, const void *ud, FILE *out)
{
	fputs(",\"modes\":[", out);
	for (size_t i = 0, j; i < n; i = j) {
		const char *name = cells[i].mode >= 0 && mode_name ? mode_name(ud, cells[i].mode) :
								     NULL;

		for (j = i + 1; j < n && cells[j].mode == cells[i].mode; j++) {
		}
		fprintf(out, "%s[%zu,%zu,", i ? "," : "", i, j - i);
		if (name)
			hl_json_write_str(out, name);
		else if (cells[i].mode >= 0)
			fprintf(out, "%d", cells[i].mode);
		else
			fputs("null", out);
		fputc(']', out);
	}
	fputc(']', out);
}

void hl_record_json_strip(const struct hl_record_cellinfo *cells, size_t n,
			  const char *const *req_ids, const char *const *part_names,
			  hl_record_mode_name_fn mode_name, const void *ud, FILE *out)
{
	size_t i = 0;
	bool first = true;

	fputs("\"cells\":\"", out);
	for (size_t k = 0; k < n; k++)
		fputc(cells[k].cell, out);
	fputs("\",\"failing\":[", out);
	while (i < n) {
		size_t j = i + 1;

		if (cells[i].cell != HL_RECORD_FAIL) {
			i++;
			continue;
		}
		while (j < n && cells[j].cell == HL_RECORD_FAIL && cells[j].req == cells[i].req &&
		       cells[j].part == cells[i].part)
			j++;
		fprintf(out, "%s[%zu,%zu,", first ? "" : ",", i, j - i);
		write_name(req_ids, cells[i].req, out);
		fputc(',', out);
		write_name(part_names, cells[i].part, out);
		fputc(']', out);
		first = false;
		i = j;
	}
	fputc(']', out);
	json_modes(cells, n, mode_name, ud, out);
}

void hl_record_json_runs(const struct hl_record_run *runs, size_t n, const char *const *req_ids,
			 const char *const *part_names, FILE *out)
{
	fputc('[', out);
	for (size_t i = 0; i < n; i++) {
		fputs(i ? ",[" : "[", out);
		hl_json_write_num(out, runs[i].t0_s, "%.4f");
		fprintf(out, ",%u,\"%c\",", runs[i].frames, runs[i].cell);
		write_name(req_ids, runs[i].req, out);
		fputc(',', out);
		write_name(part_names, runs[i].part, out);
		fputc(']', out);
	}
	fputc(']', out);
}
