/* SPDX-License-Identifier: MIT */
/*
 * The global-illumination tests of test_gi.c with GLES sensors (render/gl_sensor.c) instead of
 * the CPU's: the energy check of the bounce scene against the brute-force integral, the
 * uniform one-bounce interior of the sphere, and adaptive placement against one sensor per
 * pixel on the road. Same references, same tolerances; needs an EGL/GLES 3.1 context.
 */
#define HL_TEST_GI_GLES 1
#include "test_gi.c"
