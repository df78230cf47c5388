/* SPDX-License-Identifier: MIT */
/*
 * hdlampd's configuration: an INI file (inih) with command-line overrides
 * (--set SECTION.KEY=VALUE and the short options). Every key is listed in config.c's table and
 * in hdlampd.conf(5); an unknown key or a bad value is an error naming file, line and key.
 *
 * Thread-safety: loaded by the main thread; the other threads get a copy.
 */
#ifndef HL_DAEMON_CONFIG_H
#define HL_DAEMON_CONFIG_H

#include <stdbool.h>

#define HL_CONFIG_PATH 512
#define HL_CONFIG_NAME 64
#define HL_CONFIG_MAX_SETS 32 /* verdict sets: one bit each in the frame header */
#define HL_CONFIG_SET_ID 48 /* a set id's bytes with the NUL (lamp/regulation.h: HL_REG_ID_MAX) */
#define HL_CONFIG_ROAD_LEVELS 2 /* render/road_kpi.h: HL_ROAD_KPI_LEVELS */
#define HL_CONFIG_ROAD_WIDTHS 2 /* render/road_kpi.h: HL_ROAD_KPI_WIDTHS */

enum hl_failsafe {
	HL_FAILSAFE_HOLD, /* keep the last valid intensities */
	HL_FAILSAFE_DARK, /* all sources off */
	HL_FAILSAFE_PRESET, /* a preset's values (failsafe_preset) */
};

struct hl_config {
	/* [can] */
	char interface[HL_CONFIG_NAME]; /* SocketCAN interface, or "" */
	char replay[HL_CONFIG_PATH]; /* candump log, or "" */
	bool replay_fast, replay_loop;
	char dbc[HL_CONFIG_PATH];
	char lamps[HL_CONFIG_NAME]; /* lamp names, comma separated */
	int timeout_ms;
	/* [dbc] */
	bool dbc_strict; /* HL_DBC_STRICT: irregularities are errors, not warnings */
	/* [lamps] */
	char lid_left[HL_CONFIG_PATH], lid_right[HL_CONFIG_PATH];
	char presets[HL_CONFIG_PATH]; /* directory of NAME.json presets */
	enum hl_failsafe failsafe;
	char failsafe_preset[HL_CONFIG_NAME];
	/* [render] */
	char scene[HL_CONFIG_NAME];
	char view[HL_CONFIG_NAME];
	int width, height;
	double exposure_ev;
	char combine[HL_CONFIG_NAME], headlight[HL_CONFIG_NAME]; /* auto | cpu | gles */
	int render_threads; /* threads lighting a frame; 0: one per online CPU */
	double rate_hz; /* 0: render on every new complete cycle */
	double coalesce_ms; /* rate_hz 0: wait at most this for the other lamp's cycle */
	/* [stream] */
	char stream_tcp[HL_CONFIG_NAME]; /* host:port or "" */
	char stream_unix[HL_CONFIG_PATH]; /* socket path or "" */
	bool stream_raw;
	int stream_max_clients;
	/* [http] */
	char http_listen[HL_CONFIG_NAME]; /* host:port or "" */
	bool http_capture; /* allow POST /capture */
	/* [capture] */
	char capture_dir[HL_CONFIG_PATH];
	/* [gpio] */
	char gpio_chip[HL_CONFIG_PATH]; /* name (gpiochip0) or path; "" = no GPIO */
	char gpio_strobe[HL_CONFIG_NAME]; /* line name or offset; "" = none */
	char gpio_trigger[HL_CONFIG_NAME];
	char gpio_trigger_edge[HL_CONFIG_NAME]; /* rising | falling | both */
	char gpio_ecu_enable[HL_CONFIG_NAME];
	/* [verdict] */
	char verdict_sets[HL_CONFIG_MAX_SETS]
			 [HL_CONFIG_SET_ID]; /* set ids, in order; bit i = set i */
	int n_verdict_sets; /* 0: no verdicts */
	char regulations[HL_CONFIG_PATH]; /* directory of the sets' ID.json files */
	bool traffic_left; /* left-hand traffic: the sets' H mirrored */
	char verdict_modes[HL_CONFIG_PATH]; /* MODE:ID+ID,...: the sets per HdlBeamMode value */
	/* [road] */
	double road_levels_lx[HL_CONFIG_ROAD_LEVELS]; /* illuminance levels of the ranges */
	double road_width_at_m[HL_CONFIG_ROAD_WIDTHS]; /* where the width is taken */
	/* [sched] */
	int rt_priority; /* SCHED_FIFO of the CAN and render threads; 0: SCHED_OTHER */
};

struct hl_config_error {
	char msg[512]; /* names the file (or "command line"), the line and the key */
};

void hl_config_defaults(struct hl_config *cfg);
/* Reads path over cfg. 0, -ENOENT/-errno (cannot open), -EINVAL (err says where). */
int hl_config_load(struct hl_config *cfg, const char *path, struct hl_config_error *err);
/* Sets one key ("section.key=value"); origin names where it came from in messages. */
int hl_config_set_arg(struct hl_config *cfg, const char *assignment, const char *origin,
		      struct hl_config_error *err);
int hl_config_set(struct hl_config *cfg, const char *section, const char *key, const char *value,
		  const char *origin, int line, struct hl_config_error *err);
/* Checks the whole (e.g. exactly one CAN input). 0 or -EINVAL. */
int hl_config_check(const struct hl_config *cfg, struct hl_config_error *err);
/* Writes every key with its value as an INI file (for --print-config and the docs). */
void hl_config_print(const struct hl_config *cfg, void *file);

#endif
