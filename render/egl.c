/* SPDX-License-Identifier: MIT */
/* Headless EGL, read top to bottom as kmscube does it: client extensions, platform display,
 * bind API, config, context. Optional entry points only when their extension is advertised. */
#include "render/egl.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES3/gl31.h>

#define MAX_DEVICES 16

struct hl_egl {
	EGLDisplay dpy;
	EGLContext ctx;
	const char *platform;
	char renderer[128];
	char version[128];
	bool float_targets, float_blend;
};

static int fail(struct hl_egl_error *err, const char *fmt, ...)
{
	va_list ap;

	if (err) {
		va_start(ap, fmt);
		vsnprintf(err->msg, sizeof(err->msg), fmt, ap);
		va_end(ap);
	}
	return -ENODEV;
}

/* Whole-word match in a space-separated extension list. */
static bool has_word(const char *list, const char *word)
{
	const size_t n = strlen(word);

	for (const char *p = list; p && (p = strstr(p, word)); p += n)
		if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
			return true;
	return false;
}

/* A hardware device: one that names a DRM node. Mesa's software device names none. */
static EGLDisplay device_display(const char *client_ext)
{
	PFNEGLQUERYDEVICESEXTPROC query_devices;
	PFNEGLQUERYDEVICESTRINGEXTPROC query_device_string;
	PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display;
	EGLDeviceEXT devices[MAX_DEVICES];
	EGLint n = 0;

	if (!has_word(client_ext, "EGL_EXT_platform_device") ||
	    !has_word(client_ext, "EGL_EXT_device_enumeration"))
		return EGL_NO_DISPLAY;
	query_devices = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
	query_device_string =
		(PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
	get_platform_display =
		(PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
	if (!query_devices || !query_device_string || !get_platform_display ||
	    !query_devices(MAX_DEVICES, devices, &n))
		return EGL_NO_DISPLAY;
	for (EGLint i = 0; i < n; i++) {
		const char *ext = query_device_string(devices[i], EGL_EXTENSIONS);

		if (!ext || !has_word(ext, "EGL_EXT_device_drm"))
			continue;
		if (!query_device_string(devices[i], EGL_DRM_DEVICE_FILE_EXT))
			continue;
		return get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL);
	}
	return EGL_NO_DISPLAY;
}

static EGLDisplay surfaceless_display(const char *client_ext)
{
	PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display;

	if (!has_word(client_ext, "EGL_MESA_platform_surfaceless"))
		return EGL_NO_DISPLAY;
	get_platform_display =
		(PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
	if (!get_platform_display)
		return EGL_NO_DISPLAY;
	return get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
}

/* Opens and initialises a display; sets egl->platform. */
static int open_display(struct hl_egl *egl, struct hl_egl_error *err)
{
	const char *client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
	const char *forced = getenv("EGL_PLATFORM");
	bool want_device = true, want_surfaceless = true;
	EGLint major, minor;

	if (!client_ext)
		return fail(err, "no EGL client extensions (no EGL implementation installed?)");
	if (!has_word(client_ext, "EGL_EXT_platform_base"))
		return fail(err, "EGL lacks EGL_EXT_platform_base: cannot open a headless display");
	if (forced && *forced) {
		want_device = strcmp(forced, "device") == 0;
		want_surfaceless = strcmp(forced, "surfaceless") == 0;
		if (!want_device && !want_surfaceless)
			return fail(err,
				    "EGL_PLATFORM='%s': no such headless platform (expected "
				    "'device' or 'surfaceless')",
				    forced);
	}
	/* A GPU first; if its display will not initialise, fall back to surfaceless. */
	egl->dpy = want_device ? device_display(client_ext) : EGL_NO_DISPLAY;
	egl->platform = "device";
	if (egl->dpy != EGL_NO_DISPLAY && !eglInitialize(egl->dpy, &major, &minor)) {
		if (!want_surfaceless)
			return fail(err, "eglInitialize on the device platform failed (0x%04x)",
				    eglGetError());
		egl->dpy = EGL_NO_DISPLAY;
	}
	if (egl->dpy == EGL_NO_DISPLAY && want_surfaceless) {
		egl->dpy = surfaceless_display(client_ext);
		egl->platform = "surfaceless";
		if (egl->dpy != EGL_NO_DISPLAY && !eglInitialize(egl->dpy, &major, &minor)) {
			egl->dpy = EGL_NO_DISPLAY;
			return fail(err,
				    "eglInitialize on the surfaceless platform failed (0x%04x)",
				    eglGetError());
		}
	}
	if (egl->dpy == EGL_NO_DISPLAY)
		return fail(err, "no EGL display: no GPU device%s",
			    want_surfaceless ? " and no EGL_MESA_platform_surfaceless" :
					       " (EGL_PLATFORM=device)");
	return 0;
}

static int create_context(struct hl_egl *egl, struct hl_egl_error *err)
{
	static const EGLint config_attribs[] = {
		EGL_RENDERABLE_TYPE,
		EGL_OPENGL_ES3_BIT,
		EGL_NONE,
	};
	static const EGLint context_attribs[] = {
		EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 1, EGL_NONE,
	};
	const char *dpy_ext = eglQueryString(egl->dpy, EGL_EXTENSIONS);
	EGLConfig config = NULL;
	EGLint n = 0;

	if (!dpy_ext || !has_word(dpy_ext, "EGL_KHR_surfaceless_context"))
		return fail(err, "the %s display lacks EGL_KHR_surfaceless_context", egl->platform);
	if (!eglBindAPI(EGL_OPENGL_ES_API))
		return fail(err, "eglBindAPI(EGL_OPENGL_ES_API) failed (0x%04x)", eglGetError());
	/* With EGL_KHR_no_config_context no config is needed at all. */
	if (!has_word(dpy_ext, "EGL_KHR_no_config_context") &&
	    (!eglChooseConfig(egl->dpy, config_attribs, &config, 1, &n) || n < 1))
		return fail(err, "no EGL config for GLES 3 on the %s display", egl->platform);
	egl->ctx = eglCreateContext(egl->dpy, config, EGL_NO_CONTEXT, context_attribs);
	if (egl->ctx == EGL_NO_CONTEXT)
		return fail(err, "cannot create a GLES 3.1 context on the %s display (0x%04x)",
			    egl->platform, eglGetError());
	if (!eglMakeCurrent(egl->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, egl->ctx))
		return fail(err, "eglMakeCurrent without a surface failed (0x%04x)", eglGetError());
	return 0;
}

int hl_egl_new(struct hl_egl **ret, struct hl_egl_error *err)
{
	struct hl_egl *egl = calloc(1, sizeof(*egl));
	const char *s;
	int rc;

	if (!egl)
		return -ENOMEM;
	egl->ctx = EGL_NO_CONTEXT;
	rc = open_display(egl, err);
	if (rc < 0)
		goto err_free;
	rc = create_context(egl, err);
	if (rc < 0)
		goto err_free;
	s = (const char *)glGetString(GL_RENDERER);
	snprintf(egl->renderer, sizeof(egl->renderer), "%s", s ? s : "?");
	s = (const char *)glGetString(GL_VERSION);
	snprintf(egl->version, sizeof(egl->version), "%s", s ? s : "?");
	egl->float_targets = hl_egl_has_gl_extension(egl, "GL_EXT_color_buffer_float");
	egl->float_blend = hl_egl_has_gl_extension(egl, "GL_EXT_float_blend");
	*ret = egl;
	return 0;

err_free:
	hl_egl_free(egl);
	return rc;
}

void hl_egl_free(struct hl_egl *egl)
{
	if (!egl)
		return;
	if (egl->dpy != EGL_NO_DISPLAY) {
		eglMakeCurrent(egl->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
		if (egl->ctx != EGL_NO_CONTEXT)
			eglDestroyContext(egl->dpy, egl->ctx);
		eglTerminate(egl->dpy);
		eglReleaseThread();
	}
	free(egl);
}

const char *hl_egl_platform(const struct hl_egl *egl)
{
	return egl->platform;
}

const char *hl_egl_renderer(const struct hl_egl *egl)
{
	return egl->renderer;
}

const char *hl_egl_version(const struct hl_egl *egl)
{
	return egl->version;
}

bool hl_egl_has_gl_extension(const struct hl_egl *egl, const char *name)
{
	GLint n = 0;

	(void)egl;
	glGetIntegerv(GL_NUM_EXTENSIONS, &n);
	for (GLint i = 0; i < n; i++) {
		const char *e = (const char *)glGetStringi(GL_EXTENSIONS, i);

		if (e && strcmp(e, name) == 0)
			return true;
	}
	return false;
}

bool hl_egl_software(const struct hl_egl *egl)
{
	static const char *const names[] = { "llvmpipe", "softpipe", "swrast" };

	for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++)
		if (strstr(egl->renderer, names[i]))
			return true;
	return false;
}

bool hl_egl_float_targets(const struct hl_egl *egl)
{
	return egl->float_targets;
}

bool hl_egl_float_blend(const struct hl_egl *egl)
{
	return egl->float_blend;
}
