/* SPDX-License-Identifier: MIT */
/*
 * The judged frames of `hdlamp sil --frames DIR` as images (docs/sil.md, "Frames"): each frame
 * rendered as hdlampd's live view shows the moving scene (daemon/pipeline.c, render()) and
 * written as DIR/frame-NNNNNN.png, NNNNNN the frame's seq. The picture: the scenario's world
 * at the frame's scenario time ray cast from the driver's camera at render.size, lit by both
 * lamps with the frame's intensities, in render.view (display: tone mapped at
 * render.exposure_ev with the road users' lamps drawn as glows; lux: false colour). HDR has no
 * PNG; render.view hdr is refused.
 *
 * Reproducible to the bit: both stages run on the CPU whatever render.combine and
 * render.headlight say (the GLES stages round differently from the CPU's, by machine), the
 * threads (render.threads, 0: one per CPU) each write only their own bands of pixels (1 and 8
 * threads give the same bytes), and the PNG carries no time. Two runs of the same scenario
 * give the same bytes.
 *
 * Thread-safety: one thread (the SIL loop's); the renderer's helpers run inside
 * hl_sil_frames_write().
 */
#ifndef HL_SIL_FRAMES_H
#define HL_SIL_FRAMES_H

#include <stddef.h>
#include <stdint.h>

#include "daemon/core/config.h"
#include "lamp/lid.h"
#include "world/scenario.h"

struct hl_sil_frames;

/*
 * Frames of sc (which, and lids[0] (left), lids[1] (right), must outlive the object) into the
 * directory dir (which must exist; the string is copied), with cfg's render.* keys. 0, or
 * -errno with a message in err: -EINVAL (render.view hdr, an unknown view), -ENOMEM, or what
 * the renderer returned.
 */
int hl_sil_frames_new(const struct hl_config *cfg, struct hl_lid *const lids[2],
		      const struct hl_scenario *sc, const char *dir, struct hl_sil_frames **ret,
		      char *err, size_t err_size);
/* NULL is fine. */
void hl_sil_frames_free(struct hl_sil_frames *fr);

/*
 * Renders frame seq at scenario time t_s, lamp l lit with intensities[l] (its n_sources
 * relative currents), and writes DIR/frame-NNNNNN.png. 0, or -errno with a message naming the
 * file in err. Allocates only the PNG's bytes.
 */
int hl_sil_frames_write(struct hl_sil_frames *fr, uint64_t seq, double t_s,
			const float *const intensities[2], char *err, size_t err_size);

#endif
