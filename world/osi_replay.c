/* SPDX-License-Identifier: MIT */
/* An ASAM OSI trace file as a scenario: see world/osi_replay.h. */
#include "world/osi_replay.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "world/osi_trace.h"
#include "world/track.h"

static int error(int rc, char *err, size_t size, const char *fmt, ...)
{
	va_list ap;

	if (err && size) {
		va_start(ap, fmt);
		vsnprintf(err, size, fmt, ap);
		va_end(ap);
	}
	return rc;
}

static void note(struct hl_osi_replay_report *rep, enum hl_osi_reason r, size_t i, const char *why)
{
	if (!rep->counts[r]++) {
		rep->first[r] = i;
		snprintf(rep->why[r], sizeof(rep->why[r]), "%s", why);
	}
}

/* Message i decoded into f; a reason when it is not a message of the kind. */
static enum hl_osi_reason decode(const struct hl_osi_trace *t, size_t i, enum hl_osi_kind kind,
				 struct hl_osi_frame *f, char *why, size_t size)
{
	struct hl_osi_trace_msg m;

	if (hl_osi_trace_get(t, i, &m) < 0)
		return HL_OSI_MALFORMED;
	switch (hl_osi_decode(m.buf, m.len, kind, f, why, size)) {
	case HL_OSI_DECODE_OK:
		break;
	case HL_OSI_DECODE_TOO_MANY:
		return HL_OSI_TOO_MANY;
	default:
		return HL_OSI_MALFORMED;
	}
	if (!f->has_timestamp) {
		snprintf(why, size, "no timestamp: expected one on every message");
		return HL_OSI_NO_TIMESTAMP;
	}
	return HL_OSI_OK;
}

/* The world of the first usable message, and every later message's objects cast. */
static int make_world(const struct hl_osi_trace *t, enum hl_osi_kind kind,
		      const struct hl_scenario *base, struct hl_osi_frame *f,
		      struct hl_osi_world **ret, char *err, size_t err_size)
{
	const size_t n = hl_osi_trace_count(t);
	/* first_why: "message N: " and a why whole */
	char why[HL_OSI_REPLAY_WHY] = "", first_why[HL_OSI_REPLAY_WHY + 32] = "";
	size_t i;
	int rc = -EINVAL;

	for (i = 0; i < n && !*ret; i++) {
		if (decode(t, i, kind, f, why, sizeof(why)) != HL_OSI_OK)
			rc = -EBADMSG;
		else
			rc = hl_osi_world_new(f, base, ret, why, sizeof(why));
		if (rc < 0 && !first_why[0])
			snprintf(first_why, sizeof(first_why), "message %zu: %s", i, why);
		if (rc == -ENOMEM)
			return error(rc, err, err_size, "out of memory");
	}
	if (!n)
		return error(-EINVAL, err, err_size, "no message in the file");
	if (!*ret)
		return error(rc, err, err_size, "no usable %s message; the first fault: %s",
			     hl_osi_kind_name(kind), first_why);
	for (; i < n; i++)
		if (decode(t, i, kind, f, why, sizeof(why)) == HL_OSI_OK)
			hl_osi_world_cast(*ret, f, NULL);
	return 0;
}

/* Every message into the track. */
static int fill(const struct hl_osi_trace *t, enum hl_osi_kind kind, struct hl_osi_world *w,
		struct hl_osi_frame *f, struct hl_world_track *track,
		struct hl_osi_replay_report *rep)
{
	const size_t n = hl_osi_trace_count(t);
	char why[HL_OSI_REPLAY_WHY];
	int64_t last_ns = 0;
	bool have = false;

	for (size_t i = 0; i < n; i++) {
		enum hl_osi_reason r = decode(t, i, kind, f, why, sizeof(why));
		struct hl_world_state st;
		int rc;

		if (r == HL_OSI_OK && have && f->t_ns <= last_ns) {
			snprintf(why, sizeof(why),
				 "timestamp %.9f s: not after the last taken message's %.9f s",
				 f->t_ns / 1e9, last_ns / 1e9);
			r = HL_OSI_PAST;
		}
		if (r == HL_OSI_OK) {
			if (!have)
				rep->t0_ns = f->t_ns;
			r = hl_osi_world_map(w, f, (double)(f->t_ns - rep->t0_ns) / 1e9, &st,
					     rep->counts, why, sizeof(why));
		}
		if (r != HL_OSI_OK) {
			note(rep, r, i, why);
			continue;
		}
		if (have && (double)(f->t_ns - last_ns) / 1e9 > HL_OSI_MAX_JUMP_S) {
			snprintf(why, sizeof(why), "%.9f s after the message before: over %g s",
				 (f->t_ns - last_ns) / 1e9, HL_OSI_MAX_JUMP_S);
			note(rep, HL_OSI_TIME_JUMP, i, why);
		}
		rc = hl_world_track_push(track, &st);
		if (rc < 0)
			return rc;
		rep->counts[HL_OSI_OK]++;
		have = true;
		last_ns = f->t_ns;
	}
	rep->taken = hl_world_track_count(track);
	return 0;
}

int hl_osi_replay_load(const char *path, const enum hl_osi_kind *kind,
		       const struct hl_scenario *base, struct hl_scenario **ret,
		       struct hl_osi_replay_report *rep, char *err, size_t err_size)
{
	struct hl_osi_trace_error cut = { 0, 0, 0, 0 };
	struct hl_osi_world *w = NULL;
	struct hl_world_track *track = NULL;
	struct hl_osi_frame *f = NULL;
	struct hl_osi_trace *t = NULL;
	struct hl_scenario *sc;
	int rc;

	memset(rep, 0, sizeof(*rep));
	if (kind)
		rep->kind = *kind;
	else if (hl_osi_trace_kind_from_name(path, &rep->kind) < 0)
		return error(-EINVAL, err, err_size,
			     "%s: the file name does not say the message (OSI's naming: "
			     "<timestamp>_<gt|sv>_<osi-version>_...): expected the message named "
			     "(--osi-message ground-truth|sensor-view)",
			     path);
	rc = hl_osi_trace_open(path, &t, &cut);
	if (rc < 0)
		return error(rc, err, err_size, "%s: %s", path,
			     rc == -EBADMSG ? "not an OSI trace: a message length over 64 MiB" :
					      strerror(-rc));
	if (rc == HL_OSI_TRACE_TRUNCATED) {
		char why[HL_OSI_REPLAY_WHY];

		snprintf(why, sizeof(why),
			 "the file ends in a message: at byte %" PRIu64 " expected %" PRIu64
			 " bytes, found %" PRIu64,
			 cut.offset, cut.expected, cut.found);
		note(rep, HL_OSI_TRUNCATED, hl_osi_trace_count(t), why);
	}
	rep->messages = hl_osi_trace_count(t);
	f = hl_osi_frame_new();
	rc = f ? hl_world_track_new(&track) : -ENOMEM;
	if (rc < 0) {
		error(rc, err, err_size, "out of memory");
		goto out;
	}
	rc = make_world(t, rep->kind, base, f, &w, err, err_size);
	if (rc < 0) {
		char msg[512];

		snprintf(msg, sizeof(msg), "%s", err ? err : "");
		error(rc, err, err_size, "%s: %s", path, msg);
		goto out;
	}
	rc = fill(t, rep->kind, w, f, track, rep);
	if (rc < 0) {
		error(rc, err, err_size, "%s: %s", path, strerror(-rc));
		goto out;
	}
	sc = hl_osi_world_take_scenario(w);
	{
		const struct hl_world_state *last = hl_world_track_state(track, rep->taken - 1);

		sc->duration_s = fmax(last->t_s, 1e-3);
	}
	sc->track = track;
	track = NULL;
	*ret = sc;
out:
	hl_world_track_free(track);
	hl_osi_world_free(w);
	hl_osi_frame_free(f);
	hl_osi_trace_free(t);
	return rc < 0 ? rc : 0;
}

int hl_osi_spec_parse(const char *spec, struct hl_osi_spec *ret, char *err, size_t err_size)
{
	memset(ret, 0, sizeof(*ret));
	if (!strncmp(spec, "osi:file:", 9) && spec[9]) {
		if (strlen(spec + 9) >= sizeof(ret->path))
			return error(-EINVAL, err, err_size, "'%.40s...': the path is too long",
				     spec);
		snprintf(ret->path, sizeof(ret->path), "%s", spec + 9);
		return 0;
	}
	if (!strncmp(spec, "osi:udp:", 8) && spec[8] && strlen(spec + 4) < sizeof(ret->listen)) {
		ret->udp = true;
		snprintf(ret->listen, sizeof(ret->listen), "%s", spec + 4);
		return 0;
	}
	return error(-EINVAL, err, err_size,
		     "'%s': expected osi:file:PATH (an OSI trace) or osi:udp:HOST:PORT", spec);
}
