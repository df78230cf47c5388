/* SPDX-License-Identifier: MIT */
#include "ecu/beams.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "ecu/windows.h"
#include "lamp/model.h"

bool hl_ecu_beams_is_hd84(const struct hl_lid *lid)
{
	const char *first = hl_lid_name(lid, 0);

	return hl_lid_n_sources(lid) == HL_HD84_SOURCES && first &&
	       strcmp(first, "row1_led01") == 0;
}

static int hd84(enum hl_side side, float *low, float *high)
{
	struct hl_lid *const none[2] = { NULL, NULL };
	struct hl_preset *p;
	int rc = hl_preset_new(HL_HD84_SOURCES, &p);

	if (rc < 0)
		return rc;
	rc = hl_model_hd84_preset("low", none, p);
	if (rc == 0)
		hl_preset_intensities(p, side, low);
	if (rc == 0)
		rc = hl_model_hd84_preset("high", none, p);
	if (rc == 0)
		hl_preset_intensities(p, side, high);
	hl_preset_free(p);
	return rc;
}

int hl_ecu_beams_default(const struct hl_lid *lid, enum hl_side side, double window_fraction,
			 float *low, float *high)
{
	const int n = hl_lid_n_sources(lid);
	struct hl_ecu_window *w;
	int rc;

	if (hl_ecu_beams_is_hd84(lid))
		return hd84(side, low, high);
	w = malloc(sizeof(*w) * (size_t)n);
	if (!w)
		return -ENOMEM;
	for (int k = 0; k < n; k++)
		high[k] = 1.0f;
	rc = hl_ecu_windows(lid, high, window_fraction, w);
	for (int k = 0; rc == 0 && k < n; k++)
		low[k] = !w[k].empty && w[k].v1_deg <= 0.0 ? 1.0f : 0.0f;
	free(w);
	return rc;
}
