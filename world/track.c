/* SPDX-License-Identifier: MIT */
/* A recorded world: see world/track.h. */
#include "world/track.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

struct hl_world_track {
	size_t n, cap;
	struct hl_world_state *st;
};

int hl_world_track_new(struct hl_world_track **ret)
{
	struct hl_world_track *t = calloc(1, sizeof(*t));

	if (!t)
		return -ENOMEM;
	*ret = t;
	return 0;
}

void hl_world_track_free(struct hl_world_track *t)
{
	if (!t)
		return;
	free(t->st);
	free(t);
}

int hl_world_track_push(struct hl_world_track *t, const struct hl_world_state *st)
{
	if (t->n && !(st->t_s > t->st[t->n - 1].t_s))
		return -EINVAL;
	if (t->n == t->cap) {
		const size_t cap = t->cap ? 2 * t->cap : 256;
		struct hl_world_state *p = realloc(t->st, cap * sizeof(*p));

		if (!p)
			return -ENOMEM;
		t->st = p;
		t->cap = cap;
	}
	t->st[t->n++] = *st;
	return 0;
}

size_t hl_world_track_count(const struct hl_world_track *t)
{
	return t->n;
}

const struct hl_world_state *hl_world_track_state(const struct hl_world_track *t, size_t i)
{
	return i < t->n ? &t->st[i] : NULL;
}

size_t hl_world_track_index(const struct hl_world_track *t, double t_s)
{
	size_t lo = 0, hi = t->n; /* the answer is in [lo, hi) */

	if (!t->n || !(t_s >= t->st[0].t_s))
		return 0;
	while (hi - lo > 1) {
		const size_t mid = lo + (hi - lo) / 2;

		if (t->st[mid].t_s <= t_s)
			lo = mid;
		else
			hi = mid;
	}
	return lo;
}

/* a's pose toward b's by f in [0, 1): position and speed linear, heading the shorter way */
static void lerp(const struct hl_body_pose *a, const struct hl_body_pose *b, double f,
		 struct hl_body_pose *ret)
{
	for (int k = 0; k < 3; k++)
		ret->pos_m[k] = a->pos_m[k] + f * (b->pos_m[k] - a->pos_m[k]);
	ret->heading_rad =
		remainder(a->heading_rad + f * remainder(b->heading_rad - a->heading_rad, 2 * M_PI),
			  2 * M_PI);
	ret->speed_mps = a->speed_mps + f * (b->speed_mps - a->speed_mps);
	ret->s_m = a->s_m + f * (b->s_m - a->s_m);
}

void hl_world_track_at(const struct hl_world_track *t, double t_s, struct hl_world_state *ret)
{
	const size_t i = hl_world_track_index(t, t_s);
	const struct hl_world_state *a = &t->st[i];

	*ret = *a;
	ret->t_s = t_s;
	if (i + 1 < t->n && t_s > a->t_s) {
		const struct hl_world_state *b = &t->st[i + 1];
		const double f = (t_s - a->t_s) / (b->t_s - a->t_s);

		lerp(&a->ego, &b->ego, f, &ret->ego);
		for (int k = 0; k < a->n_actors && k < b->n_actors; k++)
			if (hl_world_present(a, k) && hl_world_present(b, k))
				lerp(&a->actor[k], &b->actor[k], f, &ret->actor[k]);
	}
}
