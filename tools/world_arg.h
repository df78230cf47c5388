/* SPDX-License-Identifier: MIT */
/*
 * --world for the CLI (hdlamp render, glare; docs/osi.md): the scene from an ASAM OSI trace
 * (osi:file:TRACE.osi) instead of a scenario's paths, the scenario (may be none) lending the
 * ego's lamps and camera and a road. What the trace held beside the messages taken is printed
 * to stderr, each reason with its count and first fault.
 */
#ifndef HL_TOOLS_WORLD_ARG_H
#define HL_TOOLS_WORLD_ARG_H

#include "world/scenario.h"

/*
 * The scenario of world (a trace) with base (may be NULL; taken: freed here either way);
 * message: "auto" or NULL (the file name's convention), "ground-truth", "sensor-view". prog
 * names the command in messages. 0 with *ret (hl_scenario_free()), or -errno, said on stderr.
 */
int hl_tool_world_load(const char *prog, const char *world, const char *message,
		       struct hl_scenario *base, struct hl_scenario **ret);

#endif
