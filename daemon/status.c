/* SPDX-License-Identifier: MIT */
#include "daemon/status.h"

#include <errno.h>
#include <inttypes.h>
#include <stddef.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include "base/clock.h"
#include "daemon/core/prom.h"
#include "base/sched.h"

struct hl_status {
	struct hl_status_sources src;
	pthread_mutex_t lock; /* guards what follows: the main thread writes, HTTP threads read */
	enum hl_failsafe failsafe;
	uint64_t reloads;
};

int hl_status_new(const struct hl_status_sources *src, enum hl_failsafe failsafe,
		  struct hl_status **ret)
{
	struct hl_status *st;

	if (src->n_lamps < 1 || src->n_lamps > HL_RING_MAX_LAMPS || !src->lamp_names)
		return -EINVAL;
	st = calloc(1, sizeof(*st));
	if (!st)
		return -ENOMEM;
	st->src = *src;
	st->failsafe = failsafe;
	if (hl_mutex_init_pi(&st->lock) < 0) {
		free(st);
		return -ENOTSUP;
	}
	*ret = st;
	return 0;
}

void hl_status_free(struct hl_status *st)
{
	if (!st)
		return;
	pthread_mutex_destroy(&st->lock);
	free(st);
}

void hl_status_reloaded(struct hl_status *st, enum hl_failsafe failsafe)
{
	pthread_mutex_lock(&st->lock);
	st->failsafe = failsafe;
	st->reloads++;
	pthread_mutex_unlock(&st->lock);
}

/* Everything the status shows, each part copied under its owner's lock. */
struct view {
	struct hl_input_status in;
	struct hl_pipeline_counts pc;
	struct hl_stream_counts sc;
	struct hl_ring_counts rc;
	struct hl_frame_pool_counts fc;
	struct hl_capture_queue_counts cc;
	enum hl_failsafe failsafe;
	uint64_t reloads;
};

static void take(struct hl_status *st, struct view *v)
{
	const struct hl_status_sources *s = &st->src;

	*v = (struct view){ .in.link_up = false };
	if (s->in)
		hl_can_input_status(s->in, &v->in);
	if (s->pipe)
		hl_pipeline_counts(s->pipe, &v->pc);
	if (s->stream)
		hl_stream_counts(s->stream, &v->sc);
	if (s->ring)
		hl_ring_counts(s->ring, &v->rc);
	if (s->pool)
		hl_frame_pool_counts(s->pool, &v->fc);
	if (s->captures)
		hl_capture_queue_counts(s->captures, &v->cc);
	pthread_mutex_lock(&st->lock);
	v->failsafe = st->failsafe;
	v->reloads = st->reloads;
	pthread_mutex_unlock(&st->lock);
}

static const char *failsafe_name(enum hl_failsafe m)
{
	return m == HL_FAILSAFE_HOLD ? "hold" : m == HL_FAILSAFE_DARK ? "dark" : "preset";
}

/* The frame stream's clients and frames (daemon/out/stream.h): "stream":{...}. */
static void stream_json(FILE *f, const struct hl_stream_counts *c)
{
	fprintf(f,
		"\"stream\":{\"clients\":%" PRIu64 ",\"clients_behind\":%" PRIu64
		",\"accepted\":%" PRIu64 ",\"refused\":%" PRIu64 ",\"dropped\":{",
		c->clients, c->clients_behind, c->accepted, c->refused);
	for (int i = 0; i < HL_STREAM_DROP_N; i++)
		fprintf(f, "%s\"%s\":%" PRIu64, i ? "," : "", hl_stream_drop_name(i),
			c->dropped[i]);
	fprintf(f,
		"},\"frames_sent\":%" PRIu64 ",\"frames_skipped\":%" PRIu64
		",\"bytes_sent\":%" PRIu64 ",\"input_reads\":%" PRIu64 "}",
		c->frames_sent, c->frames_skipped, c->bytes_sent, c->input_reads);
}

static void stream_metrics(struct hl_prom *p, const struct hl_stream_counts *c)
{
	_Static_assert(HL_STREAM_BEHIND_FRAMES == 3, "hdlamp_stream_clients_behind's help says 3");
	hl_prom_family(p, "hdlamp_stream_clients", HL_PROM_GAUGE, "Frame stream clients now.");
	hl_prom_gauge(p, "hdlamp_stream_clients", NULL, (double)c->clients);
	hl_prom_family(p, "hdlamp_stream_clients_behind", HL_PROM_GAUGE,
		       "Stream clients still sending a frame 3 or more older than the newest.");
	hl_prom_gauge(p, "hdlamp_stream_clients_behind", NULL, (double)c->clients_behind);
	hl_prom_family(p, "hdlamp_stream_clients_accepted_total", HL_PROM_COUNTER,
		       "Stream clients accepted.");
	hl_prom_counter(p, "hdlamp_stream_clients_accepted_total", NULL, c->accepted);
	hl_prom_family(p, "hdlamp_stream_clients_refused_total", HL_PROM_COUNTER,
		       "Stream clients refused: every slot held by a client not behind.");
	hl_prom_counter(p, "hdlamp_stream_clients_refused_total", NULL, c->refused);
	hl_prom_family(p, "hdlamp_stream_clients_dropped_total", HL_PROM_COUNTER,
		       "Stream clients dropped, by reason.");
	for (int i = 0; i < HL_STREAM_DROP_N; i++)
		hl_prom_counter(p, "hdlamp_stream_clients_dropped_total",
				(const char *const[]){ "reason", hl_stream_drop_name(i), NULL },
				c->dropped[i]);
	hl_prom_family(p, "hdlamp_stream_frames_sent_total", HL_PROM_COUNTER,
		       "Frames sent whole to stream clients.");
	hl_prom_counter(p, "hdlamp_stream_frames_sent_total", NULL, c->frames_sent);
	hl_prom_family(p, "hdlamp_stream_frames_skipped_total", HL_PROM_COUNTER,
		       "Frames slow stream clients skipped.");
	hl_prom_counter(p, "hdlamp_stream_frames_skipped_total", NULL, c->frames_skipped);
	hl_prom_family(p, "hdlamp_stream_sent_bytes_total", HL_PROM_COUNTER,
		       "Bytes sent to stream clients.");
	hl_prom_counter(p, "hdlamp_stream_sent_bytes_total", NULL, c->bytes_sent);
	hl_prom_family(p, "hdlamp_stream_input_reads_total", HL_PROM_COUNTER,
		       "Reads of stream clients' input (a half-close, or a client dropped).");
	hl_prom_counter(p, "hdlamp_stream_input_reads_total", NULL, c->input_reads);
}

static const char *const image_kinds[HL_IMAGE_KINDS] = { "jpeg", "png", "exr" };

/* The HTTP server's counters (daemon/out/http.h, docs/outputs.md "HTTP live view"). */
static void http_json(struct hl_http *h, FILE *f)
{
	struct hl_http_counts c;

	hl_http_counts(h, &c);
	fprintf(f,
		",\"http\":{\"requests\":%" PRIu64 ",\"errors\":%" PRIu64 ",\"overloaded\":%" PRIu64
		",\"connections\":%" PRIu64 ",\"connections_refused\":%" PRIu64
		",\"header_timeouts\":%" PRIu64 ",\"mjpeg_clients\":%" PRIu64
		",\"mjpeg_frames_sent\":%" PRIu64 ",\"mjpeg_frames_skipped\":%" PRIu64
		",\"encode_failures\":%" PRIu64 ",\"encoded\":{",
		c.requests, c.errors, c.overloaded, c.connections, c.connections_refused,
		c.header_timeouts, c.mjpeg_clients, c.mjpeg_frames_sent, c.mjpeg_frames_skipped,
		c.encode_failures);
	for (int k = 0; k < HL_IMAGE_KINDS; k++)
		fprintf(f, "%s\"%s\":%" PRIu64, k ? "," : "", image_kinds[k], c.encoded[k]);
	fputs("}}", f);
}

static void http_metrics(struct hl_http *h, struct hl_prom *p)
{
	static const struct {
		const char *name, *help;
		size_t off;
	} counters[] = {
		{ "hdlamp_http_requests_total", "HTTP requests answered, any status.",
		  offsetof(struct hl_http_counts, requests) },
		{ "hdlamp_http_errors_total", "HTTP requests answered 4xx or 5xx.",
		  offsetof(struct hl_http_counts, errors) },
		{ "hdlamp_http_overloaded_total",
		  "HTTP requests answered 503 with Retry-After: too many waited for an image, "
		  "its encode took too long, or too many streams were open.",
		  offsetof(struct hl_http_counts, overloaded) },
		{ "hdlamp_http_connections_refused_total",
		  "HTTP connections closed at once: the connection limit or the per-address one.",
		  offsetof(struct hl_http_counts, connections_refused) },
		{ "hdlamp_http_header_timeouts_total",
		  "HTTP connections closed: no whole request (headers, body) within 10 s.",
		  offsetof(struct hl_http_counts, header_timeouts) },
		{ "hdlamp_http_mjpeg_frames_sent_total", "JPEG parts sent, all MJPEG streams.",
		  offsetof(struct hl_http_counts, mjpeg_frames_sent) },
		{ "hdlamp_http_mjpeg_frames_skipped_total",
		  "Published frames an MJPEG stream did not get: it was slower.",
		  offsetof(struct hl_http_counts, mjpeg_frames_skipped) },
		{ "hdlamp_http_encode_failures_total", "Image encodes that failed.",
		  offsetof(struct hl_http_counts, encode_failures) },
	};
	struct hl_http_counts c;

	hl_http_counts(h, &c);
	for (size_t i = 0; i < sizeof(counters) / sizeof(counters[0]); i++) {
		hl_prom_family(p, counters[i].name, HL_PROM_COUNTER, counters[i].help);
		hl_prom_counter(p, counters[i].name, NULL,
				*(const uint64_t *)((const char *)&c + counters[i].off));
	}
	hl_prom_family(p, "hdlamp_http_images_encoded_total", HL_PROM_COUNTER,
		       "Images encoded for HTTP, each at most once per published frame.");
	for (int k = 0; k < HL_IMAGE_KINDS; k++)
		hl_prom_counter(p, "hdlamp_http_images_encoded_total",
				(const char *const[]){ "kind", image_kinds[k], NULL },
				c.encoded[k]);
	hl_prom_family(p, "hdlamp_http_connections", HL_PROM_GAUGE, "HTTP connections open.");
	hl_prom_gauge(p, "hdlamp_http_connections", NULL, (double)c.connections);
	hl_prom_family(p, "hdlamp_http_mjpeg_clients", HL_PROM_GAUGE, "MJPEG streams open.");
	hl_prom_gauge(p, "hdlamp_http_mjpeg_clients", NULL, (double)c.mjpeg_clients);
}

/* The pose input's counters: ,"pose":{...}; the newest pose's age (s) or -1 in *ret_age_s. */
static void pose_json(struct hl_pose_input *pi, FILE *f, double *ret_age_s)
{
	struct hl_pose_counts c;

	hl_pose_input_counts(pi, &c);
	*ret_age_s = c.have ? (double)(hl_clock_monotonic_ns() - c.t_last_ok_ns) / 1e9 : -1.0;
	fprintf(f, ",\"pose\":{\"port\":%u,\"messages\":{", hl_pose_input_port(pi));
	for (int r = 0; r < HL_POSE_N; r++)
		fprintf(f, "%s\"%s\":%" PRIu64, r ? "," : "", hl_pose_result_name(r),
			c.messages[r]);
	fputc('}', f);
	if (c.have)
		fprintf(f, ",\"t_s\":%.9g,\"age_s\":%.3f", c.t_s, *ret_age_s);
	fputc('}', f);
}

/*
 * The OSI world's counters: ,"world":{...} (docs/osi.md, "Status"): live, the newest message's
 * age (s) in *ret_age_s (or -1) and whether the world is none; a trace, its counts at load.
 */
static void world_json(struct hl_osi_input *oi, const struct hl_osi_replay_report *rep, FILE *f,
		       double *ret_age_s)
{
	struct hl_osi_input_counts c;
	const uint64_t *n = rep ? rep->counts : c.reasons;

	memset(&c, 0, sizeof(c));
	if (oi) {
		hl_osi_input_counts(oi, &c);
		*ret_age_s = c.have ? (double)(hl_clock_monotonic_ns() - c.t_last_ok_ns) / 1e9 :
				      -1.0;
		fprintf(f,
			",\"world\":{\"source\":\"osi:udp\",\"port\":%u,\"datagrams\":%" PRIu64
			",\"socket_drops\":%" PRIu64,
			hl_osi_input_port(oi), c.datagrams, c.socket_drops);
	} else {
		fprintf(f, ",\"world\":{\"source\":\"osi:file\",\"messages_in_file\":%zu",
			rep->messages);
	}
	fputs(",\"messages\":{", f);
	for (int r = 0; r < HL_OSI_REASONS; r++)
		fprintf(f, "%s\"%s\":%" PRIu64, r ? "," : "", hl_osi_reason_name(r), n[r]);
	fputc('}', f);
	if (oi && c.have)
		fprintf(f, ",\"t_s\":%.9g,\"age_s\":%.3f,\"objects\":%d,\"state\":\"%s\"", c.t_s,
			*ret_age_s, c.objects,
			*ret_age_s > hl_osi_input_timeout_s(oi) ? "none" : "live");
	else if (oi)
		fputs(",\"state\":\"none\"", f);
	fputc('}', f);
}

static void world_metrics(struct hl_osi_input *oi, const struct hl_osi_replay_report *rep,
			  struct hl_prom *p)
{
	struct hl_osi_input_counts c;
	const uint64_t *n = rep ? rep->counts : c.reasons;

	memset(&c, 0, sizeof(c));
	if (oi)
		hl_osi_input_counts(oi, &c);
	hl_prom_family(p, "hdlamp_osi_messages_total", HL_PROM_COUNTER,
		       "ASAM OSI messages, datagrams and objects by what became of them.");
	for (int r = 0; r < HL_OSI_REASONS; r++)
		hl_prom_counter(p, "hdlamp_osi_messages_total",
				(const char *const[]){ "reason", hl_osi_reason_name(r), NULL },
				n[r]);
	if (!oi)
		return;
	hl_prom_family(p, "hdlamp_osi_datagrams_total", HL_PROM_COUNTER,
		       "UDP datagrams the live OSI input received.");
	hl_prom_counter(p, "hdlamp_osi_datagrams_total", NULL, c.datagrams);
	hl_prom_family(p, "hdlamp_osi_socket_drops_total", HL_PROM_COUNTER,
		       "Datagrams the kernel dropped for a full receive buffer.");
	hl_prom_counter(p, "hdlamp_osi_socket_drops_total", NULL, c.socket_drops);
	if (c.have) {
		hl_prom_family(p, "hdlamp_osi_age_seconds", HL_PROM_GAUGE,
			       "Age of the newest good OSI message (s); none before the first.");
		hl_prom_gauge(p, "hdlamp_osi_age_seconds", NULL,
			      (double)(hl_clock_monotonic_ns() - c.t_last_ok_ns) / 1e9);
	}
}

static void pose_metrics(struct hl_pose_input *pi, struct hl_prom *p)
{
	struct hl_pose_counts c;

	hl_pose_input_counts(pi, &c);
	hl_prom_family(p, "hdlamp_pose_messages_total", HL_PROM_COUNTER,
		       "Pose input datagrams by result.");
	for (int r = 0; r < HL_POSE_N; r++)
		hl_prom_counter(p, "hdlamp_pose_messages_total",
				(const char *const[]){ "result", hl_pose_result_name(r), NULL },
				c.messages[r]);
	if (c.have)
		hl_prom_family(p, "hdlamp_pose_age_seconds", HL_PROM_GAUGE,
			       "Age of the newest good pose message (s); none before the first.");
	if (c.have)
		hl_prom_gauge(p, "hdlamp_pose_age_seconds", NULL,
			      (double)(hl_clock_monotonic_ns() - c.t_last_ok_ns) / 1e9);
}

/* The records' summaries and strips, copied under their lock (verdict_records.h). */
struct so_far_copy {
	struct hl_verdicts_so_far sf[HL_VERDICTS_MAX_SETS];
	struct hl_record_cellinfo *cells; /* HL_RECORD_STRIP per set */
};

static void copy_records(void *ud, const struct hl_record *const *records, int n)
{
	struct so_far_copy *c = ud;

	for (int i = 0; i < n && i < HL_VERDICTS_MAX_SETS; i++) {
		struct hl_record_cellinfo *cells = c->cells + (size_t)i * HL_RECORD_STRIP;

		hl_record_summary(records[i], &c->sf[i].sum);
		c->sf[i].n_strip = hl_record_strip(records[i], cells, HL_RECORD_STRIP);
		c->sf[i].strip = cells;
	}
}

/* The verdicts of the newest frame fr with each set's record (now, so far, the strip). */
static void verdicts_json(const struct hl_status_sources *s, const struct hl_frame *fr, FILE *f)
{
	struct hl_verdict_records *rec = hl_pipeline_records(s->pipe);
	const int n = hl_verdicts_n_sets(s->verdicts);
	struct so_far_copy *c = rec ? calloc(1, sizeof(*c)) : NULL;

	if (c)
		c->cells = calloc((size_t)(n > 0 ? n : 1) * HL_RECORD_STRIP, sizeof(*c->cells));
	if (c && c->cells) {
		hl_verdict_records_read(rec, copy_records, c);
		hl_verdicts_json(s->verdicts, fr, c->sf, f);
	} else {
		hl_verdicts_json(s->verdicts, fr, NULL, f); /* no records, or no memory for them */
	}
	if (c)
		free(c->cells);
	free(c);
}
int hl_status_json(struct hl_status *st, char *buf, size_t size)
{
	const struct hl_status_sources *s = &st->src;
	FILE *f = fmemopen(buf, size, "w");
	struct view v;
	long n;

	if (!f)
		return -errno;
	take(st, &v);
	fprintf(f,
		"{\"renderer\":\"%s\",\"input\":{\"source\":\"%s\",\"link\":\"%s\",\"bus\":\"%s\"},\"lamps\":[",
		s->pipe ? hl_pipeline_describe(s->pipe) : "off", s->input_name,
		v.in.link_up ? "up" : "down", v.in.bus);
	for (int l = 0; l < s->n_lamps; l++) {
		const struct hl_lamp_counters *c = &v.in.lamps[l];
		/* the renderer's counts exist for the lamps it lights */
		const uint64_t fs = l < HL_FRAME_MAX_LAMPS ? v.pc.failsafe_frames[l] : 0;
		const uint64_t nr = l < HL_FRAME_MAX_LAMPS ? v.pc.cycles_not_rendered[l] : 0;

		fprintf(f,
			"%s{\"name\":\"%s\",\"stale\":%s,\"failsafe\":%s,\"cycles\":%" PRIu64
			",\"crc_errors\":%" PRIu64 ",\"incomplete\":%" PRIu64
			",\"lost_cycles\":%" PRIu64 ",\"repeated_frames\":%" PRIu64
			",\"stale_events\":%" PRIu64 ",\"failsafe_frames\":%" PRIu64
			",\"cycles_not_rendered\":%" PRIu64 "}",
			l ? "," : "", s->lamp_names[l], v.in.stale[l] ? "true" : "false",
			v.in.stale[l] ? "true" : "false", c->cycles, c->crc_errors, c->incomplete,
			c->lost_cycles, c->repeated_frames, c->stale_events, fs, nr);
	}
	fprintf(f,
		"],\"failsafe_mode\":\"%s\",\"frames\":{\"rendered\":%" PRIu64
		",\"published\":%" PRIu64 ",\"not_published\":%" PRIu64
		",\"render_ms_last\":%.3f,\"render_ms_max\":%.3f},"
		"\"ring\":{\"pushed\":%" PRIu64 ",\"consumed\":%" PRIu64 ",\"superseded\":%" PRIu64
		",\"dropped\":%" PRIu64 "},",
		failsafe_name(v.failsafe), v.pc.frames + v.pc.not_published, v.fc.published,
		v.pc.not_published, v.pc.render_ms_last, v.pc.render_ms_max, v.rc.pushed,
		v.rc.consumed, v.rc.superseded, v.rc.dropped);
	stream_json(f, &v.sc);
	fprintf(f,
		",\"captures\":%" PRIu64 ",\"captures_failed\":%" PRIu64
		",\"captures_refused\":%" PRIu64 ",\"reloads\":%" PRIu64,
		v.cc.written, v.cc.failed, v.cc.refused, v.reloads);
	if (s->gpio) {
		struct hl_gpio_counts gc;

		hl_gpio_counts(s->gpio, &gc);
		fprintf(f,
			",\"gpio\":{\"strobe_toggles\":%" PRIu64 ",\"strobe_errors\":%" PRIu64
			",\"trigger_edges\":%" PRIu64 ",\"trigger_lost\":%" PRIu64 "}",
			gc.strobe_toggles, gc.strobe_errors, gc.trigger_edges, gc.trigger_lost);
	}
	if (s->http)
		http_json(s->http, f);
	if (s->verdicts && s->pipe && s->pool) {
		/* the newest frame's results, held while they are written */
		struct hl_frame *fr = hl_frame_pool_get(s->pool, 0, 0);

		fprintf(f, ",\"verdict_ms_last\":%.4f,\"verdict_ms_max\":%.4f,",
			v.pc.verdict_ms_last, v.pc.verdict_ms_max);
		verdicts_json(s, fr, f);
		hl_frame_pool_release(s->pool, fr);
	}
	if (s->glare && s->pool) {
		/* the newest frame's scene and glare, held while they are written */
		struct hl_frame *fr = hl_frame_pool_get(s->pool, 0, 0);
		double age_s = -1.0;

		if (s->pose)
			pose_json(s->pose, f, &age_s);
		if (s->osi || s->osi_replay)
			world_json(s->osi, s->osi_replay, f, &age_s);
		hl_glare_live_status_json(s->glare, fr, age_s, f);
		hl_frame_pool_release(s->pool, fr);
	}
	if (s->restbus)
		hl_restbus_status_json(s->restbus, f);
	hl_live_ecu_status_json(s->ecu, f); /* nothing without one */
	hl_suite_live_status_json(s->suite, f);
	if (s->loop)
		hl_loop_latency_status_json(s->loop, f);
	fputc('}', f);
	n = ftell(f);
	fclose(f);
	return n >= (long)size - 1 ? -ENOBUFS : (int)n;
}

/* One counter family with a sample per lamp. */
static void lamp_counter(struct hl_prom *p, const struct hl_status_sources *s, const char *name,
			 const char *help, const uint64_t *values, size_t stride)
{
	hl_prom_family(p, name, HL_PROM_COUNTER, help);
	for (int l = 0; l < s->n_lamps; l++)
		hl_prom_counter(p, name, (const char *const[]){ "lamp", s->lamp_names[l], NULL },
				*(const uint64_t *)((const char *)values + (size_t)l * stride));
}

int hl_status_metrics(struct hl_status *st, char *buf, size_t size)
{
	const struct hl_status_sources *s = &st->src;
	const size_t lc = sizeof(struct hl_lamp_counters);
	struct hl_prom p;
	struct view v;

	take(st, &v);
	hl_prom_init(&p, buf, size);
	lamp_counter(&p, s, "hdlamp_cycles_total", "Complete lamp cycles.", &v.in.lamps[0].cycles,
		     lc);
	lamp_counter(&p, s, "hdlamp_crc_errors_total", "Frames dropped for a wrong E2E CRC.",
		     &v.in.lamps[0].crc_errors, lc);
	lamp_counter(&p, s, "hdlamp_incomplete_cycles_total",
		     "Cycles abandoned for a missing part.", &v.in.lamps[0].incomplete, lc);
	lamp_counter(&p, s, "hdlamp_lost_cycles_total", "Alive counter values never seen.",
		     &v.in.lamps[0].lost_cycles, lc);
	lamp_counter(&p, s, "hdlamp_duplicate_frames_total", "Repeated frames ignored.",
		     &v.in.lamps[0].repeated_frames, lc);
	lamp_counter(&p, s, "hdlamp_stale_events_total", "Times the lamp became stale.",
		     &v.in.lamps[0].stale_events, lc);
	hl_prom_family(&p, "hdlamp_cycles_not_rendered_total", HL_PROM_COUNTER,
		       "Complete cycles no rendered frame showed.");
	for (int l = 0; l < s->n_lamps && l < HL_FRAME_MAX_LAMPS; l++)
		hl_prom_counter(&p, "hdlamp_cycles_not_rendered_total",
				(const char *const[]){ "lamp", s->lamp_names[l], NULL },
				v.pc.cycles_not_rendered[l]);
	hl_prom_family(&p, "hdlamp_lamp_stale", HL_PROM_GAUGE,
		       "Whether the lamp is stale (fail-safe active).");
	for (int l = 0; l < s->n_lamps; l++)
		hl_prom_gauge(&p, "hdlamp_lamp_stale",
			      (const char *const[]){ "lamp", s->lamp_names[l], NULL },
			      v.in.stale[l] ? 1 : 0);
	hl_prom_family(&p, "hdlamp_bus_state", HL_PROM_GAUGE,
		       "The CAN input's state (1 for the current one).");
	hl_prom_gauge(&p, "hdlamp_bus_state", (const char *const[]){ "state", v.in.bus, NULL }, 1);
	hl_prom_family(&p, "hdlamp_link_up", HL_PROM_GAUGE, "Whether the CAN input is open.");
	hl_prom_gauge(&p, "hdlamp_link_up", NULL, v.in.link_up ? 1 : 0);
	hl_prom_family(&p, "hdlamp_ring_snapshots_total", HL_PROM_COUNTER,
		       "Ring snapshots by fate.");
	hl_prom_counter(&p, "hdlamp_ring_snapshots_total",
			(const char *const[]){ "fate", "consumed", NULL }, v.rc.consumed);
	hl_prom_counter(&p, "hdlamp_ring_snapshots_total",
			(const char *const[]){ "fate", "superseded", NULL }, v.rc.superseded);
	hl_prom_counter(&p, "hdlamp_ring_snapshots_total",
			(const char *const[]){ "fate", "dropped", NULL }, v.rc.dropped);
	hl_prom_family(&p, "hdlamp_kernel_drops_total", HL_PROM_COUNTER,
		       "Frames the kernel dropped (SO_RXQ_OVFL).");
	hl_prom_counter(&p, "hdlamp_kernel_drops_total", NULL, v.in.socket.kernel_drops);
	hl_prom_family(&p, "hdlamp_frames_total", HL_PROM_COUNTER,
		       "Frames rendered and published.");
	hl_prom_counter(&p, "hdlamp_frames_total", NULL, v.pc.frames);
	stream_metrics(&p, &v.sc);
	hl_prom_family(&p, "hdlamp_captures_total", HL_PROM_COUNTER,
		       "Captures by result: written, failed (nothing kept), refused (queue full).");
	hl_prom_counter(&p, "hdlamp_captures_total",
			(const char *const[]){ "result", "written", NULL }, v.cc.written);
	hl_prom_counter(&p, "hdlamp_captures_total",
			(const char *const[]){ "result", "failed", NULL }, v.cc.failed);
	hl_prom_counter(&p, "hdlamp_captures_total",
			(const char *const[]){ "result", "refused", NULL }, v.cc.refused);
	if (s->pipe) {
		hl_prom_family(&p, "hdlamp_render_seconds", HL_PROM_HISTOGRAM,
			       "Time to render a frame (seconds).");
		hl_prom_histogram(&p, "hdlamp_render_seconds", NULL, &v.pc.render_seconds);
	}
	if (s->http)
		http_metrics(s->http, &p);
	if (s->verdicts && s->pipe && s->pool) {
		struct hl_frame *fr = hl_frame_pool_get(s->pool, 0, 0);

		hl_verdicts_metrics(s->verdicts, fr, v.pc.verdict_frames,
				    v.pc.verdict_failed_frames, &p);
		hl_frame_pool_release(s->pool, fr);
	}
	if (s->glare && s->pool) {
		struct hl_frame *fr = hl_frame_pool_get(s->pool, 0, 0);

		hl_glare_live_metrics(s->glare, fr, &p);
		hl_frame_pool_release(s->pool, fr);
	}
	if (s->pose)
		pose_metrics(s->pose, &p);
	if (s->osi || s->osi_replay)
		world_metrics(s->osi, s->osi_replay, &p);
	if (s->restbus)
		hl_restbus_metrics(s->restbus, &p);
	if (s->loop)
		hl_loop_latency_metrics(s->loop, &p);
	hl_suite_live_metrics(s->suite, &p);
	return hl_prom_end(&p);
}
