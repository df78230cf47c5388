/* SPDX-License-Identifier: MIT */
/*
 * The attribute and value sections (attributes.c), called by parse.c's top-level loop with
 * p->tok past the keyword. Each returns 0 or a negative errno, as the lexer's readers.
 */
#ifndef HL_DBC_ATTRIBUTES_H
#define HL_DBC_ATTRIBUTES_H

#include "dbc/lexer.h"

int dbc_parse_val_table(struct parser *p); /* VAL_TABLE_ */
int dbc_parse_ba_def(struct parser *p); /* BA_DEF_ */
int dbc_parse_ba_def_def(struct parser *p); /* BA_DEF_DEF_ */
int dbc_parse_ba(struct parser *p); /* BA_ */
int dbc_parse_val(struct parser *p); /* VAL_ */
int dbc_parse_sig_valtype(struct parser *p); /* SIG_VALTYPE_ */
/* SG_MUL_VAL_; kw_line, kw_col: where its keyword is. */
int dbc_parse_sg_mul_val(struct parser *p, int kw_line, int kw_col);

/* After parsing: CANdb++'s long names from the attributes replace the cut ones. */
void dbc_apply_long_names(struct hl_dbc *db);

#endif
