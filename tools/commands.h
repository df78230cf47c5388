/* SPDX-License-Identifier: MIT */
/* The subcommands of the hdlamp tool; each returns the exit code (0 ok, 1 failure, 2 usage). */
#ifndef HL_TOOLS_COMMANDS_H
#define HL_TOOLS_COMMANDS_H

#include <stddef.h>

#define HL_EXIT_OK 0
#define HL_EXIT_FAIL 1
#define HL_EXIT_USAGE 2

int hl_cmd_model(int argc, char **argv);
int hl_cmd_lid(int argc, char **argv);
int hl_cmd_dbc(int argc, char **argv);
int hl_cmd_scenario(int argc, char **argv);
int hl_cmd_render(int argc, char **argv);
int hl_cmd_glare(int argc, char **argv);
int hl_cmd_ecu(int argc, char **argv);
int hl_cmd_sil(int argc, char **argv);
int hl_cmd_suite(int argc, char **argv);
/* hdlamp batch (cmd_batch.c): argv[1] is the verb (tools/batch.h). */
int hl_cmd_batch(int argc, char **argv);
/* hdlamp lid import / export (cmd_lid_import.c); argv[0] is the verb. */
int hl_cmd_lid_import(int argc, char **argv);
int hl_cmd_lid_export(int argc, char **argv);
/* hdlamp scenario validate / builtin (cmd_scenario_file.c); argv[0] is the verb. */
int hl_cmd_scenario_validate(int argc, char **argv);
int hl_cmd_scenario_builtin(int argc, char **argv);
/* hdlamp scenario osi (cmd_scenario_osi.c): a scenario as an ASAM OSI trace. */
int hl_cmd_scenario_osi(int argc, char **argv);
/* hdlamp render --scenario (cmd_render_scenario.c): argv as hdlamp render's. */
int hl_cmd_render_scenario(int argc, char **argv);
/* hdlamp lid check (cmd_lid_check.c); argv[0] is the verb. */
int hl_cmd_lid_check(int argc, char **argv);

/*
 * hdlampd beside this binary (installed) or in the build tree's daemon/ (tools/cmd_suite.c).
 * 0 or -ENOENT.
 */
int hl_cli_hdlampd_path(char *buf, size_t size);

struct hl_lid;
/*
 * The distribution of one lamp of a LID file: a combined file as it is, a source file under the
 * preset's values for side (every source at full current without a preset). Prints what is
 * wrong. 0 or -errno; *ret is malloc'd (grid layout, cd).
 */
int hl_cli_lid_distribution(const struct hl_lid *lid, const char *preset_path, int side,
			    float **ret);

#endif
