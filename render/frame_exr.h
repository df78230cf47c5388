/* SPDX-License-Identifier: MIT */
/*
 * Rendered frames as OpenEXR (OpenEXRCore): an HDR frame (R, G, B, A as HALF, linear
 * luminance in cd/m^2) or an illuminance image (one FLOAT channel "E", lux). Every file
 * carries the standard camera attributes worldToCamera and worldToNDC (m44f, see
 * hl_camera_world_to_camera), so any tool can map a pixel back to its ray, and the lamp poses:
 * hdlamp:leftPosition / hdlamp:rightPosition (v3f, m, vehicle frame), hdlamp:leftAim /
 * hdlamp:rightAim (v2f: yaw, pitch in degrees), and hdlamp:unit ("cd/m2" or "lx").
 *
 * Thread-safety: any thread; the buffers are only read.
 */
#ifndef HL_RENDER_FRAME_EXR_H
#define HL_RENDER_FRAME_EXR_H

#include <stddef.h>
#include <stdint.h>

#include "world/camera.h"
#include "lamp/lid.h"

#define HL_FRAME_EXR_MAX_META 16

struct hl_frame_exr_info {
	const struct hl_camera *camera;
	int n_lamps; /* 1 or 2 */
	struct hl_lamp_pose lamps[2];
	/* further string attributes (e.g. "hdlamp:cycleSeq"), written as given */
	int n_meta;
	const char *meta_names[HL_FRAME_EXR_MAX_META];
	const char *meta_values[HL_FRAME_EXR_MAX_META];
};

/*
 * rgba: 4 floats per pixel, row 0 at the top. 0, -EINVAL, -ENOMEM, the failed open or write's
 * -errno (-ENOSPC, -EFBIG, -EACCES, ...) or -EIO; err names the file.
 */
int hl_frame_exr_write_hdr(const char *path, int width, int height, const float *rgba,
			   const struct hl_frame_exr_info *info, struct hl_lid_error *err);
/* lux: one float per pixel. */
int hl_frame_exr_write_lux(const char *path, int width, int height, const float *lux,
			   const struct hl_frame_exr_info *info, struct hl_lid_error *err);

/*
 * The lux image as an EXR file in memory (for HTTP): *ret_data is malloc'd (the caller frees
 * it), *ret_size bytes; both untouched on failure. info may be NULL, and info->camera may be
 * NULL: those attributes are then left out. 0, -EINVAL, -EIO, -ENOMEM.
 */
int hl_frame_exr_encode_lux(int width, int height, const float *lux,
			    const struct hl_frame_exr_info *info, uint8_t **ret_data,
			    size_t *ret_size, struct hl_lid_error *err);

#endif
