/* SPDX-License-Identifier: MIT */
#include "tools/pixel_drive.h"

#include <errno.h>
#include <math.h>

/* The high beam's value of a cell: strongest on the axis, half above V +2. */
static uint8_t high_beam(float hc, float vc)
{
	const long v = lroundf(24.0f + 39.0f * expf(-hc * hc / 150.0f));

	return (uint8_t)(vc > 2.0f ? v / 2 : v);
}

/* The low beam's value: below the horizon, up to V +1 on the traffic side (H > 0), else off. */
static uint8_t low_beam(float hc, float v1)
{
	if (v1 <= 0.0f || (hc > 0.0f && v1 <= 1.0f))
		return (uint8_t)lroundf(16.0f + 24.0f * expf(-hc * hc / 150.0f));
	return 0;
}

float hl_pixel_drive_window_deg(int c, int n_cycles)
{
	return n_cycles > 1 ? -20.0f + 40.0f * c / (n_cycles - 1) : 0.0f;
}

int hl_pixel_drive(const struct hl_pixel_layout *l, enum hl_pixel_phase phase, int c, int n_cycles,
		   struct hl_preset *p)
{
	const float centre = hl_pixel_drive_window_deg(c, n_cycles);
	const int bar = n_cycles > 1 ? c * (l->cols - HL_PIXEL_BAR_COLS) / (n_cycles - 1) : 0;

	if (p->n_sources != l->n || c < 0 || c >= n_cycles)
		return -EINVAL;
	for (int k = 0; k < l->n; k++) {
		const int col = k % l->cols;
		float h0, h1, v0, v1, hc, vc;
		uint8_t v;

		hl_model_pixel_cell(l, k, &h0, &h1, &v0, &v1);
		hc = 0.5f * (h0 + h1);
		vc = 0.5f * (v0 + v1);
		switch (phase) {
		case HL_PIXEL_GLAREFREE:
			v = high_beam(hc, vc);
			if (h1 > centre - 0.5f * HL_PIXEL_WINDOW_W_DEG &&
			    h0 < centre + 0.5f * HL_PIXEL_WINDOW_W_DEG && v1 > HL_GLAREFREE_V_MIN &&
			    v0 < HL_GLAREFREE_V_MAX)
				v = 0;
			p->dim[HL_SIDE_LEFT][k] = p->dim[HL_SIDE_RIGHT][k] = v;
			break;
		case HL_PIXEL_SWEEP:
			v = low_beam(hc, v1);
			if (col >= bar && col < bar + HL_PIXEL_BAR_COLS)
				v = HL_DIM_MAX;
			p->dim[HL_SIDE_LEFT][k] = p->dim[HL_SIDE_RIGHT][k] = v;
			break;
		case HL_PIXEL_RAMP:
			p->dim[HL_SIDE_LEFT][k] = (uint8_t)((k + c) % (HL_DIM_MAX + 1));
			p->dim[HL_SIDE_RIGHT][k] = (uint8_t)(HL_DIM_MAX - p->dim[HL_SIDE_LEFT][k]);
			break;
		default:
			return -EINVAL;
		}
	}
	return 0;
}
