/* SPDX-License-Identifier: MIT */
/* --world for the CLI: see tools/world_arg.h. */
#include "tools/world_arg.h"

#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "world/osi_replay.h"

int hl_tool_world_load(const char *prog, const char *world, const char *message,
		       struct hl_scenario *base, struct hl_scenario **ret)
{
	struct hl_osi_replay_report *rep = calloc(1, sizeof(*rep));
	struct hl_osi_spec spec;
	enum hl_osi_kind kind;
	char err[1024];
	int rc;

	if (!rep) {
		rc = -ENOMEM;
		fprintf(stderr, "%s: out of memory\n", prog);
		goto out;
	}
	rc = hl_osi_spec_parse(world, &spec, err, sizeof(err));
	if (rc == 0 && spec.udp) {
		snprintf(err, sizeof(err),
			 "'%s': the CLI reads a trace (osi:file:PATH); a live stream is hdlampd's "
			 "(scene.world)",
			 world);
		rc = -EINVAL;
	}
	if (rc == 0 && message && strcmp(message, "auto") &&
	    hl_osi_kind_parse(message, &kind) < 0) {
		snprintf(err, sizeof(err),
			 "--osi-message '%s': expected auto, ground-truth or sensor-view", message);
		rc = -EINVAL;
	}
	if (rc < 0) {
		fprintf(stderr, "%s: --world %s\n", prog, err);
		goto out;
	}
	rc = hl_osi_replay_load(spec.path, message && strcmp(message, "auto") ? &kind : NULL, base,
				ret, rep, err, sizeof(err));
	if (rc < 0) {
		fprintf(stderr, "%s: --world: %s\n", prog, err);
		goto out;
	}
	fprintf(stderr, "%s: %s: %zu %s messages, %zu taken, %.3f s\n", prog, spec.path,
		rep->messages, hl_osi_kind_name(rep->kind), rep->taken, (*ret)->duration_s);
	for (int r = 1; r < HL_OSI_REASONS; r++)
		if (rep->counts[r])
			fprintf(stderr, "%s: %s: %" PRIu64 " %s; the first, message %zu: %s\n",
				prog, spec.path, rep->counts[r], hl_osi_reason_name(r),
				rep->first[r],
				rep->why[r][0] ? rep->why[r] : "(an object left out)");
out:
	free(rep);
	hl_scenario_free(base);
	return rc;
}
