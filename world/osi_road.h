/* SPDX-License-Identifier: MIT */
/*
 * The road of an ASAM OSI message (world/osi_msg.h): its lane boundaries made into our road
 * model (world/road.h), seen from the ego vehicle.
 *
 * The rules:
 * - Every boundary point must be finite and within 1e5 m of the origin (x and y; z is ignored:
 *   the ground is flat), else the message is refused (-EINVAL, why names the boundary's id).
 *   A boundary of fewer than 2 points is skipped.
 * - A boundary runs alongside the ego when the ego point's foot on it is not one of its ends,
 *   its direction there is within 30 degrees of the ego's heading (either way round) and it is
 *   at most 30 m to the side. These are the road's boundaries, ordered by their signed lateral
 *   offset at the foot (left positive, seen along the ego's heading). At least 2 are needed,
 *   with the ego between the outermost two.
 * - lanes = boundaries - 1; lane width = the outermost two's spacing / lanes (the mean spacing),
 *   refused outside the scenario's 2 to 6 m. Lanes are assumed of equal width: the inner
 *   boundaries give their count and the separator's kind, not the centre line.
 * - Centre line: midway between the outermost two, from the left one's points (each with its
 *   foot on the right one; points whose spacing differs from the width at the ego by more than
 *   a quarter are beyond the other's end and dropped), oriented so that +s is the ego's
 *   direction of travel, simplified by hl_road_set_polyline() within 0.01 m.
 * - Markings: the model has one edge kind for both edges: solid when either outer boundary is a
 *   painted line (SOLID_LINE, DASHED_LINE, BOTTS_DOTS), none otherwise (ROAD_EDGE, CURB, a
 *   barrier, NO_LINE, UNKNOWN, ...). The separator is that of the inner boundary nearest the
 *   ego: DASHED_LINE or BOTTS_DOTS dashed, SOLID_LINE solid, else none. Line widths, dash and
 *   gap are the scenario's defaults; no posts.
 *
 * Thread-safety: reentrant; allocates a scratch buffer for the centre line's points.
 */
#ifndef HL_WORLD_OSI_ROAD_H
#define HL_WORLD_OSI_ROAD_H

#include <stddef.h>

#include "world/osi_msg.h"
#include "world/road.h"

#define HL_OSI_ROAD_TOL_M 0.01 /* the centre line's simplification */
#define HL_OSI_ROAD_MAX_SIDE_M 30.0 /* a boundary farther to the side is another road's */
#define HL_OSI_ROAD_MAX_ANGLE_DEG 30.0 /* a boundary's direction from the ego's heading */

/*
 * The road the ego (world x, y, heading; OSI's frame, metres, radians) drives on, from f's
 * lane boundaries, into *ret (overwritten whole; untouched on failure). 0; -EINVAL with why
 * (may be NULL) saying what is wrong; -E2BIG when the centre line does not fit in
 * HL_SCN_MAX_SEGMENTS legs; -ENOMEM.
 */
int hl_osi_road(const struct hl_osi_frame *f, double ego_x_m, double ego_y_m,
		double ego_heading_rad, struct hl_road *ret, char *why, size_t why_size);

#endif
