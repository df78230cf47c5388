/* SPDX-License-Identifier: MIT */
/* Between lid.c and the file reader only: hands a box-packed source to the lid. */
#ifndef HL_RENDER_LID_INTERNAL_H
#define HL_RENDER_LID_INTERNAL_H

#include "lamp/lid.h"

/* Takes ownership of packed (box width * box height floats, validated by the caller). */
void hl_lid_adopt_source(struct hl_lid *lid, int k, const struct hl_lid_box *box, float *packed);

#endif
