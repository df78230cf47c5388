/* SPDX-License-Identifier: MIT */
/* hdlampd --no-render: the JSON lines of the decoded cycles and events, and the summary. */
#include "daemon/core/decode_report.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "can/socket.h"
#include "base/json_write.h"

static void print_cycle(const struct hl_assembler *a, const struct hl_snapshot *s, int l)
{
	const int n = hl_assembler_n_sources(a, l);
	const float *i = s->i + (size_t)l * s->n_sources;

	printf("{\"lamp\":\"%s\",\"seq\":%" PRIu64 ",\"counter\":%u,\"t_rx_ns\":%" PRId64
	       ",\"t_done_ns\":%" PRId64 ",\"i\":[",
	       hl_assembler_lamp_name(a, l), s->lamps[l].cycle_seq, s->lamps[l].counter,
	       s->lamps[l].t_rx_first_ns, s->lamps[l].t_complete_ns);
	for (int k = 0; k < n; k++)
		printf("%s%.9g", k ? "," : "", i[k]);
	printf("]}\n");
}

/* A link or bus event line; the interface name escaped (a kernel name may hold a '"'). */
static void event_line(const char *event, const char *iface, const char *state, const char *error,
		       int64_t t_ns)
{
	printf("{\"event\":\"%s\",\"iface\":", event);
	hl_json_write_str(stdout, iface);
	printf(",\"state\":\"%s\"", state);
	if (error) {
		fputs(",\"error\":", stdout);
		hl_json_write_str(stdout, error);
	} else if (strcmp(event, "link") == 0) {
		fputs(",\"error\":\"\"", stdout);
	}
	printf(",\"t_ns\":%" PRId64 "}\n", t_ns);
}

bool hl_decode_report(const char *iface, bool print_cycles, const struct hl_assembler *a,
		      const struct hl_snapshot *s, struct hl_decode_seen *seen)
{
	if ((s->status & HL_INPUT_LINK_UP) != (seen->status & HL_INPUT_LINK_UP) ||
	    s->link_errno != seen->link_errno)
		event_line("link", iface, (s->status & HL_INPUT_LINK_UP) ? "up" : "down",
			   s->link_errno ? strerror(s->link_errno) : NULL, s->t_event_ns);
	if (s->bus != seen->bus)
		event_line("bus", iface, hl_can_bus_state_name(s->bus), NULL, s->t_event_ns);
	for (int l = 0; l < hl_assembler_n_lamps(a); l++) {
		const bool was_stale = seen->lamp_status[l] & HL_LAMP_STALE;
		const bool stale = s->lamps[l].status & HL_LAMP_STALE;

		if (s->lamps[l].cycle_seq != seen->cycle_seq[l] && print_cycles)
			print_cycle(a, s, l);
		if (stale != was_stale)
			printf("{\"event\":\"%s\",\"lamp\":\"%s\",\"t_ns\":%" PRId64 "}\n",
			       stale ? "stale" : "recovered", hl_assembler_lamp_name(a, l),
			       s->t_event_ns);
		seen->cycle_seq[l] = s->lamps[l].cycle_seq;
		seen->lamp_status[l] = s->lamps[l].status;
	}
	seen->status = s->status;
	seen->bus = s->bus;
	seen->link_errno = s->link_errno;
	return s->status & HL_INPUT_DONE;
}

void hl_decode_summary(const struct hl_assembler *a, const struct hl_ring *ring,
		       struct hl_can_input *in)
{
	struct hl_ring_counts rc;
	struct hl_input_status st;

	hl_ring_counts(ring, &rc);
	hl_can_input_status(in, &st);
	printf("{\"event\":\"summary\",\"lamps\":{");
	for (int l = 0; l < st.n_lamps; l++) {
		const struct hl_lamp_counters *c = &st.lamps[l];

		printf("%s\"%s\":{\"frames\":%" PRIu64 ",\"cycles\":%" PRIu64
		       ",\"crc_errors\":%" PRIu64 ",\"incomplete\":%" PRIu64
		       ",\"lost_cycles\":%" PRIu64 ",\"repeated_frames\":%" PRIu64
		       ",\"out_of_range\":%" PRIu64 ",\"stale_events\":%" PRIu64
		       ",\"recoveries\":%" PRIu64 ",\"stale\":%s}",
		       l ? "," : "", hl_assembler_lamp_name(a, l), c->frames, c->cycles,
		       c->crc_errors, c->incomplete, c->lost_cycles, c->repeated_frames,
		       c->out_of_range, c->stale_events, c->recoveries,
		       st.stale[l] ? "true" : "false");
	}
	printf("},");
	hl_can_input_report(in, stdout);
	printf(",\"ring\":{\"pushed\":%" PRIu64 ",\"consumed\":%" PRIu64 ",\"superseded\":%" PRIu64
	       ",\"dropped\":%" PRIu64 "}}\n",
	       rc.pushed, rc.consumed, rc.superseded, rc.dropped);
}
