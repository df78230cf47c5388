/* SPDX-License-Identifier: MIT */
/*
 * Captures: a frame written to a new directory under the capture directory: hdr.exr (linear luminance RGBA), lux.exr (illuminance E), and each lamp's combined
 * distribution (<lamp>.lid.exr, channel I, cd). hdr.exr and lux.exr carry the frame's metadata
 * as string attributes: hdlamp:frameSeq, hdlamp:cycleSeq, hdlamp:counter, hdlamp:flags,
 * hdlamp:tCycleRxNs, hdlamp:tCycleDoneNs, hdlamp:tRenderDoneNs and hdlamp:dims.<lamp> (the raw
 * dimming values, comma separated). With verdicts, the frame's verdicts and road KPIs go to
 * verdict.json in the same directory, and the same JSON text into the EXR attribute
 * hdlamp:verdict.
 *
 * The directory is written under a temporary name, .tmp-frame-NNNNNNNN-PID, every file synced,
 * then renamed to frame-NNNNNNNN (the frame's sequence number), or frame-NNNNNNNN-2, -3, ... when
 * that frame was captured before: a reader never sees a half-written capture, and a capture
 * never replaces another. A capture that fails is removed entirely.
 *
 * Thread-safety: any thread, one capture at a time per directory (daemon/out/capture_queue.h has
 * the daemon's one writer). Allocates (not the hot path).
 */
#ifndef HL_DAEMON_OUT_CAPTURE_H
#define HL_DAEMON_OUT_CAPTURE_H

#include <stddef.h>

#include "daemon/core/frame.h"
#include "daemon/core/verdicts.h"
#include "world/camera.h"
#include "lamp/lid.h"
#include "render/scene.h"

struct hl_capture_scene {
	const struct hl_gbuffer *gb; /* NULL: a moving scene, no hdr.exr */
	const struct hl_camera *cam;
	int n_lamps;
	const char *lamp_names[HL_FRAME_MAX_LAMPS];
	const struct hl_lid_grid *grids[HL_FRAME_MAX_LAMPS];
	const struct hl_verdicts *verdicts; /* NULL: no verdict.json */
};

#define HL_CAPTURE_MAX_SAME_FRAME 1000 /* captures of one frame sequence number in a directory */

/*
 * Writes f (its pixels are not needed: hdr.exr is made from the G-buffer and the illuminance);
 * ret_path gets the directory. 0, or -errno of what failed (-ENOSPC, -EFBIG, -EACCES, ...,
 * -EEXIST: HL_CAPTURE_MAX_SAME_FRAME captures of the frame exist) and err names the file and
 * the reason.
 */
int hl_capture_write(const char *dir, const struct hl_frame *f, const struct hl_capture_scene *sc,
		     char *ret_path, size_t path_size, char *err, size_t err_size);

#endif
