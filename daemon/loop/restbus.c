/* SPDX-License-Identifier: MIT */
/* The restbus: see daemon/loop/restbus.h. */
#include "daemon/loop/restbus.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <net/if.h>

#include "base/clock.h"
#include "daemon/loop/world_feed.h"
#include "base/sched.h"
#include "world/world.h"
#include "base/json_write.h"
#include "daemon/core/sched_start.h"
#include "world/scenario_clock.h"

#define MS_NS 1000000LL

/* A periodic task: the vehicle message, or the camera cycle (every objects message). */
struct task {
	int64_t period_ns;
	int64_t next_ns; /* the next deadline */
	unsigned counter, counter_max;
	int64_t served; /* deadlines served: the index of the last one + 1 */
};

struct hl_restbus {
	struct hl_restbus_config cfg;
	char iface[IFNAMSIZ];
	char dbc[4096];
	struct hl_dbc *db;
	struct hl_inputs_map *map;
	struct hl_can_socket *sock;
	int64_t t0_ns;
	pthread_t thread;
	bool started;
	atomic_int stop;
	struct task veh, cam;
	/* a live OSI world: the newest two distinct states the vehicle cycle saw */
	struct hl_world_state live_prev, live_cur;
	bool have_live;
	/* the thread's own: when each message was last sent and in which deadline */
	int64_t last_sent_ns[HL_RESTBUS_MAX_MESSAGES];
	int64_t last_deadline_idx[HL_RESTBUS_MAX_MESSAGES];
	double jitter_sum_ms[HL_RESTBUS_MAX_MESSAGES];
	int64_t retry_at_ns;
	bool logged_down; /* the interface's failure is logged once until it opens */

	pthread_mutex_t lock; /* PI; guards c, held only to update or copy it */
	struct hl_restbus_counts c;
};

static void free_parts(struct hl_restbus *rb)
{
	hl_can_socket_free(rb->sock);
	hl_inputs_map_free(rb->map);
	hl_dbc_free(rb->db);
	free(rb);
}

int hl_restbus_new(const struct hl_restbus_config *cfg, struct hl_restbus **ret, char *err,
		   size_t err_size)
{
	struct hl_restbus *rb;
	struct hl_dbc_error derr;
	uint32_t ids[HL_RESTBUS_MAX_MESSAGES];
	char msg[256];
	double lo, hi;
	int rc;

	rb = calloc(1, sizeof(*rb));
	if (!rb)
		return -ENOMEM;
	rb->cfg = *cfg;
	snprintf(rb->iface, sizeof(rb->iface), "%s", cfg->iface);
	rb->cfg.iface = rb->iface;
	snprintf(rb->dbc, sizeof(rb->dbc), "%s", cfg->dbc);
	rb->cfg.dbc = rb->dbc;
	atomic_init(&rb->stop, 0);
	rc = hl_dbc_parse_file(cfg->dbc, &rb->db, &derr);
	if (rc < 0) {
		snprintf(err, err_size, "restbus.dbc '%s':%d:%d: %s", cfg->dbc, derr.line,
			 derr.column, derr.msg);
		goto err_free;
	}
	for (int i = 0; cfg->log && i < hl_dbc_n_warnings(rb->db); i++) {
		int line, col;
		const char *w = hl_dbc_warning(rb->db, i, &line, &col);

		fprintf(cfg->log, "hdlampd: restbus.dbc '%s':%d:%d: warning: %s\n", cfg->dbc, line,
			col, w);
	}
	rc = hl_inputs_map_new(rb->db, &rb->map, msg, sizeof(msg));
	if (rc < 0) {
		snprintf(err, err_size, "restbus.dbc '%s': %s", cfg->dbc,
			 rc == -EINVAL ? msg : strerror(-rc));
		goto err_free;
	}
	rb->c.n_messages = hl_inputs_map_n_messages(rb->map);
	for (int i = 0; i < rb->c.n_messages; i++) {
		const struct hl_inputs_message *im = hl_inputs_map_message(rb->map, i);
		struct hl_restbus_message_counts *mc = &rb->c.msg[i];

		snprintf(mc->name, sizeof(mc->name), "%s", im->msg->name);
		mc->can_id = im->msg->can_id;
		mc->cycle_ms = im->cycle_ms;
		ids[i] = im->msg->extended ? (im->msg->id | CAN_EFF_FLAG) : im->msg->id;
		if (im->cycle_ms < 1 || im->cycle_ms > HL_RESTBUS_MAX_CYCLE_MS ||
		    (i > 1 && im->cycle_ms != hl_inputs_map_message(rb->map, 1)->cycle_ms)) {
			snprintf(
				err, err_size,
				"restbus.dbc '%s': message '%s': GenMsgCycleTime %u: expected 1..%d "
				"ms%s",
				cfg->dbc, im->msg->name, im->cycle_ms, HL_RESTBUS_MAX_CYCLE_MS,
				i > 0 ? ", the same for every objects message (one camera cycle)" :
					"");
			rc = -EINVAL;
			goto err_free;
		}
	}
	/* the field of view must fit the box signals, or a clipped box could not be sent */
	if ((hl_inputs_map_range(rb->map, "h_left", &lo, &hi) == 0 && hi > lo &&
	     (cfg->cam.fov_h_deg / 2 > hi || -cfg->cam.fov_h_deg / 2 < lo)) ||
	    (hl_inputs_map_range(rb->map, "v_top", &lo, &hi) == 0 && hi > lo &&
	     (cfg->cam.fov_v_deg / 2 > hi || -cfg->cam.fov_v_deg / 2 < lo))) {
		snprintf(err, err_size,
			 "restbus.fov_deg %g,%g: wider than the database '%s' can carry (its box "
			 "signals' ranges)",
			 cfg->cam.fov_h_deg, cfg->cam.fov_v_deg, cfg->dbc);
		rc = -EINVAL;
		goto err_free;
	}
	/* and the range the distance signal, or a far object could not be sent */
	if (hl_inputs_map_range(rb->map, "distance", &lo, &hi) == 0 && hi > lo &&
	    cfg->cam.range_m > hi) {
		snprintf(
			err, err_size,
			"restbus.range_m %g: farther than the database '%s' can carry (its distance "
			"signal's range ends at %g m)",
			cfg->cam.range_m, cfg->dbc, hi);
		rc = -EINVAL;
		goto err_free;
	}
	rc = hl_can_socket_new(rb->iface, ids, rb->c.n_messages, &rb->sock);
	if (rc < 0) {
		snprintf(err, err_size, "restbus.interface '%s': %s", rb->iface, strerror(-rc));
		goto err_free;
	}
	rc = hl_mutex_init_pi(&rb->lock);
	if (rc < 0) {
		snprintf(err, err_size, "restbus: %s", strerror(-rc));
		goto err_free;
	}
	rb->veh.period_ns = hl_inputs_map_message(rb->map, 0)->cycle_ms * MS_NS;
	rb->veh.counter_max = hl_inputs_map_counter_max(rb->map, 0);
	rb->cam.period_ns = hl_inputs_map_message(rb->map, 1)->cycle_ms * MS_NS;
	rb->cam.counter_max = UINT32_MAX;
	for (int i = 1; i < rb->c.n_messages; i++) {
		const unsigned m = hl_inputs_map_counter_max(rb->map, i);

		rb->cam.counter_max = m < rb->cam.counter_max ? m : rb->cam.counter_max;
	}
	*ret = rb;
	return 0;

err_free:
	free_parts(rb);
	return rc;
}

/* The world at deadline d (daemon/loop/world_feed.h): a live input's, or d's scenario time. */
static void world_at(struct hl_restbus *rb, int64_t d_ns, struct hl_world_state *w)
{
	const struct hl_world_feed feed = { rb->cfg.sc, rb->cfg.pose, rb->cfg.osi };
	int64_t rx_ns;

	hl_world_feed_at(&feed, hl_scenario_clock_at(rb->cfg.sc, rb->t0_ns, d_ns), HL_SCENE_CLOCK,
			 w, &rx_ns);
}

/* Sends frame fr of message i for the deadline (index idx, time d_ns); counts what became of it. */
static void send_frame(struct hl_restbus *rb, int i, const struct hl_inputs_frame *fr,
		       bool first_of_cycle, int64_t idx, int64_t d_ns, int64_t period_ns)
{
	struct hl_restbus_message_counts *mc = &rb->c.msg[i];
	int rc = hl_can_socket_send(rb->sock,
				    fr->can_id & HL_DBC_EFF_FLAG ?
					    (fr->can_id & ~HL_DBC_EFF_FLAG) | CAN_EFF_FLAG :
					    fr->can_id,
				    fr->data, fr->len, fr->fd);
	const int64_t now = hl_clock_monotonic_ns();

	pthread_mutex_lock(&rb->lock);
	if (rc < 0) {
		mc->failed++;
		if (rc == -EAGAIN || rc == -ENOBUFS)
			rb->c.tx_full++;
		else if (rc == -ENETDOWN || rc == -ENODEV)
			rb->c.link_down++;
		else
			rb->c.tx_errors++;
		pthread_mutex_unlock(&rb->lock);
		return;
	}
	mc->sent++;
	if (first_of_cycle) {
		mc->late_last_ms = (double)(now - d_ns) / 1e6;
		mc->late_max_ms = fmax(mc->late_max_ms, mc->late_last_ms);
		if (rb->last_deadline_idx[i] == idx - 1 && idx > 0) {
			const double dev = (double)(now - rb->last_sent_ns[i] - period_ns) / 1e6;

			mc->intervals++;
			mc->jitter_last_ms = dev;
			mc->jitter_max_ms = fmax(mc->jitter_max_ms, fabs(dev));
			rb->jitter_sum_ms[i] += fabs(dev);
			mc->jitter_mean_abs_ms = rb->jitter_sum_ms[i] / (double)mc->intervals;
		}
		rb->last_sent_ns[i] = now;
		rb->last_deadline_idx[i] = idx;
	}
	pthread_mutex_unlock(&rb->lock);
}

/* Every frame due at a deadline failed before the socket: counted per message. */
static void count_unsent(struct hl_restbus *rb, int i, int n, uint64_t *reason)
{
	pthread_mutex_lock(&rb->lock);
	rb->c.msg[i].failed += (uint64_t)n;
	*reason += (uint64_t)n;
	pthread_mutex_unlock(&rb->lock);
}

static void serve_vehicle(struct hl_restbus *rb, int64_t d_ns, int64_t idx)
{
	struct hl_world_state w;
	struct hl_vehicle_state vs;
	struct hl_inputs_frame fr;

	world_at(rb, d_ns, &w);
	if (rb->cfg.osi) { /* a live world has no path: its states' own motion */
		if (!rb->have_live || w.t_s > rb->live_cur.t_s) {
			rb->live_prev = rb->have_live ? rb->live_cur : w;
			rb->live_cur = w;
			rb->have_live = true;
		}
		hl_restbus_vehicle_live(&w, &rb->live_prev, rb->cfg.light_switch,
					rb->cfg.adb_enable, &vs);
	} else {
		hl_restbus_vehicle(rb->cfg.sc, &w, rb->cfg.light_switch, rb->cfg.adb_enable, &vs);
	}
	if (hl_inputs_encode_vehicle(rb->map, &vs, rb->veh.counter, &fr) < 0) {
		count_unsent(rb, 0, 1, &rb->c.encode_errors);
	} else if (hl_can_socket_fd(rb->sock) < 0) {
		count_unsent(rb, 0, 1, &rb->c.link_down);
	} else {
		send_frame(rb, 0, &fr, true, idx, d_ns, rb->veh.period_ns);
	}
	rb->veh.counter = rb->veh.counter >= rb->veh.counter_max ? 0 : rb->veh.counter + 1;
	pthread_mutex_lock(&rb->lock);
	rb->c.vehicle_cycles++;
	rb->c.vehicle = vs;
	pthread_mutex_unlock(&rb->lock);
}

static int message_of(const struct hl_restbus *rb, uint32_t can_id)
{
	for (int i = 0; i < rb->c.n_messages; i++)
		if (hl_inputs_map_message(rb->map, i)->msg->can_id == can_id)
			return i;
	return -1;
}

static void serve_camera(struct hl_restbus *rb, int64_t d_ns, int64_t idx)
{
	struct hl_inputs_frame fr[HL_INPUTS_MAX_CYCLE_FRAMES];
	struct hl_world_state w;
	struct hl_camera_objects o;
	struct hl_restbus_unseen un;
	bool first[HL_RESTBUS_MAX_MESSAGES];
	int n;

	world_at(rb, d_ns, &w);
	hl_restbus_objects(rb->cfg.sc, &w, &rb->cfg.cam, hl_inputs_map_slots(rb->map), &o, &un);
	n = hl_inputs_encode_objects(rb->map, &o, rb->cam.counter, fr);
	if (n < 0) {
		/* a cycle it cannot encode: each objects message's frames counted as unsent */
		for (int i = 1; i < rb->c.n_messages; i++)
			count_unsent(rb, i, o.n ? o.n : 1, &rb->c.encode_errors);
	} else {
		for (int i = 0; i < HL_RESTBUS_MAX_MESSAGES; i++)
			first[i] = true;
		for (int k = 0; k < n; k++) {
			const int i = message_of(rb, fr[k].can_id);

			if (hl_can_socket_fd(rb->sock) < 0) {
				count_unsent(rb, i, 1, &rb->c.link_down);
				continue;
			}
			send_frame(rb, i, &fr[k], first[i], idx, d_ns, rb->cam.period_ns);
			first[i] = false;
		}
	}
	if (rb->cfg.loop) {
		/* the road users the cycle carried, and when its last frame went out */
		uint32_t visible = 0;

		for (int k = 0; n >= 0 && k < o.n; k++)
			if (o.obj[k].id >= 1 && o.obj[k].id <= 32)
				visible |= 1u << (o.obj[k].id - 1);
		hl_loop_latency_camera(rb->cfg.loop, d_ns, w.t_s, visible, hl_clock_monotonic_ns());
	}
	rb->cam.counter = rb->cam.counter >= rb->cam.counter_max ? 0 : rb->cam.counter + 1;
	pthread_mutex_lock(&rb->lock);
	rb->c.camera_cycles++;
	rb->c.objects_sent += n < 0 ? 0 : (uint64_t)o.n;
	rb->c.unseen_behind += (uint64_t)un.behind;
	rb->c.unseen_beyond_range += (uint64_t)un.beyond_range;
	rb->c.unseen_outside_fov += (uint64_t)un.outside_fov;
	rb->c.unseen_over_max += (uint64_t)un.over_max;
	rb->c.have_cycle = true;
	rb->c.cycle_t_s = w.t_s;
	rb->c.objects = o;
	pthread_mutex_unlock(&rb->lock);
}

/* The first deadline of a task at or after now: a whole number of periods from t0. */
static void task_begin(struct task *t, int64_t t0_ns, int64_t now_ns)
{
	int64_t k = now_ns <= t0_ns ? 0 : (now_ns - t0_ns + t->period_ns - 1) / t->period_ns;

	t->next_ns = t0_ns + k * t->period_ns;
	t->served = k; /* the deadline's index */
}

/* Serves the task if due; the newest passed deadline only, the skipped ones counted. */
static void task_run(struct hl_restbus *rb, struct task *t, int64_t now_ns,
		     void (*serve)(struct hl_restbus *, int64_t, int64_t))
{
	int64_t missed;

	if (t->next_ns > now_ns)
		return;
	missed = (now_ns - t->next_ns) / t->period_ns;
	if (missed > 0) {
		pthread_mutex_lock(&rb->lock);
		rb->c.overruns += (uint64_t)missed;
		pthread_mutex_unlock(&rb->lock);
		t->next_ns += missed * t->period_ns;
		t->served += missed;
	}
	serve(rb, t->next_ns, t->served);
	t->next_ns += t->period_ns;
	t->served++;
}

/* Error frames (bus state) and foreign frames of our IDs; reopens a closed socket. */
static void socket_upkeep(struct hl_restbus *rb, int64_t now_ns)
{
	struct hl_can_rx rx;
	int rc;

	if (hl_can_socket_fd(rb->sock) < 0) {
		if (now_ns < rb->retry_at_ns)
			return;
		rc = hl_can_socket_open(rb->sock);
		if (rc < 0) {
			rb->retry_at_ns = now_ns + hl_can_socket_retry_ms(rb->sock) * MS_NS;
			if (rb->cfg.log && !rb->logged_down)
				fprintf(rb->cfg.log,
					"hdlampd: restbus: '%s': %s; retrying, the frames due "
					"meanwhile counted as link_down\n",
					rb->iface, strerror(-rc));
			rb->logged_down = true;
			return;
		}
		rb->logged_down = false;
		if (rb->cfg.log)
			fprintf(rb->cfg.log, "hdlampd: restbus: '%s': open\n", rb->iface);
	}
	while ((rc = hl_can_socket_read(rb->sock, &rx)) > 0) {
		if (rx.error)
			continue;
		pthread_mutex_lock(&rb->lock);
		rb->c.foreign_frames++;
		pthread_mutex_unlock(&rb->lock);
	}
	if (rc < 0) {
		rb->retry_at_ns = now_ns + hl_can_socket_retry_ms(rb->sock) * MS_NS;
		rb->logged_down = true;
		if (rb->cfg.log)
			fprintf(rb->cfg.log, "hdlampd: restbus: '%s': %s, reopening\n", rb->iface,
				strerror(-rc));
	}
	pthread_mutex_lock(&rb->lock);
	hl_can_socket_stats(rb->sock, &rb->c.sock);
	pthread_mutex_unlock(&rb->lock);
}

static void *thread_main(void *arg)
{
	struct hl_restbus *rb = arg;
	int64_t now;

	pthread_setname_np(pthread_self(), "hl-restbus");
	hl_sched_start_thread("restbus", rb->cfg.rt_priority, rb->cfg.log);
	now = hl_clock_monotonic_ns();
	task_begin(&rb->veh, rb->t0_ns, now);
	task_begin(&rb->cam, rb->t0_ns, now);
	socket_upkeep(rb, now);
	while (!atomic_load(&rb->stop)) {
		const int64_t next = rb->veh.next_ns < rb->cam.next_ns ? rb->veh.next_ns :
									 rb->cam.next_ns;

		hl_clock_sleep_until_ns(next, NULL);
		now = hl_clock_monotonic_ns();
		socket_upkeep(rb, now);
		task_run(rb, &rb->veh, now, serve_vehicle);
		task_run(rb, &rb->cam, now, serve_camera);
	}
	return NULL;
}

int hl_restbus_start(struct hl_restbus *rb, int64_t t0_ns)
{
	int rc;

	rb->t0_ns = t0_ns; /* the thread's, read before it starts */
	/* no interval before two consecutive deadlines were sent (a first send at deadline 1 has
	 * no interval from a send at 0 that never was) */
	for (int i = 0; i < HL_RESTBUS_MAX_MESSAGES; i++)
		rb->last_deadline_idx[i] = -2;
	pthread_mutex_lock(&rb->lock);
	rb->c.t0_ns = t0_ns;
	pthread_mutex_unlock(&rb->lock);
	rc = pthread_create(&rb->thread, NULL, thread_main, rb);
	if (rc)
		return -rc;
	rb->started = true;
	return 0;
}

void hl_restbus_stop(struct hl_restbus *rb)
{
	if (!rb || !rb->started)
		return;
	atomic_store(&rb->stop, 1);
	pthread_join(rb->thread, NULL);
	rb->started = false;
}

void hl_restbus_free(struct hl_restbus *rb)
{
	if (!rb)
		return;
	hl_restbus_stop(rb);
	pthread_mutex_destroy(&rb->lock);
	free_parts(rb);
}

void hl_restbus_counts(struct hl_restbus *rb, struct hl_restbus_counts *ret)
{
	pthread_mutex_lock(&rb->lock);
	*ret = rb->c;
	pthread_mutex_unlock(&rb->lock);
}

void hl_restbus_status_json(struct hl_restbus *rb, FILE *f)
{
	struct hl_restbus_counts c;

	hl_restbus_counts(rb, &c);
	fputs(",\"restbus\":{\"interface\":", f);
	hl_json_write_str(f, rb->iface);
	fputs(",\"dbc\":", f);
	hl_json_write_str(f, rb->cfg.dbc);
	fprintf(f,
		",\"t0_monotonic_ns\":%" PRId64 ",\"open\":%s,\"bus\":\"%s\",\"bus_off\":%" PRIu64
		",\"error_frames\":%" PRIu64 ",\"vehicle_cycles\":%" PRIu64
		",\"camera_cycles\":%" PRIu64 ",\"overruns\":%" PRIu64 ",\"tx_full\":%" PRIu64
		",\"tx_errors\":%" PRIu64 ",\"encode_errors\":%" PRIu64 ",\"link_down\":%" PRIu64
		",\"foreign_frames\":%" PRIu64 ",\"objects_sent\":%" PRIu64
		",\"unseen\":{\"behind\":%" PRIu64 ",\"beyond_range\":%" PRIu64
		",\"outside_fov\":%" PRIu64 ",\"over_max\":%" PRIu64 "},"
		"\"messages\":[",
		c.t0_ns, c.sock.open ? "true" : "false", hl_can_bus_state_name(c.sock.bus),
		c.sock.bus_off, c.sock.error_frames, c.vehicle_cycles, c.camera_cycles, c.overruns,
		c.tx_full, c.tx_errors, c.encode_errors, c.link_down, c.foreign_frames,
		c.objects_sent, c.unseen_behind, c.unseen_beyond_range, c.unseen_outside_fov,
		c.unseen_over_max);
	for (int i = 0; i < c.n_messages; i++) {
		const struct hl_restbus_message_counts *m = &c.msg[i];

		fprintf(f,
			"%s{\"name\":\"%s\",\"id\":\"0x%" PRIx32
			"\",\"cycle_ms\":%u,\"sent\":%" PRIu64 ",\"failed\":%" PRIu64
			",\"intervals\":%" PRIu64
			",\"jitter_ms\":{\"last\":%.4f,\"max\":%.4f,\"mean_abs\":%.4f},"
			"\"late_ms\":{\"last\":%.4f,\"max\":%.4f}}",
			i ? "," : "", m->name, m->can_id & ~HL_DBC_EFF_FLAG, m->cycle_ms, m->sent,
			m->failed, m->intervals, m->jitter_last_ms, m->jitter_max_ms,
			m->jitter_mean_abs_ms, m->late_last_ms, m->late_max_ms);
	}
	fprintf(f,
		"],\"vehicle\":{\"speed_mps\":%.6g,\"yaw_rate_rad_s\":%.6g,\"steering_rad\":%.6g,"
		"\"light_switch\":\"%s\",\"adb_enable\":%s}",
		c.vehicle.speed_mps, c.vehicle.yaw_rate_rad_s, c.vehicle.steering_rad,
		hl_light_switch_name(c.vehicle.light_switch),
		c.vehicle.adb_enable ? "true" : "false");
	if (c.have_cycle) {
		fprintf(f, ",\"camera\":{\"t_s\":%.6f,\"objects\":[", c.cycle_t_s);
		for (int i = 0; i < c.objects.n; i++) {
			const struct hl_camera_object *o = &c.objects.obj[i];

			fprintf(f,
				"%s{\"id\":%u,\"class\":\"%s\",\"h_deg\":[%.4f,%.4f],\"v_deg\":[%.4f,"
				"%.4f],\"distance_m\":%.3f}",
				i ? "," : "", o->id, hl_object_class_name(o->cls), o->h_left_deg,
				o->h_right_deg, o->v_bottom_deg, o->v_top_deg, o->distance_m);
		}
		fputs("]}", f);
	}
	fputc('}', f);
}

void hl_restbus_metrics(struct hl_restbus *rb, struct hl_prom *p)
{
	struct hl_restbus_counts c;
	static const char *const reasons[] = { "behind", "beyond_range", "outside_fov",
					       "over_max" };

	hl_restbus_counts(rb, &c);
	hl_prom_family(p, "hdlamp_restbus_frames_total", HL_PROM_COUNTER,
		       "Restbus frames by message and result (sent, failed).");
	for (int i = 0; i < c.n_messages; i++) {
		hl_prom_counter(p, "hdlamp_restbus_frames_total",
				(const char *const[]){ "message", c.msg[i].name, "result", "sent",
						       NULL },
				c.msg[i].sent);
		hl_prom_counter(p, "hdlamp_restbus_frames_total",
				(const char *const[]){ "message", c.msg[i].name, "result", "failed",
						       NULL },
				c.msg[i].failed);
	}
	hl_prom_family(p, "hdlamp_restbus_jitter_max_seconds", HL_PROM_GAUGE,
		       "Largest deviation of a send interval from the message's period (s).");
	for (int i = 0; i < c.n_messages; i++)
		hl_prom_gauge(p, "hdlamp_restbus_jitter_max_seconds",
			      (const char *const[]){ "message", c.msg[i].name, NULL },
			      c.msg[i].jitter_max_ms / 1e3);
	hl_prom_family(p, "hdlamp_restbus_jitter_mean_abs_seconds", HL_PROM_GAUGE,
		       "Mean absolute deviation of the send intervals from the period (s).");
	for (int i = 0; i < c.n_messages; i++)
		hl_prom_gauge(p, "hdlamp_restbus_jitter_mean_abs_seconds",
			      (const char *const[]){ "message", c.msg[i].name, NULL },
			      c.msg[i].jitter_mean_abs_ms / 1e3);
	hl_prom_family(p, "hdlamp_restbus_late_max_seconds", HL_PROM_GAUGE,
		       "Largest delay of a send behind its deadline (s).");
	for (int i = 0; i < c.n_messages; i++)
		hl_prom_gauge(p, "hdlamp_restbus_late_max_seconds",
			      (const char *const[]){ "message", c.msg[i].name, NULL },
			      c.msg[i].late_max_ms / 1e3);
	hl_prom_family(p, "hdlamp_restbus_overruns_total", HL_PROM_COUNTER,
		       "Restbus deadlines skipped because the thread woke a period late or more.");
	hl_prom_counter(p, "hdlamp_restbus_overruns_total", NULL, c.overruns);
	hl_prom_family(p, "hdlamp_restbus_tx_errors_total", HL_PROM_COUNTER,
		       "Restbus frames not sent, by reason.");
	hl_prom_counter(p, "hdlamp_restbus_tx_errors_total",
			(const char *const[]){ "reason", "queue_full", NULL }, c.tx_full);
	hl_prom_counter(p, "hdlamp_restbus_tx_errors_total",
			(const char *const[]){ "reason", "error", NULL }, c.tx_errors);
	hl_prom_counter(p, "hdlamp_restbus_tx_errors_total",
			(const char *const[]){ "reason", "link_down", NULL }, c.link_down);
	hl_prom_counter(p, "hdlamp_restbus_tx_errors_total",
			(const char *const[]){ "reason", "unencodable", NULL }, c.encode_errors);
	hl_prom_family(p, "hdlamp_restbus_bus_off_total", HL_PROM_COUNTER,
		       "Times the restbus interface's controller went bus-off.");
	hl_prom_counter(p, "hdlamp_restbus_bus_off_total", NULL, c.sock.bus_off);
	hl_prom_family(p, "hdlamp_restbus_foreign_frames_total", HL_PROM_COUNTER,
		       "Frames of the restbus's own IDs sent by another node.");
	hl_prom_counter(p, "hdlamp_restbus_foreign_frames_total", NULL, c.foreign_frames);
	hl_prom_family(p, "hdlamp_restbus_cycles_total", HL_PROM_COUNTER,
		       "Restbus deadlines served, by task (vehicle, camera).");
	hl_prom_counter(p, "hdlamp_restbus_cycles_total",
			(const char *const[]){ "task", "vehicle", NULL }, c.vehicle_cycles);
	hl_prom_counter(p, "hdlamp_restbus_cycles_total",
			(const char *const[]){ "task", "camera", NULL }, c.camera_cycles);
	hl_prom_family(p, "hdlamp_restbus_objects_total", HL_PROM_COUNTER,
		       "Road users in camera cycles: sent, or why not.");
	hl_prom_counter(p, "hdlamp_restbus_objects_total",
			(const char *const[]){ "result", "sent", NULL }, c.objects_sent);
	for (int r = 0; r < 4; r++) {
		const uint64_t v[4] = { c.unseen_behind, c.unseen_beyond_range,
					c.unseen_outside_fov, c.unseen_over_max };

		hl_prom_counter(p, "hdlamp_restbus_objects_total",
				(const char *const[]){ "result", reasons[r], NULL }, v[r]);
	}
	hl_prom_family(p, "hdlamp_restbus_link_up", HL_PROM_GAUGE,
		       "Whether the restbus interface is open.");
	hl_prom_gauge(p, "hdlamp_restbus_link_up", NULL, c.sock.open ? 1 : 0);
}
