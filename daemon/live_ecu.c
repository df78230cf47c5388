/* SPDX-License-Identifier: MIT */
/* The ECU in the loop in real time: see daemon/live_ecu.h. */
#include "daemon/live_ecu.h"

#include <errno.h>
#include <inttypes.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "base/json_write.h"
#include "base/share_dir.h"
#include "can/inputs.h"
#include "can/vbus.h"
#include "can/vbus_port.h"
#include "can/vbus_rt.h"
#include "daemon/live_log.h"
#include "dbc/database.h"
#include "ecu/node.h"

#define ECU_PERIOD_NS 20000000 /* the dimming period of docs/design.md §1 */

struct hl_live_ecu {
	struct hl_vbus *bus;
	bool registered;
	struct hl_dbc *input_db;
	struct hl_inputs_map *map;
	struct hl_ecu_config ref;
	struct hl_ecu_node_config nc;
	struct hl_ecu_node *node;
	struct hl_vbus_rt *rt;
	pthread_mutex_t lock; /* the node's counts for readers on other threads */
	struct hl_ecu_node_counts counts;
	char error[512];
};

int hl_live_ecu_new(const struct hl_config *cfg, const char *trace, struct hl_live_ecu **ret,
		    bool *ret_config_error)
{
	const struct hl_vbus_config bc = { .name = HL_CONFIG_VBUS };
	struct hl_live_ecu *le;
	char list[HL_CONFIG_NAME];
	int rc;

	*ret = NULL;
	if (!cfg->ecu_model[0])
		return 0;
	le = calloc(1, sizeof(*le));
	if (!le)
		return -ENOMEM;
	pthread_mutex_init(&le->lock, NULL);
	hl_ecu_config_default(&le->ref);
	snprintf(list, sizeof(list), "%s", cfg->ecu_faults);
	for (char *save = NULL, *f = strtok_r(list, ",", &save); f; f = strtok_r(NULL, ",", &save))
		if (hl_ecu_node_fault(f, &le->nc, &le->ref) < 0) {
			hl_live_log("ecu.faults: '%s': expected %s", f, HL_ECU_NODE_FAULTS);
			*ret_config_error = true;
			hl_live_ecu_free(le);
			return -EINVAL;
		}
	rc = hl_vbus_new(&bc, &le->bus);
	if (rc == 0) {
		rc = hl_vbus_register(HL_CONFIG_VBUS, le->bus);
		le->registered = rc == 0;
	}
	if (rc < 0) {
		hl_live_log("the virtual bus %s: %s", HL_CONFIG_VBUS, strerror(-rc));
		hl_live_ecu_free(le);
		return rc;
	}
	if (trace) { /* candump -L times: CLOCK_MONOTONIC seconds, the bus's own clock */
		rc = hl_vbus_trace(le->bus, trace, 0);
		if (rc < 0) {
			hl_live_log("the virtual bus %s: trace '%s': %s", HL_CONFIG_VBUS, trace,
				    strerror(-rc));
			hl_live_ecu_free(le);
			return rc;
		}
	}
	*ret = le;
	return 0;
}

/* The bus's hook: the ECU's steps and late sends. */
static int64_t hook_next(void *ctx)
{
	struct hl_live_ecu *le = ctx;
	const int64_t a = hl_ecu_node_next_step(le->node), b = hl_ecu_node_next_send(le->node);

	return a < b ? a : b;
}

static int hook_run(void *ctx, int64_t t)
{
	struct hl_live_ecu *le = ctx;
	char err[512] = "";
	const int rc = hl_ecu_node_run(le->node, t, err, sizeof(err));

	pthread_mutex_lock(&le->lock);
	hl_ecu_node_counts(le->node, &le->counts);
	if (rc < 0)
		snprintf(le->error, sizeof(le->error), "%s", err);
	pthread_mutex_unlock(&le->lock);
	if (rc < 0)
		hl_live_log("ecu '%s' stopped: %s", hl_ecu_node_name(le->node), err);
	return rc;
}

static int load_inputs(struct hl_live_ecu *le, const struct hl_config *cfg, bool *ret_config_error)
{
	char path[HL_CONFIG_PATH + 32], msg[1024];
	struct hl_dbc_error derr;
	int rc;

	if (cfg->restbus_dbc[0]) {
		snprintf(path, sizeof(path), "%s", cfg->restbus_dbc);
	} else if (hl_share_dir("dbc", path, sizeof(path) - 20) == 0) {
		strcat(path, "/hd84_inputs.dbc");
	} else {
		hl_live_log("restbus.dbc: cannot find the shipped databases beside the binary; set "
			    "restbus.dbc");
		*ret_config_error = true;
		return -ENOENT;
	}
	rc = hl_dbc_parse_file(path, &le->input_db, &derr);
	if (rc < 0) {
		hl_live_log("'%s':%d:%d: %s", path, derr.line, derr.column, derr.msg);
		*ret_config_error = true;
		return rc;
	}
	rc = hl_inputs_map_new(le->input_db, &le->map, msg, sizeof(msg));
	if (rc < 0) {
		hl_live_log("'%s': %s", path, msg);
		*ret_config_error = true;
	}
	/* the reference ECU's input timeouts: 3 of each message's cycle time, as hdlamp ecu */
	for (int i = 0; rc == 0 && i < hl_inputs_map_n_messages(le->map); i++) {
		const struct hl_inputs_message *m = hl_inputs_map_message(le->map, i);

		if (!m->cycle_ms)
			continue;
		if (m->kind == HL_INPUTS_VEHICLE)
			le->ref.vehicle_timeout_ns = 3 * (int64_t)m->cycle_ms * 1000000;
		else
			le->ref.objects_timeout_ns = 3 * (int64_t)m->cycle_ms * 1000000;
	}
	return rc;
}

int hl_live_ecu_start(struct hl_live_ecu *le, const struct hl_config *cfg,
		      const struct hl_assembler *a, struct hl_lid *const *lids,
		      const char *const *lamp_names, bool *ret_config_error)
{
	const struct hl_vbus_rt_hook hook = { hook_next, hook_run, le };
	char err[1024] = "";
	int rc;

	if (!le)
		return 0;
	rc = load_inputs(le, cfg, ret_config_error);
	if (rc < 0)
		return rc;
	le->nc.ecu = cfg->ecu_model;
	le->nc.ref = &le->ref;
	le->nc.n_lamps = 2;
	le->nc.lids = lids;
	le->nc.lamp_names = lamp_names;
	le->nc.map = le->map;
	le->nc.a = a;
	le->nc.period_ns = ECU_PERIOD_NS;
	le->nc.start_ns = hl_clock_monotonic_ns();
	le->nc.log = stderr;
	pthread_mutex_lock(&le->lock); /* /status reads it from the HTTP thread */
	rc = hl_ecu_node_new(&le->nc, le->bus, &le->node, err, sizeof(err));
	pthread_mutex_unlock(&le->lock);
	if (rc < 0) {
		hl_live_log("ecu.model: %s", err);
		*ret_config_error = rc != -ENOMEM;
		return rc;
	}
	rc = hl_vbus_rt_start(le->bus, &hook, &le->rt);
	if (rc < 0) {
		hl_live_log("the virtual bus's thread: %s", strerror(-rc));
		return rc;
	}
	hl_live_log("ecu '%s' in process on the virtual bus %s (%s): steps every %d ms%s%s",
		    hl_ecu_node_name(le->node), HL_CONFIG_VBUS, "500 kbit/s",
		    ECU_PERIOD_NS / 1000000, cfg->ecu_faults[0] ? ", faults " : "",
		    cfg->ecu_faults);
	return 0;
}

void hl_live_ecu_stop(struct hl_live_ecu *le)
{
	if (!le)
		return;
	hl_vbus_rt_stop(le->rt);
	le->rt = NULL;
}

void hl_live_ecu_free(struct hl_live_ecu *le)
{
	if (!le)
		return;
	hl_live_ecu_stop(le);
	if (le->registered)
		hl_vbus_unregister(HL_CONFIG_VBUS);
	hl_ecu_node_free(le->node);
	hl_vbus_free(le->bus);
	hl_inputs_map_free(le->map);
	hl_dbc_free(le->input_db);
	pthread_mutex_destroy(&le->lock);
	free(le);
}

int hl_live_ecu_error(struct hl_live_ecu *le)
{
	return le && le->rt ? hl_vbus_rt_error(le->rt) : 0;
}

/* Read after the bus's thread stopped (or under the lock it writes it with). */
const char *hl_live_ecu_error_text(struct hl_live_ecu *le)
{
	const char *e;

	if (!le)
		return NULL;
	pthread_mutex_lock(&le->lock);
	e = le->error[0] ? le->error : NULL;
	pthread_mutex_unlock(&le->lock);
	return e;
}

const char *hl_live_ecu_name(const struct hl_live_ecu *le)
{
	return le && le->node ? hl_ecu_node_name(le->node) : NULL;
}

void hl_live_ecu_status_json(struct hl_live_ecu *le, FILE *f)
{
	struct hl_ecu_node_counts c;
	struct hl_vbus_counts bc;
	char error[512];

	if (!le)
		return;
	pthread_mutex_lock(&le->lock);
	if (!le->node) {
		pthread_mutex_unlock(&le->lock);
		return;
	}
	c = le->counts;
	snprintf(error, sizeof(error), "%s", le->error);
	pthread_mutex_unlock(&le->lock);
	hl_vbus_counts(le->bus, &bc);
	fputs(",\"ecu\":{\"model\":", f);
	hl_json_write_str(f, hl_ecu_node_name(le->node));
	fprintf(f,
		",\"bus\":\"%s\",\"steps\":%" PRIu64 ",\"frames_sent\":%" PRIu64
		",\"tx_errors\":%" PRIu64 ",\"rx_frames\":%" PRIu64 ",\"failsafe_steps\":%" PRIu64
		",\"bus_frames\":%" PRIu64 ",\"bus_busy_ms\":%.3f,\"error\":",
		HL_CONFIG_VBUS, c.steps, c.frames_sent, c.tx_errors, c.rx_frames, c.failsafe_steps,
		bc.frames, (double)bc.busy_ns / 1e6);
	hl_json_write_str(f, error);
	fputc('}', f);
}
