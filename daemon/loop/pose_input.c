/* SPDX-License-Identifier: MIT */
/* The pose input: see daemon/loop/pose_input.h. */
#include "daemon/loop/pose_input.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "base/clock.h"
#include "base/addr.h"
#include "base/sched.h"
#include "world/road.h"

#define DEG (M_PI / 180.0)
#define POLL_MS 100 /* longest wait for a datagram, so that stop is seen */

struct hl_pose_input {
	const struct hl_scenario *sc;
	FILE *log;
	int fd;
	uint16_t port;
	char listen[64];
	pthread_t thread;
	bool started;
	atomic_int stop;
	char *buf; /* HL_POSE_MAX_DATAGRAM + 1 bytes, the input thread's */

	pthread_mutex_t lock; /* PI: the render thread takes it; guards what follows */
	struct hl_world_state latest;
	struct hl_pose_counts c;
};

static const char *const result_names[HL_POSE_N] = {
	"ok", "malformed", "invalid", "unknown_actor", "too_large",
};

const char *hl_pose_result_name(enum hl_pose_result r)
{
	return r >= 0 && r < HL_POSE_N ? result_names[r] : "?";
}

static enum hl_pose_result fail(enum hl_pose_result r, char *why, size_t size, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
static enum hl_pose_result fail(enum hl_pose_result r, char *why, size_t size, const char *fmt, ...)
{
	va_list ap;

	if (why && size) {
		va_start(ap, fmt);
		vsnprintf(why, size, fmt, ap);
		va_end(ap);
	}
	return r;
}

/* obj's keys all in allowed; else the first other one in *ret_key. */
static bool only_keys(json_t *obj, const char *const *allowed, const char **ret_key)
{
	const char *key;
	json_t *v;

	json_object_foreach(obj, key, v)
	{
		bool ok = false;

		(void)v;
		for (const char *const *a = allowed; *a && !ok; a++)
			ok = strcmp(*a, key) == 0;
		if (!ok) {
			*ret_key = key;
			return false;
		}
	}
	return true;
}

/* obj.key, a finite number within [lo, hi]. */
static bool number(json_t *obj, const char *key, double lo, double hi, double *ret)
{
	json_t *v = json_object_get(obj, key);

	if (!json_is_number(v))
		return false;
	*ret = json_number_value(v);
	return isfinite(*ret) && *ret >= lo && *ret <= hi;
}

#define MAX_COORD_M 1e7 /* |x|, |y| at most: 10,000 km */

/* x_m, y_m, heading_deg of obj (path names it in messages) into a body pose. */
static enum hl_pose_result pose_of(json_t *obj, const char *path, struct hl_body_pose *ret,
				   char *why, size_t size)
{
	double x, y, h;

	if (!number(obj, "x_m", -MAX_COORD_M, MAX_COORD_M, &x))
		return fail(HL_POSE_INVALID, why, size, "%s.x_m: expected a number (m)", path);
	if (!number(obj, "y_m", -MAX_COORD_M, MAX_COORD_M, &y))
		return fail(HL_POSE_INVALID, why, size, "%s.y_m: expected a number (m)", path);
	if (!number(obj, "heading_deg", -3600.0, 3600.0, &h))
		return fail(HL_POSE_INVALID, why, size,
			    "%s.heading_deg: expected a number -3600..3600 (degrees)", path);
	*ret = (struct hl_body_pose){ .pos_m = { x, y, 0.0 },
				      .heading_rad = remainder(h * DEG, 2.0 * M_PI),
				      .s_m = NAN,
				      .speed_mps = NAN };
	return HL_POSE_OK;
}

enum hl_pose_result hl_pose_parse(const struct hl_scenario *sc, const char *buf, size_t len,
				  struct hl_world_state *ret, char *why, size_t why_size)
{
	static const char *const top_keys[] = { "t_s", "ego", "actors", NULL };
	static const char *const ego_keys[] = { "x_m", "y_m", "heading_deg", NULL };
	static const char *const actor_keys[] = { "id", "x_m", "y_m", "heading_deg", "lamps", NULL };
	enum hl_pose_result r = HL_POSE_OK;
	struct hl_world_state w;
	json_error_t jerr;
	json_t *root, *ego, *actors;
	const char *key;
	uint32_t named = 0;
	double t;

	root = json_loadb(buf, len, JSON_REJECT_DUPLICATES, &jerr);
	if (!root)
		return fail(HL_POSE_MALFORMED, why, why_size, "not JSON: %d:%d: %s", jerr.line,
			    jerr.column, jerr.text);
	if (!json_is_object(root)) {
		r = fail(HL_POSE_MALFORMED, why, why_size, "expected one JSON object");
		goto out;
	}
	if (!only_keys(root, top_keys, &key)) {
		r = fail(HL_POSE_INVALID, why, why_size,
			 "%s: unknown key; expected t_s, ego, actors", key);
		goto out;
	}
	if (!number(root, "t_s", -1e9, 1e9, &t)) {
		r = fail(HL_POSE_INVALID, why, why_size, "t_s: expected a number (s)");
		goto out;
	}
	hl_world_at(sc, t, &w);
	ego = json_object_get(root, "ego");
	if (!json_is_object(ego)) {
		r = fail(HL_POSE_INVALID, why, why_size, "ego: expected an object");
		goto out;
	}
	if (!only_keys(ego, ego_keys, &key)) {
		r = fail(HL_POSE_INVALID, why, why_size,
			 "ego.%s: unknown key; expected x_m, y_m, heading_deg", key);
		goto out;
	}
	r = pose_of(ego, "ego", &w.ego, why, why_size);
	if (r != HL_POSE_OK)
		goto out;
	actors = json_object_get(root, "actors");
	if (actors && !json_is_array(actors)) {
		r = fail(HL_POSE_INVALID, why, why_size, "actors: expected an array");
		goto out;
	}
	for (size_t i = 0; actors && i < json_array_size(actors); i++) {
		json_t *a = json_array_get(actors, i), *id, *lamps;
		char path[48];
		int k;

		snprintf(path, sizeof(path), "actors[%zu]", i);
		if (!json_is_object(a)) {
			r = fail(HL_POSE_INVALID, why, why_size, "%s: expected an object", path);
			goto out;
		}
		if (!only_keys(a, actor_keys, &key)) {
			r = fail(HL_POSE_INVALID, why, why_size,
				 "%s.%s: unknown key; expected id, x_m, y_m, heading_deg, lamps",
				 path, key);
			goto out;
		}
		id = json_object_get(a, "id");
		if (!json_is_string(id)) {
			r = fail(HL_POSE_INVALID, why, why_size,
				 "%s.id: expected a string (a road user's id)", path);
			goto out;
		}
		for (k = 0; k < sc->n_actors; k++)
			if (strcmp(sc->actor[k].id, json_string_value(id)) == 0)
				break;
		if (k == sc->n_actors) {
			r = fail(HL_POSE_UNKNOWN_ACTOR, why, why_size,
				 "%s.id '%.48s': no road user of that id in the scenario", path,
				 json_string_value(id));
			goto out;
		}
		if (named & (1u << k)) {
			r = fail(HL_POSE_INVALID, why, why_size, "%s.id '%s': named twice", path,
				 sc->actor[k].id);
			goto out;
		}
		named |= 1u << k;
		r = pose_of(a, path, &w.actor[k], why, why_size);
		if (r != HL_POSE_OK)
			goto out;
		lamps = json_object_get(a, "lamps");
		if (lamps && !json_is_boolean(lamps)) {
			r = fail(HL_POSE_INVALID, why, why_size, "%s.lamps: expected true or false",
				 path);
			goto out;
		}
		if (lamps && !json_is_true(lamps))
			w.lamps_on &= ~(1u << k);
	}
	*ret = w;
out:
	json_decref(root);
	return r;
}

static void count(struct hl_pose_input *pi, enum hl_pose_result r, const char *why)
{
	uint64_t n;

	pthread_mutex_lock(&pi->lock);
	n = ++pi->c.messages[r];
	pthread_mutex_unlock(&pi->lock);
	if (r != HL_POSE_OK && n <= HL_POSE_LOGGED && pi->log)
		fprintf(pi->log, "hdlampd: pose.listen '%s': %s message: %s%s\n", pi->listen,
			result_names[r], why,
			n == HL_POSE_LOGGED ? " (further ones only counted)" : "");
}

static void *thread_main(void *arg)
{
	struct hl_pose_input *pi = arg;

	pthread_setname_np(pthread_self(), "hl-pose");
	while (!atomic_load(&pi->stop)) {
		struct pollfd pfd = { .fd = pi->fd, .events = POLLIN };
		struct hl_world_state w;
		enum hl_pose_result r;
		char why[256];
		ssize_t n;

		if (poll(&pfd, 1, POLL_MS) <= 0)
			continue;
		/* MSG_TRUNC: the datagram's real length, so an over-long one is told apart */
		n = recv(pi->fd, pi->buf, HL_POSE_MAX_DATAGRAM + 1, MSG_TRUNC | MSG_DONTWAIT);
		if (n < 0)
			continue; /* EAGAIN, EINTR: nothing to count */
		if (n > HL_POSE_MAX_DATAGRAM) {
			snprintf(why, sizeof(why), "%zd bytes; at most %d", n,
				 HL_POSE_MAX_DATAGRAM);
			count(pi, HL_POSE_TOO_LARGE, why);
			continue;
		}
		r = hl_pose_parse(pi->sc, pi->buf, (size_t)n, &w, why, sizeof(why));
		if (r == HL_POSE_OK) {
			const int64_t now = hl_clock_monotonic_ns();

			pthread_mutex_lock(&pi->lock);
			pi->latest = w;
			pi->c.have = true;
			pi->c.t_last_ok_ns = now;
			pi->c.t_s = w.t_s;
			pthread_mutex_unlock(&pi->lock);
		}
		count(pi, r, why);
	}
	return NULL;
}

int hl_pose_input_new(const char *listen, const struct hl_scenario *sc, FILE *log,
		      struct hl_pose_input **ret, char *err, size_t err_size)
{
	struct sockaddr_storage ss;
	socklen_t len;
	struct hl_pose_input *pi;
	int rc;

	if (strncmp(listen, "udp:", 4) != 0 || hl_addr_parse(listen + 4, &ss, NULL) < 0) {
		snprintf(err, err_size, "pose.listen '%s': expected udp:HOST:PORT", listen);
		return -EINVAL;
	}
	pi = calloc(1, sizeof(*pi));
	if (!pi)
		return -ENOMEM;
	pi->sc = sc;
	pi->log = log;
	pi->fd = -1;
	snprintf(pi->listen, sizeof(pi->listen), "%s", listen);
	atomic_init(&pi->stop, 0);
	pi->buf = malloc(HL_POSE_MAX_DATAGRAM + 1);
	rc = pi->buf ? hl_mutex_init_pi(&pi->lock) : -ENOMEM;
	if (rc < 0) {
		free(pi->buf);
		free(pi);
		return rc;
	}
	pi->fd = socket(ss.ss_family, SOCK_DGRAM | SOCK_CLOEXEC, 0);
	len = ss.ss_family == AF_INET6 ? sizeof(struct sockaddr_in6) : sizeof(struct sockaddr_in);
	if (pi->fd < 0 || bind(pi->fd, (struct sockaddr *)&ss, len) < 0 ||
	    getsockname(pi->fd, (struct sockaddr *)&ss, &len) < 0) {
		rc = -errno;
		snprintf(err, err_size, "pose.listen '%s': %s", listen, strerror(errno));
		hl_pose_input_free(pi);
		return rc;
	}
	pi->port = ntohs(ss.ss_family == AF_INET6 ? ((struct sockaddr_in6 *)&ss)->sin6_port :
						    ((struct sockaddr_in *)&ss)->sin_port);
	*ret = pi;
	return 0;
}

int hl_pose_input_start(struct hl_pose_input *pi)
{
	const int rc = pthread_create(&pi->thread, NULL, thread_main, pi);

	if (rc)
		return -rc;
	pi->started = true;
	return 0;
}

void hl_pose_input_stop(struct hl_pose_input *pi)
{
	if (!pi || !pi->started)
		return;
	atomic_store(&pi->stop, 1);
	pthread_join(pi->thread, NULL);
	pi->started = false;
}

void hl_pose_input_free(struct hl_pose_input *pi)
{
	if (!pi)
		return;
	hl_pose_input_stop(pi);
	if (pi->fd >= 0)
		close(pi->fd);
	pthread_mutex_destroy(&pi->lock);
	free(pi->buf);
	free(pi);
}

uint16_t hl_pose_input_port(const struct hl_pose_input *pi)
{
	return pi->port;
}

bool hl_pose_input_latest(struct hl_pose_input *pi, struct hl_world_state *ret, int64_t *ret_rx_ns)
{
	bool have;

	pthread_mutex_lock(&pi->lock);
	have = pi->c.have;
	if (have) {
		*ret = pi->latest;
		*ret_rx_ns = pi->c.t_last_ok_ns;
	}
	pthread_mutex_unlock(&pi->lock);
	return have;
}

void hl_pose_input_counts(struct hl_pose_input *pi, struct hl_pose_counts *ret)
{
	pthread_mutex_lock(&pi->lock);
	*ret = pi->c;
	pthread_mutex_unlock(&pi->lock);
}
