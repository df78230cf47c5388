/* SPDX-License-Identifier: MIT */
/*
 * What the OSI tests share (test_osi_world, test_osi_replay): frames (world/osi_msg.h) filled
 * by hand: moving objects, straight lane boundaries and a message of a two-lane road with the
 * host on it.
 */
#ifndef HL_TEST_OSI_FIXTURE_H
#define HL_TEST_OSI_FIXTURE_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "world/osi_msg.h"

#define OSI_HOST 1 /* the host's id in osi_message() */

static const double osi_car_dim[3] = { 4.5, 1.8, 1.5 };

/* Appends a moving object: its box centre at (x, y, height / 2), yaw, standing still. */
static inline struct hl_osi_object *osi_add(struct hl_osi_frame *f, uint64_t id, int type, double x,
					    double y, double yaw)
{
	struct hl_osi_object *o = &f->object[f->n_objects++];

	*o = (struct hl_osi_object){ .id = id, .has_id = true, .type = type };
	memcpy(o->dim_m, osi_car_dim, sizeof(osi_car_dim));
	o->pos_m[0] = x;
	o->pos_m[1] = y;
	o->pos_m[2] = osi_car_dim[2] / 2;
	o->rpy_rad[2] = yaw;
	return o;
}

/* A vehicle with a classification. */
static inline struct hl_osi_object *osi_add_vehicle(struct hl_osi_frame *f, uint64_t id,
						    int vehicle_type, double x, double y,
						    double yaw)
{
	struct hl_osi_object *o = osi_add(f, id, HL_OSI_TYPE_VEHICLE, x, y, yaw);

	o->has_classification = true;
	o->vehicle_type = vehicle_type;
	return o;
}

/* A straight lane boundary along +x from x = -50 every 10 m to x = 200, at y = lat. */
static inline void osi_add_boundary(struct hl_osi_frame *f, uint64_t id, int type, double lat)
{
	struct hl_osi_boundary *b = &f->boundary[f->n_boundaries++];

	*b = (struct hl_osi_boundary){ .id = id, .type = type, .first = f->n_points, .n = 26 };
	for (int i = 0; i < 26; i++) {
		f->point[f->n_points][0] = -50.0 + 10.0 * i;
		f->point[f->n_points][1] = lat;
		f->point[f->n_points][2] = 0.0;
		f->point_width_m[f->n_points++] = 0.15;
	}
}

/*
 * A new message at t_ns: two lanes of 3.5 m along +x (boundaries at y = -3.5, 0, 3.5) and the
 * host OSI_HOST in the right lane, its front face at x = 0, heading +x. hl_osi_frame_free().
 */
static inline struct hl_osi_frame *osi_message(int64_t t_ns)
{
	struct hl_osi_frame *f = hl_osi_frame_new();

	assert_non_null(f);
	f->has_timestamp = true;
	f->t_ns = t_ns;
	f->has_host = true;
	f->host_id = OSI_HOST;
	osi_add_vehicle(f, OSI_HOST, HL_OSI_VEHICLE_MEDIUM_CAR, -2.25, -1.75, 0.0);
	osi_add_boundary(f, 101, HL_OSI_BOUNDARY_SOLID_LINE, -3.5);
	osi_add_boundary(f, 102, HL_OSI_BOUNDARY_DASHED_LINE, 0.0);
	osi_add_boundary(f, 103, HL_OSI_BOUNDARY_SOLID_LINE, 3.5);
	return f;
}

#endif
