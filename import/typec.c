/* SPDX-License-Identifier: MIT */
#include "import/typec.h"

#include <math.h>

void hl_typec_from_dir(const double d[3], double *ret_c_rad, double *ret_gamma_rad)
{
	double c = atan2(-d[0], d[2]);

	if (c < 0.0)
		c += 2.0 * M_PI;
	/* atan2 may round -tiny + 2 pi up to exactly 2 pi */
	if (c >= 2.0 * M_PI)
		c = 0.0;
	*ret_c_rad = c;
	*ret_gamma_rad = atan2(hypot(d[0], d[2]), -d[1]);
}

void hl_typec_to_dir(double c_rad, double gamma_rad, double ret_d[3])
{
	const double s = sin(gamma_rad);

	ret_d[0] = -s * sin(c_rad);
	ret_d[1] = -cos(gamma_rad);
	ret_d[2] = s * cos(c_rad);
}
