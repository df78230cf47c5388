/* SPDX-License-Identifier: MIT */
/*
 * daemon/loop/pose_input.c: the message parser (every result, the poses it sets and the ones it
 * leaves on the scenario's paths, the reasons it names) and the input over a real UDP socket on
 * the loopback: datagrams sent, counted by result, the newest good state handed over.
 */
#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <netinet/in.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "daemon/loop/pose_input.h"
#include "world/road.h"

static const char scenario_json[] =
	"{\"version\": 1, \"title\": \"poses\", \"duration_s\": 10,\n"
	" \"road\": {\"segments\": [{\"kind\": \"straight\", \"length_m\": 400}],\n"
	"          \"lanes\": {\"count\": 2, \"width_m\": 3.5}},\n"
	" \"ego\": {\"start_s_m\": 0, \"lane\": 1, \"speed_mps\": 10},\n"
	" \"actors\": [\n"
	"  {\"id\": \"oncoming\", \"kind\": \"car\", \"role\": \"oncoming\",\n"
	"   \"path\": {\"lane\": 2, \"start_s_m\": 200, \"speed_mps\": 20}},\n"
	"  {\"id\": \"ahead\", \"kind\": \"car\", \"role\": \"preceding\",\n"
	"   \"path\": {\"lane\": 1, \"start_s_m\": 60, \"speed_mps\": 15}}]}\n";

static struct hl_scenario *scenario(void)
{
	struct hl_scenario *sc = NULL;
	struct hl_json_error err;

	assert_int_equal(hl_scenario_parse(scenario_json, "poses.json", &sc, &err), 0);
	return sc;
}

static enum hl_pose_result parse(const struct hl_scenario *sc, const char *text,
				 struct hl_world_state *w, char *why)
{
	return hl_pose_parse(sc, text, strlen(text), w, why, 256);
}

static void pose_sets_named_users_and_leaves_the_others_on_their_paths(void **state)
{
	struct hl_scenario *sc = scenario();
	struct hl_world_state w, at;
	char why[256];

	(void)state;
	assert_int_equal(
		parse(sc,
		      "{\"t_s\": 2.5, \"ego\": {\"x_m\": 12, \"y_m\": -1.75, \"heading_deg\": 90},"
		      " \"actors\": [{\"id\": \"oncoming\", \"x_m\": 80.5, \"y_m\": 1.75,"
		      " \"heading_deg\": 180, \"lamps\": false}]}",
		      &w, why),
		HL_POSE_OK);
	hl_world_at(sc, 2.5, &at);
	assert_true(w.t_s == 2.5);
	assert_true(w.ego.pos_m[0] == 12.0 && w.ego.pos_m[1] == -1.75 && w.ego.pos_m[2] == 0.0);
	assert_true(fabs(w.ego.heading_rad - M_PI / 2) < 1e-15);
	assert_int_equal(w.n_actors, 2);
	assert_true(w.actor[0].pos_m[0] == 80.5 && w.actor[0].pos_m[1] == 1.75);
	assert_true(fabs(fabs(w.actor[0].heading_rad) - M_PI) < 1e-15);
	/* not named: where the scenario puts it at t_s; its lamps on, the named one's off */
	assert_memory_equal(&w.actor[1], &at.actor[1], sizeof(at.actor[1]));
	assert_int_equal(w.lamps_on, 0x2u);
	hl_scenario_free(sc);
}

static void bad_messages_are_told_apart_and_named(void **state)
{
	static const struct {
		const char *text;
		enum hl_pose_result r;
		const char *why;
	} cases[] = {
		{ "not json", HL_POSE_MALFORMED, "not JSON: 1:" },
		{ "[1, 2]", HL_POSE_MALFORMED, "expected one JSON object" },
		{ "{\"t_s\": 1, \"t_s\": 2, \"ego\": {}}", HL_POSE_MALFORMED, "not JSON" },
		{ "{\"ego\": {\"x_m\": 0, \"y_m\": 0, \"heading_deg\": 0}}", HL_POSE_INVALID,
		  "t_s: expected a number (s)" },
		{ "{\"t_s\": \"1\", \"ego\": {}}", HL_POSE_INVALID, "t_s: expected a number (s)" },
		{ "{\"t_s\": 1}", HL_POSE_INVALID, "ego: expected an object" },
		{ "{\"t_s\": 1, \"ego\": {\"x_m\": 0, \"y_m\": 0}}", HL_POSE_INVALID,
		  "ego.heading_deg: expected a number -3600..3600 (degrees)" },
		{ "{\"t_s\": 1, \"ego\": {\"x_m\": 0, \"y_m\": 0, \"heading_deg\": 0, \"z_m\": 1}}",
		  HL_POSE_INVALID, "ego.z_m: unknown key; expected x_m, y_m, heading_deg" },
		{ "{\"t_s\": 1, \"speed\": 3, \"ego\": {}}", HL_POSE_INVALID,
		  "speed: unknown key; expected t_s, ego, actors" },
		{ "{\"t_s\": 1, \"ego\": {\"x_m\": 0, \"y_m\": 0, \"heading_deg\": 0},"
		  " \"actors\": {}}",
		  HL_POSE_INVALID, "actors: expected an array" },
		{ "{\"t_s\": 1, \"ego\": {\"x_m\": 0, \"y_m\": 0, \"heading_deg\": 0},"
		  " \"actors\": [{\"id\": \"truck\", \"x_m\": 0, \"y_m\": 0, \"heading_deg\": 0}]}",
		  HL_POSE_UNKNOWN_ACTOR,
		  "actors[0].id 'truck': no road user of that id in the scenario" },
		{ "{\"t_s\": 1, \"ego\": {\"x_m\": 0, \"y_m\": 0, \"heading_deg\": 0},"
		  " \"actors\": [{\"id\": \"ahead\", \"x_m\": 0, \"y_m\": 0, \"heading_deg\": 0},"
		  " {\"id\": \"ahead\", \"x_m\": 1, \"y_m\": 0, \"heading_deg\": 0}]}",
		  HL_POSE_INVALID, "actors[1].id 'ahead': named twice" },
		{ "{\"t_s\": 1, \"ego\": {\"x_m\": 0, \"y_m\": 0, \"heading_deg\": 0},"
		  " \"actors\": [{\"id\": \"ahead\", \"x_m\": 0, \"y_m\": 0, \"heading_deg\": 0,"
		  " \"lamps\": 1}]}",
		  HL_POSE_INVALID, "actors[0].lamps: expected true or false" },
		{ "{\"t_s\": 1, \"ego\": {\"x_m\": 1e300, \"y_m\": 0, \"heading_deg\": 0}}",
		  HL_POSE_INVALID, "ego.x_m: expected a number (m)" },
	};
	struct hl_scenario *sc = scenario();

	(void)state;
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		struct hl_world_state w = { .t_s = -42.0 };
		char why[256] = "";

		assert_int_equal(parse(sc, cases[i].text, &w, why), cases[i].r);
		if (!strstr(why, cases[i].why))
			fail_msg("case %zu: '%s' does not hold '%s'", i, why, cases[i].why);
		assert_true(w.t_s == -42.0); /* untouched */
	}
	assert_string_equal(hl_pose_result_name(HL_POSE_UNKNOWN_ACTOR), "unknown_actor");
	assert_string_equal(hl_pose_result_name(HL_POSE_TOO_LARGE), "too_large");
	hl_scenario_free(sc);
}

static void wait_messages(struct hl_pose_input *pi, uint64_t n)
{
	for (int k = 0; k < 500; k++) {
		struct hl_pose_counts c;
		uint64_t sum = 0;

		hl_pose_input_counts(pi, &c);
		for (int r = 0; r < HL_POSE_N; r++)
			sum += c.messages[r];
		if (sum >= n)
			return;
		nanosleep(&(struct timespec){ 0, 10000000 }, NULL);
	}
	fail_msg("the input did not count %llu datagrams", (unsigned long long)n);
}

static void input_counts_datagrams_and_hands_over_the_newest(void **state)
{
	struct hl_scenario *sc = scenario();
	struct hl_pose_input *pi = NULL;
	struct sockaddr_in to = { .sin_family = AF_INET };
	struct hl_world_state w;
	struct hl_pose_counts c;
	char err[256];
	static char big[HL_POSE_MAX_DATAGRAM + 10];
	int64_t rx;
	int fd;

	(void)state;
	assert_int_equal(hl_pose_input_new("udp:127.0.0.1:0", sc, NULL, &pi, err, sizeof(err)), 0);
	assert_int_equal(hl_pose_input_new("tcp:127.0.0.1:0", sc, NULL, &pi, err, sizeof(err)),
			 -EINVAL);
	assert_string_equal(err, "pose.listen 'tcp:127.0.0.1:0': expected udp:HOST:PORT");
	assert_true(hl_pose_input_port(pi) > 0);
	assert_false(hl_pose_input_latest(pi, &w, &rx));
	assert_int_equal(hl_pose_input_start(pi), 0);
	fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
	assert_true(fd >= 0);
	to.sin_port = htons(hl_pose_input_port(pi));
	to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
	memset(big, ' ', sizeof(big));
	{
		const char *msgs[] = {
			"{\"t_s\": 1, \"ego\": {\"x_m\": 1, \"y_m\": 0, \"heading_deg\": 0}}",
			"garbage",
			"{\"t_s\": 2, \"ego\": {\"x_m\": 2, \"y_m\": 0, \"heading_deg\": 0}}",
		};

		for (int i = 0; i < 3; i++)
			assert_int_equal(sendto(fd, msgs[i], strlen(msgs[i]), 0,
						(struct sockaddr *)&to, sizeof(to)),
					 (ssize_t)strlen(msgs[i]));
	}
	assert_int_equal(sendto(fd, big, sizeof(big), 0, (struct sockaddr *)&to, sizeof(to)),
			 (ssize_t)sizeof(big));
	wait_messages(pi, 4);
	hl_pose_input_counts(pi, &c);
	assert_int_equal(c.messages[HL_POSE_OK], 2);
	assert_int_equal(c.messages[HL_POSE_MALFORMED], 1);
	assert_int_equal(c.messages[HL_POSE_TOO_LARGE], 1);
	assert_true(c.have && c.t_s == 2.0);
	assert_true(hl_pose_input_latest(pi, &w, &rx));
	assert_true(w.t_s == 2.0 && w.ego.pos_m[0] == 2.0 && rx == c.t_last_ok_ns);
	close(fd);
	hl_pose_input_free(pi);
	hl_scenario_free(sc);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(pose_sets_named_users_and_leaves_the_others_on_their_paths),
		cmocka_unit_test(bad_messages_are_told_apart_and_named),
		cmocka_unit_test(input_counts_datagrams_and_hands_over_the_newest),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
