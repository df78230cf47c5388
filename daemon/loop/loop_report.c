/* SPDX-License-Identifier: MIT */
/* The closed-loop run's report: see daemon/loop/loop_report.h. */
#include "daemon/loop/loop_report.h"
#include "base/file_replace.h"
#include "base/json_write.h"

#include <errno.h>
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A set's record in the report: now, so far and the whole run's strip (verdict_records.h). */
struct report_set {
	const struct hl_verdicts *v;
	int set;
	FILE *f;
};

static void write_record(void *ud, const struct hl_record *const *records, int n)
{
	const struct report_set *rs = ud;
	const char *req_ids[HL_REG_MAX_REQUIREMENTS], *part_names[HL_FRAME_MAX_LAMPS];
	struct hl_record_summary sum;

	if (rs->set >= n)
		return;
	hl_record_summary(records[rs->set], &sum);
	hl_verdicts_names(rs->v, rs->set, req_ids, part_names);
	fputc(',', rs->f);
	hl_record_json_summary(&sum, req_ids, part_names, rs->f);
	fputc(',', rs->f);
	hl_verdict_records_json_runs(rs->v, rs->set, records[rs->set], rs->f);
}

/* Why the verdict failed, as a mask of these. */
enum {
	NO_FRAMES = 1,
	NOT_JUDGED = 2,
	SET_FAILED = 4,
	GLARE_FAILED = 8,
	ECU_FAILED = 16,
};

static unsigned failures(const struct hl_loop_report *s)
{
	struct hl_loop_counts lc;
	unsigned why = 0;

	hl_loop_latency_counts(s->loop, &lc);
	if (s->frames == 0)
		why |= NO_FRAMES;
	if (lc.frames_dropped || lc.frames_judged != lc.frames_in)
		why |= NOT_JUDGED;
	for (int i = 0; s->verdicts && i < hl_verdicts_n_sets(s->verdicts); i++)
		if (s->verdict_failed_frames[i])
			why |= SET_FAILED;
	if (!hl_loop_latency_passed(s->loop))
		why |= GLARE_FAILED;
	if (s->ecu_error)
		why |= ECU_FAILED;
	return why;
}

bool hl_loop_report_passed(const struct hl_loop_report *s)
{
	return failures(s) == 0;
}

void hl_loop_report_json(const struct hl_loop_report *s, FILE *f)
{
	static const char *const reasons[] = {
		"no frame rendered",
		"frames not judged (the hand-over ring was full)",
		"a verdict set failed on a frame",
		("a road user's glare over its limit after the reaction time (or, without a "
		 "restbus, at all)"),
		"the ECU in the loop failed: the run did not reach the scenario's end",
	};
	const unsigned why = failures(s);
	bool first = true;

	fputs("{\"report\":\"hdlamp closed-loop run\",\"version\":1,\"scenario\":", f);
	hl_json_write_str(f, s->scenario_path);
	fputs(",\"title\":", f);
	hl_json_write_str(f, s->sc->title);
	fprintf(f, ",\"duration_s\":%.6g,\"end\":", s->sc->duration_s);
	hl_json_write_str(f, s->end);
	if (s->ecu) {
		fputs(",\"ecu\":", f);
		hl_json_write_str(f, s->ecu);
	}
	if (s->ecu_error) {
		fputs(",\"ecu_error\":", f);
		hl_json_write_str(f, s->ecu_error);
	}
	fprintf(f,
		",\"frames\":{\"rendered\":%" PRIu64 ",\"not_published\":%" PRIu64
		",\"render_ms_max\":%.3f},\"snapshots\":{\"pushed\":%" PRIu64
		",\"superseded\":%" PRIu64 ",\"dropped\":%" PRIu64 "},\"cycles\":{",
		s->frames, s->not_published, s->render_ms_max, s->snapshots_pushed,
		s->snapshots_superseded, s->snapshots_dropped);
	for (int l = 0; l < s->n_lamps; l++) {
		const struct hl_lamp_counters *lc = &s->lamp[l];
		const uint64_t nr = s->cycles_not_rendered[l];

		fprintf(f, "%s", l ? "," : "");
		hl_json_write_str(f, s->lamp_names[l]);
		fprintf(f,
			":{\"complete\":%" PRIu64 ",\"rendered\":%" PRIu64
			",\"not_rendered\":%" PRIu64 ",\"lost\":%" PRIu64 ",\"incomplete\":%" PRIu64
			",\"crc_errors\":%" PRIu64 ",\"failsafe_frames\":%" PRIu64 "}",
			lc->cycles, lc->cycles >= nr ? lc->cycles - nr : 0, nr, lc->lost_cycles,
			lc->incomplete, lc->crc_errors, s->failsafe_frames[l]);
	}
	fputs("},\"verdict_sets\":[", f);
	for (int i = 0; s->verdicts && i < hl_verdicts_n_sets(s->verdicts); i++) {
		fprintf(f, "%s{\"id\":", i ? "," : "");
		hl_json_write_str(f, hl_verdicts_set(s->verdicts, i)->id);
		fprintf(f,
			",\"frames\":%" PRIu64 ",\"passed\":%" PRIu64 ",\"failed\":%" PRIu64
			",\"held\":%s",
			s->verdict_frames[i], s->verdict_frames[i] - s->verdict_failed_frames[i],
			s->verdict_failed_frames[i],
			s->verdict_failed_frames[i] ? "false" : "true");
		if (s->records) {
			struct report_set rs = { s->verdicts, i, f };

			hl_verdict_records_read(s->records, write_record, &rs);
		}
		fputc('}', f);
	}
	fputs("],\"glare_set\":", f);
	hl_json_write_str(f, s->glare_set);
	fputc(',', f);
	hl_loop_latency_report_json(s->loop, f);
	if (s->have_restbus) {
		fprintf(f,
			",\"restbus\":{\"camera_cycles\":%" PRIu64 ",\"vehicle_cycles\":%" PRIu64
			",\"overruns\":%" PRIu64 ",\"tx_full\":%" PRIu64 ",\"tx_errors\":%" PRIu64
			",\"link_down\":%" PRIu64 "}",
			s->restbus.camera_cycles, s->restbus.vehicle_cycles, s->restbus.overruns,
			s->restbus.tx_full, s->restbus.tx_errors, s->restbus.link_down);
	}
	fprintf(f, ",\"verdict\":%s,\"failed_because\":[", why ? "false" : "true");
	for (unsigned b = 0; b < sizeof(reasons) / sizeof(reasons[0]); b++) {
		if (!(why & (1u << b)))
			continue;
		fprintf(f, "%s\"%s\"", first ? "" : ",", reasons[b]);
		first = false;
	}
	fputs("]}\n", f);
}

static void write_json(void *ctx, FILE *f)
{
	hl_loop_report_json(ctx, f);
}

int hl_loop_report_write(const struct hl_loop_report *r, const char *path)
{
	return hl_file_replace(path, write_json, (void *)r);
}
