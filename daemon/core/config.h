/* SPDX-License-Identifier: MIT */
/*
 * hdlampd's configuration: an INI file (inih) with command-line overrides
 * (--set SECTION.KEY=VALUE and the short options). Every key is listed in config.c's table and
 * in hdlampd.conf(5). Each value's whole syntax and range is checked when it is set; the files
 * the keys name are checked once everything is set (hl_config_check_files). An unknown key or a
 * bad value is an error naming where it was set (the file and line, or the option) and the key.
 *
 * Thread-safety: loaded by the main thread; the other threads get a copy.
 */
#ifndef HL_DAEMON_CORE_CONFIG_H
#define HL_DAEMON_CORE_CONFIG_H

#include <stdbool.h>

#include "daemon/core/config_syntax.h" /* HL_CONFIG_MAX_SETS, HL_CONFIG_SET_ID */

#define HL_CONFIG_PATH 512
#define HL_CONFIG_NAME 64
#define HL_CONFIG_ROAD_LEVELS 2 /* render/road_kpi.h: HL_ROAD_KPI_LEVELS */
#define HL_CONFIG_ROAD_WIDTHS 2 /* render/road_kpi.h: HL_ROAD_KPI_WIDTHS */
#define HL_CONFIG_MAX_KEYS 80 /* keys in config.c's table, at most */
#define HL_CONFIG_MAX_WARNINGS 8 /* listed one by one; the rest counted */

/* Where a key's value came from, for messages about it after loading. */
struct hl_config_origin {
	const char *origin; /* borrowed from the caller of hl_config_set (a path, an option as
			     * given); NULL: the default */
	int line; /* in the file origin, 0 for the command line */
};

enum hl_failsafe {
	HL_FAILSAFE_HOLD, /* keep the last valid intensities */
	HL_FAILSAFE_DARK, /* all sources off */
	HL_FAILSAFE_PRESET, /* a preset's values (failsafe_preset) */
};

/* The virtual bus an in-process ECU (ecu.model) runs on: can.interface and restbus.interface. */
#define HL_CONFIG_VBUS "vbus0"

struct hl_config {
	/* [can] */
	char interface[HL_CONFIG_NAME]; /* SocketCAN interface, or "" */
	char replay[HL_CONFIG_PATH]; /* candump log, or "" */
	bool replay_fast, replay_loop;
	int replay_passes; /* with replay_loop: stop after this many passes, 0 = never */
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
	int stream_stall_timeout_ms; /* a client taking no byte of its frame this long is dropped */
	/* [http] */
	char http_listen[HL_CONFIG_NAME]; /* host:port or "" */
	bool http_capture; /* allow POST /capture */
	/* [capture] */
	char capture_dir[HL_CONFIG_PATH];
	int capture_queue; /* captures waiting or being written at once (daemon/out/capture_queue.h) */
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
	/* [scene] */
	char scenario[HL_CONFIG_PATH]; /* scenario file (world/scenario.h), or "" */
	char glare_set[HL_CONFIG_SET_ID]; /* the regulation set of the live glare limits */
	int glare_history; /* frames /glare.json keeps */
	char world[HL_CONFIG_PATH]; /* osi:file:PATH | osi:udp:HOST:PORT (docs/osi.md), or "" */
	char world_message[HL_CONFIG_NAME]; /* auto | ground-truth | sensor-view */
	double world_timeout_s; /* a live world this old is none */
	double world_wait_s; /* for the first live message at start */
	/* [pose] */
	char pose_listen[HL_CONFIG_NAME]; /* udp:HOST:PORT of the pose input, or "" */
	/* [restbus] */
	char restbus_interface[HL_CONFIG_NAME]; /* SocketCAN interface of the restbus, or "" */
	/* [ecu] the ECU in process on the virtual bus HL_CONFIG_VBUS: "reference", an FMU, "" */
	char ecu_model[HL_CONFIG_PATH];
	char ecu_faults[HL_CONFIG_NAME]; /* comma separated, hdlamp ecu's --fault names */
	char restbus_dbc[HL_CONFIG_PATH]; /* the input database; "": the shipped hd84_inputs.dbc */
	double restbus_camera_pos_m[3]; /* the camera, ego body frame */
	double restbus_fov_deg[2]; /* horizontal, vertical field of view (full angles) */
	double restbus_range_m;
	char restbus_light_switch[HL_CONFIG_NAME]; /* off | auto | low | high */
	bool restbus_adb_enable;
	/* [loop] (daemon/loop/loop_latency.h, docs/loop.md) */
	double loop_reaction_ms; /* glare allowed this long after entering the camera's view */
	char loop_events[HL_CONFIG_PATH]; /* JSON lines per event: a file, "-" stdout, "" none */
	bool loop_exit_at_end; /* stop at the scenario's end */
	char loop_report[HL_CONFIG_PATH]; /* the run's JSON report at exit, or "" */
	char loop_junit[HL_CONFIG_PATH]; /* the run's verdicts as JUnit XML at exit, or "" */
	/* [sched] */
	int rt_priority; /* SCHED_FIFO of the CAN and render threads (stream: one below); 0: off */
	/* where each key of config.c's table was last set, by its index there */
	struct hl_config_origin set_at[HL_CONFIG_MAX_KEYS];
};

struct hl_config_error {
	char msg[512]; /* names the file and line (or the option), and the key */
	/* hl_config_load: keys set more than once in the file (the last value counts), each
	 * naming both lines; n_warnings counts them all, the first HL_CONFIG_MAX_WARNINGS listed */
	int n_warnings;
	char warnings[HL_CONFIG_MAX_WARNINGS][320];
};

void hl_config_defaults(struct hl_config *cfg);
/*
 * (config_file.c) Reads path over cfg (path is kept in cfg->set_at: it must outlive cfg's messages). 0,
 * -ENOENT/-errno (cannot open; err says so), -EINVAL (err says where); err's warnings are set
 * in every case.
 */
int hl_config_load(struct hl_config *cfg, const char *path, struct hl_config_error *err);
/*
 * Sets one key ("section.key=value"); origin names where it came from in messages, e.g. the
 * option as given ("--set render.view=lux"), and is kept in cfg->set_at (borrowed).
 */
int hl_config_set_arg(struct hl_config *cfg, const char *assignment, const char *origin,
		      struct hl_config_error *err);
/* The same, line > 0 for a line of the file origin. 0 or -EINVAL (cfg untouched). */
int hl_config_set(struct hl_config *cfg, const char *section, const char *key, const char *value,
		  const char *origin, int line, struct hl_config_error *err);
/* Checks the whole (e.g. exactly one CAN input). 0 or -EINVAL. */
int hl_config_check(const struct hl_config *cfg, struct hl_config_error *err);
/*
 * Checks the files the keys name, as they are now: the replay log (a readable file with at
 * least one frame; "-" is not checked), the DBC, and when render is set the lamps' LID files
 * (the first two lamps of can.lamps), the fail-safe preset and the Unix socket's directory.
 * 0, or -EINVAL with err naming where the key was set, the key, the file and why.
 */
int hl_config_check_files(const struct hl_config *cfg, bool render, struct hl_config_error *err);
/* Writes every key with its value as an INI file (for --print-config and the docs). */
void hl_config_print(const struct hl_config *cfg, void *file);

#endif
