/* SPDX-License-Identifier: MIT */
/* OSI lane boundaries made into our road model: the rules are world/osi_road.h's. */
#include "world/osi_road.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

#define DEG (M_PI / 180.0)
#define MAX_COORD_M 1e5
#define MIN_WIDTH_M 2.0 /* the scenario's lane width range */
#define MAX_WIDTH_M 6.0
#define SPACING_TOL 0.25 /* a centre point's spacing against the width at the ego, relative */

/* A boundary that runs alongside the ego. */
struct side {
	int b; /* index in the frame */
	double lat_m; /* signed lateral offset at the foot, left positive */
	bool reversed; /* its points run against the ego's heading */
};

static int fail(char *why, size_t why_size, int rc, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));

static int fail(char *why, size_t why_size, int rc, const char *fmt, ...)
{
	va_list ap;

	if (why && why_size) {
		va_start(ap, fmt);
		vsnprintf(why, why_size, fmt, ap);
		va_end(ap);
	}
	return rc;
}

/*
 * The foot of (x, y) on boundary bd's polyline: the point, the leg's index and the parameter
 * along it in [0, 1]; the distance.
 */
static double foot(const struct hl_osi_frame *f, const struct hl_osi_boundary *bd, double x,
		   double y, double ret[2], int *ret_leg, double *ret_u)
{
	double best = INFINITY;

	for (int i = 0; i + 1 < bd->n; i++) {
		const double *a = f->point[bd->first + i], *b = f->point[bd->first + i + 1];
		const double ex = b[0] - a[0], ey = b[1] - a[1], len2 = ex * ex + ey * ey;
		double u = len2 > 0.0 ? ((x - a[0]) * ex + (y - a[1]) * ey) / len2 : 0.0, dist;

		u = u < 0.0 ? 0.0 : u > 1.0 ? 1.0 : u;
		dist = hypot(x - a[0] - u * ex, y - a[1] - u * ey);
		if (dist < best) {
			best = dist;
			ret[0] = a[0] + u * ex;
			ret[1] = a[1] + u * ey;
			*ret_leg = i;
			*ret_u = u;
		}
	}
	return best;
}

/* Whether boundary bd runs alongside the ego at (x, y) heading (c, s); how, into ret. */
static bool alongside(const struct hl_osi_frame *f, int b, double x, double y, double c, double s,
		      struct side *ret)
{
	const struct hl_osi_boundary *bd = &f->boundary[b];
	double p[2], u, ex, ey;
	int leg;

	if (bd->n < 2)
		return false;
	foot(f, bd, x, y, p, &leg, &u);
	if ((leg == 0 && u <= 0.0) || (leg == bd->n - 2 && u >= 1.0))
		return false; /* beside its end, not alongside */
	ex = f->point[bd->first + leg + 1][0] - f->point[bd->first + leg][0];
	ey = f->point[bd->first + leg + 1][1] - f->point[bd->first + leg][1];
	if (fabs(ex * c + ey * s) < hypot(ex, ey) * cos(HL_OSI_ROAD_MAX_ANGLE_DEG * DEG))
		return false;
	ret->b = b;
	ret->lat_m = -(p[0] - x) * s + (p[1] - y) * c;
	ret->reversed = ex * c + ey * s < 0.0;
	return fabs(ret->lat_m) <= HL_OSI_ROAD_MAX_SIDE_M;
}

static bool painted(int type)
{
	return type == HL_OSI_BOUNDARY_SOLID_LINE || type == HL_OSI_BOUNDARY_DASHED_LINE ||
	       type == HL_OSI_BOUNDARY_BOTTS_DOTS;
}

static enum hl_marking separator(int type)
{
	return type == HL_OSI_BOUNDARY_DASHED_LINE || type == HL_OSI_BOUNDARY_BOTTS_DOTS ?
		       HL_MARK_DASHED :
	       type == HL_OSI_BOUNDARY_SOLID_LINE ? HL_MARK_SOLID :
						    HL_MARK_NONE;
}

int hl_osi_road(const struct hl_osi_frame *f, double ego_x_m, double ego_y_m,
		double ego_heading_rad, struct hl_road *ret, char *why, size_t why_size)
{
	const double c = cos(ego_heading_rad), s = sin(ego_heading_rad);
	struct side side[HL_OSI_MAX_BOUNDARIES], left, right;
	double width, lane_width, (*mid)[2];
	int n = 0, n_mid = 0, rc, inner = -1;

	if (!isfinite(ego_x_m) || !isfinite(ego_y_m) || !isfinite(ego_heading_rad))
		return fail(why, why_size, -EINVAL, "the ego's pose is not finite");
	for (int b = 0; b < f->n_boundaries; b++) {
		const struct hl_osi_boundary *bd = &f->boundary[b];

		if (bd->first < 0 || bd->n < 0 || bd->first + bd->n > f->n_points)
			return fail(why, why_size, -EINVAL,
				    "lane boundary %" PRIu64 ": points %d..%d beyond the %d given",
				    bd->id, bd->first, bd->first + bd->n - 1, f->n_points);
		for (int i = bd->first; i < bd->first + bd->n; i++)
			for (int k = 0; k < 2; k++)
				if (!(fabs(f->point[i][k]) <= MAX_COORD_M))
					return fail(why, why_size, -EINVAL,
						    "lane boundary %" PRIu64
						    ": point %d: %c = %g: expected a finite "
						    "coordinate within %g m",
						    bd->id, i - bd->first, "xy"[k],
						    f -> point[i][k], MAX_COORD_M);
	}
	for (int b = 0; b < f->n_boundaries; b++)
		if (alongside(f, b, ego_x_m, ego_y_m, c, s, &side[n]))
			n++;
	/* By lateral offset, right (negative) first: insertion sort, n is small. */
	for (int i = 1; i < n; i++)
		for (int j = i; j > 0 && side[j].lat_m < side[j - 1].lat_m; j--) {
			const struct side t = side[j];

			side[j] = side[j - 1];
			side[j - 1] = t;
		}
	if (n < 2 || side[0].lat_m > 0.0 || side[n - 1].lat_m < 0.0)
		return fail(
			why, why_size, -EINVAL,
			"%d lane boundaries run alongside the ego at (%g, %g): expected the ego "
			"between two",
			n, ego_x_m, ego_y_m);
	right = side[0];
	left = side[n - 1];
	width = left.lat_m - right.lat_m;
	lane_width = width / (n - 1);
	if (lane_width < MIN_WIDTH_M || lane_width > MAX_WIDTH_M)
		return fail(why, why_size, -EINVAL,
			    "lane boundaries %" PRIu64 " and %" PRIu64
			    ": %d lanes of %.3g m: expected %g to %g m",
			    f->boundary[right.b].id, f->boundary[left.b].id, n - 1, lane_width,
			    MIN_WIDTH_M, MAX_WIDTH_M);
	/* The inner boundary nearest the ego gives the separator. */
	for (int i = 1; i < n - 1; i++)
		if (inner < 0 || fabs(side[i].lat_m) < fabs(side[inner].lat_m))
			inner = i;
	/* The centre line: from the left boundary's points, in the ego's direction. */
	{
		const struct hl_osi_boundary *lb = &f->boundary[left.b];
		const struct hl_osi_boundary *rb = &f->boundary[right.b];

		mid = malloc(sizeof(*mid) * (size_t)lb->n);
		if (!mid)
			return -ENOMEM;
		for (int k = 0; k < lb->n; k++) {
			const double *q = f->point[lb->first + (left.reversed ? lb->n - 1 - k : k)];
			double p[2], u;
			int leg;
			const double dist = foot(f, rb, q[0], q[1], p, &leg, &u);

			if (fabs(dist - width) > SPACING_TOL * width)
				continue;
			mid[n_mid][0] = (q[0] + p[0]) / 2;
			mid[n_mid][1] = (q[1] + p[1]) / 2;
			n_mid++;
		}
	}
	rc = n_mid < 2 ?
		     -EINVAL :
		     hl_road_set_polyline(ret, (const double(*)[2])mid, n_mid, HL_OSI_ROAD_TOL_M);
	free(mid);
	if (rc == -EINVAL)
		return fail(why, why_size, rc,
			    "lane boundaries %" PRIu64 " and %" PRIu64
			    ": no centre line between them (fewer than 2 distinct points)",
			    f->boundary[right.b].id, f->boundary[left.b].id);
	if (rc == -E2BIG)
		return fail(why, why_size, rc,
			    "lane boundaries %" PRIu64 " and %" PRIu64
			    ": the centre line needs more than %d legs within %g m",
			    f->boundary[right.b].id, f->boundary[left.b].id, HL_SCN_MAX_SEGMENTS,
			    HL_OSI_ROAD_TOL_M);
	if (rc < 0)
		return rc;
	ret->lanes = n - 1;
	ret->lane_width_m = lane_width;
	ret->edge = painted(f->boundary[left.b].type) || painted(f->boundary[right.b].type) ?
			    HL_MARK_SOLID :
			    HL_MARK_NONE;
	ret->separator = inner < 0 ? HL_MARK_NONE : separator(f->boundary[side[inner].b].type);
	ret->edge_line_width_m = 0.15; /* the scenario's defaults (docs/scenarios.md) */
	ret->separator_line_width_m = 0.12;
	ret->dash_m = 3.0;
	ret->gap_m = 6.0;
	ret->post_spacing_m = 0.0;
	ret->post_offset_m = 0.75;
	ret->post_height_m = 1.0;
	return 0;
}
