/* SPDX-License-Identifier: MIT */
#include "world/scenario_clock.h"

double hl_scenario_clock_clamp(const struct hl_scenario *sc, double t_s)
{
	return t_s < 0.0 ? 0.0 : t_s > sc->duration_s ? sc->duration_s : t_s;
}

double hl_scenario_clock_at(const struct hl_scenario *sc, int64_t t0_ns, int64_t t_ns)
{
	return hl_scenario_clock_clamp(sc, (double)(t_ns - t0_ns) / 1e9);
}

bool hl_scenario_clock_over(const struct hl_scenario *sc, int64_t t0_ns, int64_t now_ns,
			    int64_t margin_ns)
{
	return now_ns >= t0_ns + (int64_t)(sc->duration_s * 1e9) + margin_ns;
}
