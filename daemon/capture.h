/* SPDX-License-Identifier: MIT */
/*
 * Captures: the newest published frame written to a new directory under the capture
 * directory: hdr.exr (linear luminance RGBA), lux.exr (illuminance E), and each lamp's combined
 * distribution (<lamp>.lid.exr, channel I, cd). hdr.exr and lux.exr carry the frame's metadata
 * as string attributes: hdlamp:frameSeq, hdlamp:cycleSeq, hdlamp:counter, hdlamp:flags,
 * hdlamp:tCycleRxNs, hdlamp:tCycleDoneNs, hdlamp:tRenderDoneNs and hdlamp:dims.<lamp> (the raw
 * dimming values, comma separated). With verdicts, the frame's verdicts and road KPIs go to
 * verdict.json in the same directory, and the same JSON text into the EXR attribute
 * hdlamp:verdict.
 *
 * Thread-safety: any thread; captures are serialised by the caller (they are rare).
 * Allocates (not the hot path).
 */
#ifndef HL_DAEMON_CAPTURE_H
#define HL_DAEMON_CAPTURE_H

#include <stddef.h>

#include "daemon/frame.h"
#include "daemon/verdicts.h"
#include "render/camera.h"
#include "lamp/lid.h"
#include "render/scene.h"

struct hl_capture_scene {
	const struct hl_gbuffer *gb;
	const struct hl_camera *cam;
	int n_lamps;
	const char *lamp_names[HL_FRAME_MAX_LAMPS];
	const struct hl_lid_grid *grids[HL_FRAME_MAX_LAMPS];
	const struct hl_verdicts *verdicts; /* NULL: no verdict.json */
};

/* Writes f; ret_path gets the directory. 0 or -errno (err says what failed). */
int hl_capture_write(const char *dir, const struct hl_frame *f, const struct hl_capture_scene *sc,
		     char *ret_path, size_t path_size, char *err, size_t err_size);

#endif
