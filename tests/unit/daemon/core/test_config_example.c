/* SPDX-License-Identifier: MIT */
/*
 * systemd/hdlampd.conf, the example installed as /etc/hdlampd/hdlampd.conf: it loads and checks
 * cleanly, lists every key of daemon/core/config.c's table (each once, in its section), and holds
 * the bench values docs/daemon.md describes.
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "daemon/core/config.h"

#define MAX_KEYS 128

struct keyset {
	int n;
	char key[MAX_KEYS][136]; /* "section.name" */
};

/* The "section.name" of every "name = value" line of an INI text. */
static void collect(FILE *f, struct keyset *ks)
{
	char line[1024], section[64] = "", name[64];

	ks->n = 0;
	while (fgets(line, sizeof(line), f)) {
		if (sscanf(line, "[%63[^]]]", section) == 1)
			continue;
		if (line[0] == ';' || sscanf(line, "%63s =", name) != 1 || !strstr(line, " ="))
			continue;
		assert_true(ks->n < MAX_KEYS);
		snprintf(ks->key[ks->n++], sizeof(ks->key[0]), "%s.%s", section, name);
	}
}

static int count(const struct keyset *ks, const char *key)
{
	int n = 0;

	for (int i = 0; i < ks->n; i++)
		n += strcmp(ks->key[i], key) == 0;
	return n;
}

static const char *example_path(char *buf, size_t size)
{
	const char *src = getenv("HL_SOURCE_DIR");

	assert_non_null(src);
	snprintf(buf, size, "%s/systemd/hdlampd.conf", src);
	return buf;
}

static void config_example_loads_and_checks(void **state)
{
	struct hl_config cfg;
	struct hl_config_error err = { .msg = "" };
	char path[1024];
	(void)state;

	hl_config_defaults(&cfg);
	assert_int_equal(hl_config_load(&cfg, example_path(path, sizeof(path)), &err), 0);
	assert_int_equal(hl_config_check(&cfg, &err), 0);
	assert_string_equal(cfg.interface, "can0");
	assert_string_equal(cfg.replay, "");
	assert_string_equal(cfg.dbc, "/usr/share/hdlamp/dbc/hd84.dbc");
	assert_string_equal(cfg.lid_left, "/var/lib/hdlampd/lamps/hd84_left.lid.exr");
	assert_string_equal(cfg.lid_right, "/var/lib/hdlampd/lamps/hd84_right.lid.exr");
	assert_string_equal(cfg.capture_dir, "/var/lib/hdlampd/captures");
	assert_string_equal(cfg.stream_unix, "/run/hdlampd/frames.sock");
	assert_string_equal(cfg.http_listen, "127.0.0.1:8080");
	assert_false(cfg.http_capture);
	assert_string_equal(cfg.gpio_chip, "");
	assert_string_equal(cfg.gpio_trigger_edge, "rising");
}

static void config_example_lists_every_key_once(void **state)
{
	static struct keyset table, example;
	struct hl_config cfg;
	char path[1024], *text = NULL;
	size_t size = 0;
	FILE *f;
	(void)state;

	/* The table's keys, as hl_config_print writes them. */
	hl_config_defaults(&cfg);
	f = open_memstream(&text, &size);
	assert_non_null(f);
	hl_config_print(&cfg, f);
	fclose(f);
	f = fmemopen(text, size, "r");
	assert_non_null(f);
	collect(f, &table);
	fclose(f);
	free(text);
	assert_true(table.n >= 30);

	f = fopen(example_path(path, sizeof(path)), "r");
	assert_non_null(f);
	collect(f, &example);
	fclose(f);

	for (int i = 0; i < table.n; i++) {
		if (count(&example, table.key[i]) != 1)
			fail_msg("systemd/hdlampd.conf: key '%s' appears %d times, not once",
				 table.key[i], count(&example, table.key[i]));
	}
	for (int i = 0; i < example.n; i++)
		if (count(&table, example.key[i]) != 1)
			fail_msg("systemd/hdlampd.conf: '%s' is not a key of daemon/core/config.c",
				 example.key[i]);
	assert_int_equal(example.n, table.n);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(config_example_loads_and_checks),
		cmocka_unit_test(config_example_lists_every_key_once),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
