/* SPDX-License-Identifier: MIT */
/*
 * Judging a suite's measurements (docs/lab.md "How a bin is judged"): which bin a range falls
 * in, the rounding of a bin's maximum, and the cases of one scenario variant built from its
 * samples — an FMVSS 108 bin at a photometer, an R149 glare-table row.
 *
 * The bin rule: a limit table gives its bins to 0.1 m ("15.0-29.9", "30.0-59.9"); a bin holds
 * the ranges from its lower bound up to the next bin's lower bound when the next one follows
 * it within 0.1 m (so 29.95 m is in 15.0-29.9 and 30.0 m in 30.0-59.9), and up to its own upper
 * bound inclusive when no bin follows (120.0-220: 220.0 m is in it, 220.01 m in none). A
 * range below the first bound is in none. Samples outside the variant's measured range
 * (Table XXII) are not judged.
 *
 * Thread-safety: plain functions over the caller's data.
 */
#ifndef HL_VERDICT_SUITE_JUDGE_H
#define HL_VERDICT_SUITE_JUDGE_H

#include "verdict/glare.h"
#include "verdict/suite.h"
#include "verdict/suite_result.h"

/* The index in s->bin[] of the bin of role holding range_m, or -1. */
int hl_suite_bin_of(const struct hl_suite *s, enum hl_actor_role role, double range_m);

/*
 * v rounded by the suite's rule to its decimals (half-even: ASTM E29's; half-up); v itself
 * without a rounding rule. A value within 1e-9 of a tie is a tie (a measured 0.25 is not
 * 0.2499999).
 */
double hl_suite_round(const struct hl_suite *s, double v);

/*
 * A new case at the end of v->cases: zeroed, its numbers (and limit) NAN, no bin or photometer; NULL when
 * out of memory (v unchanged).
 */
struct hl_suite_case *hl_suite_case_add(struct hl_suite_variant *v);

/*
 * The FMVSS cases of a variant: one per bin of role that overlaps the variant's measured range
 * and per photometer of that role, in bin order, then photometer order. 0, -ENOMEM.
 */
int hl_suite_fmvss_cases(const struct hl_suite *s, enum hl_actor_role role,
			 struct hl_suite_variant *v);
/* One measurement at suite photometer pm. */
void hl_suite_fmvss_sample(const struct hl_suite *s, struct hl_suite_variant *v, int pm,
			   double range_m, double lx, double t_s);

/*
 * The R149 cases of a variant: one per tabulated distance of the glare plan's rows of role
 * within the measured range (the rows of a distance hold from it up to the next one). 0,
 * -ENOMEM.
 */
int hl_suite_r149_cases(const struct hl_regulation *reg, enum hl_actor_role role,
			struct hl_suite_variant *v);
/* One glare result (the stimulus vehicle's). */
void hl_suite_r149_sample(struct hl_suite_variant *v, const struct hl_glare_result *r);

/*
 * Ends judging: rounds each case's maximum, compares it with the limit, sets margin, pass,
 * no_samples. Works on every kind of case.
 */
void hl_suite_judge_finish(const struct hl_suite *s, struct hl_suite_variant *v);

#endif
