/* SPDX-License-Identifier: MIT */
/*
 * Type C angles (CIE 70 / LM-63 / EULUMDAT C-gamma) in hdlamp's lamp space (docs/design.md §4: +z
 * the optical axis, +x right seen from behind the lamp, +y up).
 *
 * The photometric polar axis is vertical, as on the C-gamma goniophotometers these files come
 * from: gamma is measured from the nadir (-y), so gamma = 0 is straight down, 90 horizontal and
 * 180 straight up. C is the azimuth of the half-plane about the vertical axis: C = 0 contains
 * the optical axis (+z), and C grows counter-clockwise seen from above (LM-63 / EULUMDAT), so
 * C = 90 is the lamp's left (-x) and C = 270 its right (+x). Hence
 *
 *   d = (-sin(gamma) sin(C), -cos(gamma), sin(gamma) cos(C))
 *   gamma = atan2(hypot(x, z), -y),  C = atan2(-x, z) in [0, 360)
 *
 * and on the horizon near the axis H = -C (mod 360), V = gamma - 90: the (H, V) = (0, 0)
 * direction is (C, gamma) = (0, 90). Angles in radians here.
 */
#ifndef HL_IMPORT_TYPEC_H
#define HL_IMPORT_TYPEC_H

/* (C, gamma) of direction d, C in [0, 2 pi), gamma in [0, pi]; d must not be zero. */
void hl_typec_from_dir(const double d[3], double *ret_c_rad, double *ret_gamma_rad);
/* Unit direction of (C, gamma). */
void hl_typec_to_dir(double c_rad, double gamma_rad, double ret_d[3]);

#endif
