/* SPDX-License-Identifier: MIT */
/* The closed-loop run's report from hdlampd's objects: see daemon/run_report.h. */
#include "daemon/run_report.h"
#include "daemon/loop/loop_junit.h"

#include <stdio.h>
#include <string.h>

void hl_run_report_collect(const struct hl_run_report_sources *s, struct hl_loop_report *ret)
{
	struct hl_pipeline_counts pc;
	struct hl_input_status st;
	struct hl_ring_counts rc;

	hl_pipeline_counts(s->pipe, &pc);
	hl_can_input_status(s->in, &st);
	hl_ring_counts(s->ring, &rc);
	*ret = (struct hl_loop_report){
		.scenario_path = s->scenario_path,
		.sc = s->sc,
		.glare_set = s->glare_set,
		.end = s->end,
		.ecu = s->ecu,
		.ecu_error = s->ecu_error,
		.n_lamps = s->n_lamps,
		.lamp_names = s->lamp_names,
		.frames = pc.frames,
		.not_published = pc.not_published,
		.render_ms_max = pc.render_ms_max,
		.snapshots_pushed = rc.pushed,
		.snapshots_superseded = rc.superseded,
		.snapshots_dropped = rc.dropped,
		.verdicts = s->verdicts,
		.records = s->pipe ? hl_pipeline_records(s->pipe) : NULL,
		.loop = s->loop,
	};
	for (int l = 0; l < s->n_lamps && l < HL_FRAME_MAX_LAMPS; l++) {
		ret->lamp[l] = st.lamps[l];
		ret->cycles_not_rendered[l] = pc.cycles_not_rendered[l];
		ret->failsafe_frames[l] = pc.failsafe_frames[l];
	}
	memcpy(ret->verdict_frames, pc.verdict_frames, sizeof(ret->verdict_frames));
	memcpy(ret->verdict_failed_frames, pc.verdict_failed_frames,
	       sizeof(ret->verdict_failed_frames));
	if (s->restbus) {
		struct hl_restbus_counts rb;

		hl_restbus_counts(s->restbus, &rb);
		ret->have_restbus = true;
		ret->restbus.camera_cycles = rb.camera_cycles;
		ret->restbus.vehicle_cycles = rb.vehicle_cycles;
		ret->restbus.overruns = rb.overruns;
		ret->restbus.tx_full = rb.tx_full;
		ret->restbus.tx_errors = rb.tx_errors;
		ret->restbus.link_down = rb.link_down;
	}
}

bool hl_run_report_passed(const struct hl_run_report_sources *s)
{
	struct hl_loop_report r;

	hl_run_report_collect(s, &r);
	return hl_loop_report_passed(&r);
}

void hl_run_report_json(const struct hl_run_report_sources *s, FILE *f)
{
	struct hl_loop_report r;

	hl_run_report_collect(s, &r);
	hl_loop_report_json(&r, f);
}

int hl_run_report_write(const struct hl_run_report_sources *s, const char *path)
{
	struct hl_loop_report r;

	hl_run_report_collect(s, &r);
	return hl_loop_report_write(&r, path);
}

int hl_run_report_end(const struct hl_run_report_sources *s, const char *path, const char *junit,
		      bool exit_at_end, int code)
{
	bool passed;
	int rc;

	hl_loop_latency_finish(s->loop);
	if (!path[0] && !junit[0] && !exit_at_end)
		return code;
	passed = hl_run_report_passed(s);
	if (path[0]) {
		rc = hl_run_report_write(s, path);
		if (rc < 0) {
			fprintf(stderr, "hdlampd: loop.report '%s': %s\n", path, strerror(-rc));
			return 1;
		}
	}
	if (junit[0]) {
		struct hl_loop_report r;

		hl_run_report_collect(s, &r);
		rc = hl_loop_junit_write(&r, s->ecu_error, junit);
		if (rc < 0) {
			fprintf(stderr, "hdlampd: loop.junit '%s': %s\n", junit, strerror(-rc));
			return 1;
		}
	}
	fprintf(stderr, "hdlampd: run ended (%s): verdict %s%s%s\n", s->end,
		passed ? "held" : "FAILED", path[0] ? "; report in " : "", path);
	return code == 0 && !passed ? 3 : code;
}
