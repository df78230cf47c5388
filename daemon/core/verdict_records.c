/* SPDX-License-Identifier: MIT */
#include "daemon/core/verdict_records.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>

#include "base/sched.h"

struct hl_verdict_records {
	const struct hl_verdicts *v;
	int n;
	struct hl_record *rec[HL_VERDICTS_MAX_SETS];
	pthread_mutex_t lock;
	int64_t t0_ns; /* the first evaluated frame's cycle time */
	bool started;
};

int hl_verdict_records_new(const struct hl_verdicts *v, struct hl_verdict_records **ret)
{
	struct hl_verdict_records *r = calloc(1, sizeof(*r));
	int rc;

	if (!r)
		return -ENOMEM;
	r->v = v;
	r->n = hl_verdicts_n_sets(v);
	for (int i = 0; i < r->n; i++) {
		rc = hl_record_new(HL_VERDICT_RECORDS_RUNS, &r->rec[i]);
		if (rc < 0)
			goto err_free;
	}
	rc = hl_mutex_init_pi(&r->lock);
	if (rc < 0)
		goto err_free;
	*ret = r;
	return 0;
err_free:
	for (int i = 0; i < r->n; i++)
		hl_record_free(r->rec[i]);
	free(r);
	return rc;
}

void hl_verdict_records_free(struct hl_verdict_records *r)
{
	if (!r)
		return;
	for (int i = 0; i < r->n; i++)
		hl_record_free(r->rec[i]);
	pthread_mutex_destroy(&r->lock);
	free(r);
}

/* Set i's cell of frame f: its deciding requirement is the smallest margin over its parts. */
static void cell_of(const struct hl_verdicts *v, int i, const struct hl_frame *f, double t_s,
		    struct hl_record_frame *ret)
{
	const int n_req = hl_verdicts_set(v, i)->n_requirements;

	*ret = (struct hl_record_frame){ .t_s = t_s,
					 .cell = HL_RECORD_NA,
					 .req = -1,
					 .part = -1,
					 .margin = NAN,
					 .mode = f->beam_mode < 0 || f->beam_mode > INT32_MAX ?
							 -1 :
							 (int)f->beam_mode };
	if (!(f->hdr.sets_evaluated & (1u << i)))
		return;
	ret->cell = (f->hdr.sets_failed & (1u << i)) ? HL_RECORD_FAIL : HL_RECORD_PASS;
	for (int j = 0; j < hl_verdicts_n_parts(v, i); j++) {
		const struct hl_req_result *res = &f->results[hl_verdicts_part(v, i, j)->first];

		for (int k = 0; k < n_req; k++)
			if (!isnan(res[k].margin) &&
			    (ret->req < 0 || res[k].margin < ret->margin)) {
				ret->margin = res[k].margin;
				ret->req = k;
				ret->part = j;
			}
	}
}

void hl_verdict_records_add(struct hl_verdict_records *r, const struct hl_frame *f)
{
	struct hl_record_frame cells[HL_VERDICTS_MAX_SETS];
	double t_s;

	if (!r->started) {
		r->started = true; /* the render thread's own fields */
		r->t0_ns = f->hdr.t_cycle_rx_ns;
	}
	t_s = (double)(f->hdr.t_cycle_rx_ns - r->t0_ns) / 1e9;
	for (int i = 0; i < r->n; i++)
		cell_of(r->v, i, f, t_s, &cells[i]);
	pthread_mutex_lock(&r->lock);
	for (int i = 0; i < r->n; i++)
		hl_record_add(r->rec[i], &cells[i]);
	pthread_mutex_unlock(&r->lock);
}

void hl_verdict_records_read(struct hl_verdict_records *r,
			     void (*fn)(void *ud, const struct hl_record *const *records, int n),
			     void *ud)
{
	pthread_mutex_lock(&r->lock);
	fn(ud, (const struct hl_record *const *)r->rec, r->n);
	pthread_mutex_unlock(&r->lock);
}

void hl_verdict_records_json_runs(const struct hl_verdicts *v, int set, const struct hl_record *rec,
				  FILE *out)
{
	const char *req_ids[HL_REG_MAX_REQUIREMENTS], *part_names[HL_FRAME_MAX_LAMPS];
	const struct hl_record_run *runs;
	const size_t n = hl_record_runs(rec, &runs);

	hl_verdicts_names(v, set, req_ids, part_names);
	fputs("\"strip_runs\":", out);
	hl_record_json_runs(runs, n, req_ids, part_names, out);
}
