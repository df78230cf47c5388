/* SPDX-License-Identifier: MIT */
/*
 * hdlamp scenario validate / builtin: scenario files (docs/scenarios.md). validate checks files
 * and names each fault as FILE:LINE:COL: KEY: MESSAGE; builtin lists and writes the shipped
 * scenarios, read from the installed directory (world/scenario.h: hl_scenario_default_dir()).
 */
#include <dirent.h>
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "world/scenario.h"
#include "world/road.h"
#include "tools/commands.h"

static void usage_validate(FILE *f)
{
	fprintf(f,
		"usage: hdlamp scenario validate FILE...\n"
		"\n"
		"Checks scenario files (docs/scenarios.md). Prints 'FILE: ok' and a summary for\n"
		"each valid file, and FILE:LINE:COL: KEY: MESSAGE on standard error for each one\n"
		"that is not. Exit 0 when every file is valid, 1 when one is not, 2 on usage.\n");
}

static void usage_builtin(FILE *f)
{
	fprintf(f,
		"usage: hdlamp scenario builtin --list\n"
		"       hdlamp scenario builtin NAME --out FILE\n"
		"\n"
		"The shipped scenarios (share/hdlamp/scenarios beside the binary's directory).\n"
		"--list prints each one's name and title, tab-separated; NAME --out FILE writes\n"
		"the named one to FILE ('-': standard output) after checking it.\n");
}

/* Only these: no path can be smuggled in through a name. */
static int valid_name(const char *name)
{
	if (!*name || strlen(name) > 64 || name[0] == '-')
		return 0;
	for (const char *p = name; *p; p++)
		if (!((*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') || *p == '-' ||
		      *p == '_'))
			return 0;
	return 1;
}

static int is_json(const struct dirent *e)
{
	const size_t n = strlen(e->d_name);

	return n > 5 && e->d_name[0] != '.' && !strcmp(e->d_name + n - 5, ".json");
}

static void print_error(const struct hl_json_error *err)
{
	char line[1024];

	fprintf(stderr, "%s\n", hl_json_error_format(err, line, sizeof(line)));
}

int hl_cmd_scenario_validate(int argc, char **argv)
{
	int rc = HL_EXIT_OK;

	if (argc < 2) {
		usage_validate(stderr);
		return HL_EXIT_USAGE;
	}
	if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
		usage_validate(stdout);
		return HL_EXIT_OK;
	}
	for (int i = 1; i < argc; i++) {
		struct hl_scenario *sc;
		struct hl_json_error err;

		if (hl_scenario_read(argv[i], &sc, &err) < 0) {
			print_error(&err);
			rc = HL_EXIT_FAIL;
			continue;
		}
		printf("%s: ok: %.2f s, road %.1f m in %d segment(s), %d lane(s), %d road user(s)\n",
		       argv[i], sc->duration_s, sc->road.length_m, sc->road.n_segments,
		       sc->road.lanes, sc->n_actors);
		hl_scenario_free(sc);
	}
	return rc;
}

static int list(const char *dir)
{
	struct dirent **names;
	const int n = scandir(dir, &names, is_json, alphasort);
	int rc = HL_EXIT_OK;

	if (n < 0) {
		fprintf(stderr, "hdlamp scenario builtin: '%s': %s\n", dir, strerror(errno));
		return HL_EXIT_FAIL;
	}
	for (int i = 0; i < n; i++) {
		char path[4400];
		struct hl_scenario *sc;
		struct hl_json_error err;

		snprintf(path, sizeof(path), "%s/%s", dir, names[i]->d_name);
		names[i]->d_name[strlen(names[i]->d_name) - 5] = '\0';
		if (hl_scenario_read(path, &sc, &err) < 0) {
			print_error(&err);
			rc = HL_EXIT_FAIL;
		} else {
			printf("%s\t%s\n", names[i]->d_name, sc->title);
			hl_scenario_free(sc);
		}
		free(names[i]);
	}
	free(names);
	return rc;
}

/* Checks the shipped file, then copies its bytes as they are (comments of layout kept). */
static int write_builtin(const char *dir, const char *name, const char *out)
{
	char path[4200], *text;
	struct hl_scenario *sc;
	struct hl_json_error err;
	FILE *f;
	int rc;

	snprintf(path, sizeof(path), "%s/%s.json", dir, name);
	rc = hl_scenario_read(path, &sc, &err);
	if (rc == -ENOENT) {
		fprintf(stderr,
			"hdlamp scenario builtin: no built-in scenario '%s' in %s (see --list)\n",
			name, dir);
		return HL_EXIT_FAIL;
	}
	if (rc < 0) {
		print_error(&err);
		return HL_EXIT_FAIL;
	}
	hl_scenario_free(sc);
	if (hl_json_read_file(path, &text, &err) < 0) {
		print_error(&err);
		return HL_EXIT_FAIL;
	}
	f = strcmp(out, "-") ? fopen(out, "we") : stdout;
	if (!f) {
		fprintf(stderr, "hdlamp scenario builtin: cannot create '%s': %s\n", out,
			strerror(errno));
		free(text);
		return HL_EXIT_FAIL;
	}
	rc = fputs(text, f) < 0 ? HL_EXIT_FAIL : HL_EXIT_OK;
	if (f != stdout ? fclose(f) != 0 : fflush(f) != 0)
		rc = HL_EXIT_FAIL;
	if (rc != HL_EXIT_OK)
		fprintf(stderr, "hdlamp scenario builtin: cannot write '%s'\n", out);
	free(text);
	return rc;
}

int hl_cmd_scenario_builtin(int argc, char **argv)
{
	static const struct option opts[] = {
		{ "list", no_argument, NULL, 'l' },
		{ "out", required_argument, NULL, 'o' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *out = NULL;
	char dir[4096];
	int c, do_list = 0, rc;

	optind = 1;
	while ((c = getopt_long(argc, argv, "lo:h", opts, NULL)) != -1) {
		switch (c) {
		case 'l':
			do_list = 1;
			break;
		case 'o':
			out = optarg;
			break;
		case 'h':
			usage_builtin(stdout);
			return HL_EXIT_OK;
		default:
			usage_builtin(stderr);
			return HL_EXIT_USAGE;
		}
	}
	if (do_list ? (out || optind != argc) : (!out || optind != argc - 1)) {
		usage_builtin(stderr);
		return HL_EXIT_USAGE;
	}
	if (!do_list && !valid_name(argv[optind])) {
		fprintf(stderr,
			"hdlamp scenario builtin: '%s': expected a name like iihs-approach-straight "
			"(lower-case letters, digits, '-'; see --list)\n",
			argv[optind]);
		return HL_EXIT_USAGE;
	}
	rc = hl_scenario_default_dir(dir, sizeof(dir));
	if (rc < 0) {
		fprintf(stderr, "hdlamp scenario builtin: cannot find the scenarios: %s\n",
			strerror(-rc));
		return HL_EXIT_FAIL;
	}
	return do_list ? list(dir) : write_builtin(dir, argv[optind], out);
}
