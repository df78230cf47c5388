/* SPDX-License-Identifier: MIT */
/*
 * Where the shipped data is: share/hdlamp/NAME beside the running executable's bin/ directory
 * (/usr/bin/hdlamp -> /usr/share/hdlamp/NAME; in the build tree the build links
 * build/share/hdlamp/NAME to the source's NAME/). The one place the regulation sets
 * (hl_regulation_default_dir()) and the scenarios (hl_scenario_default_dir()) are looked for.
 *
 * Thread-safety: any thread.
 */
#ifndef HL_BASE_SHARE_DIR_H
#define HL_BASE_SHARE_DIR_H

#include <stddef.h>

/* "<the executable's directory>/../share/hdlamp/NAME" into buf. 0, -ENAMETOOLONG, -errno. */
int hl_share_dir(const char *name, char *buf, size_t size);
/* "<the executable's directory>/REL" into buf (the FMU's shared object: ../lib/hdlamp/...). */
int hl_exe_relative(const char *rel, char *buf, size_t size);

#endif
