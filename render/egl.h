/* SPDX-License-Identifier: MIT */
/*
 * A headless EGL display and GLES 3.1+ context, no window: all drawing goes into FBOs.
 * Platform order: EGL_EXT_platform_device with a hardware device (one that has a DRM node),
 * then EGL_PLATFORM_SURFACELESS_MESA (llvmpipe on a machine without a GPU). EGL_PLATFORM in
 * the environment forces one: "device" or "surfaceless"; anything else is refused, so a user
 * who asks for a platform that does not exist gets an error, not a silent fallback.
 *
 * Thread-safety: the context is made current on the thread that calls hl_egl_new(); that
 * thread owns it and every GL object made while it is current (the render thread).
 */
#ifndef HL_RENDER_EGL_H
#define HL_RENDER_EGL_H

#include <stdbool.h>

struct hl_egl;

struct hl_egl_error {
	char msg[256];
};

/*
 * Opens a display, creates a GLES 3.1 (or newer) context and makes it current with no surface.
 * 0, -ENODEV (no EGL display or no suitable context; err says which step failed), -ENOMEM.
 */
int hl_egl_new(struct hl_egl **ret, struct hl_egl_error *err);
/* Releases the context and terminates the display; NULL is fine. */
void hl_egl_free(struct hl_egl *egl);

/* "device" or "surfaceless". Owned by egl. */
const char *hl_egl_platform(const struct hl_egl *egl);
/* GL_RENDERER and GL_VERSION strings, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)". Owned by egl. */
const char *hl_egl_renderer(const struct hl_egl *egl);
const char *hl_egl_version(const struct hl_egl *egl);
/* Whether GL_<name> is advertised by the context, e.g. "GL_EXT_color_buffer_float". */
bool hl_egl_has_gl_extension(const struct hl_egl *egl, const char *name);
/* Float render targets (EXT_color_buffer_float) and blending into 32-bit floats (EXT_float_blend). */
bool hl_egl_float_targets(const struct hl_egl *egl);
/* A software rasteriser (Mesa's llvmpipe, softpipe, swrast): GLES runs on the CPU's cores. */
bool hl_egl_software(const struct hl_egl *egl);
bool hl_egl_float_blend(const struct hl_egl *egl);

#endif
