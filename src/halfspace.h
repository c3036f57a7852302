/* halfspace.h: internals of the half-space JKR model (src/model_halfspace.c)
 * that the tests measure.  Not installed.
 *
 * With r = sqrt(a/a_s) (the scales of model_halfspace.c's header) the curve
 * of a power-law punch on a half-space is, for each k, one curve:
 *   delta/delta_s = D(r) = r^(2k) - r,   P/P_s = Pi(r) = 2k/(k+1) r^(2k+2) - 2 r^3.
 * The table holds, for each k, the stable branch's inverse: y = r - r_det
 * against s = delta/delta_s - D_det > 0. */
#ifndef LF_HALFSPACE_H
#define LF_HALFSPACE_H

#include "internal.h"

/* The largest relative errors, over every cell of the table of k (built
 * if need be) at several points inside each, of the interpolated y
 * (*interp) and of r after the one Newton step the model takes from it
 * (*final), against y solved to rounding.  LF_EINVAL for k <= 1/2,
 * LF_ENOMEM. */
int lf_halfspace_table_error(double k, double *interp, double *final);

/* r on the stable branch where D(r) = t (t > D_det), as the model
 * computes it (table, then one Newton step), and the same solved by
 * safeguarded Newton to rounding.  For tests. */
int lf_halfspace_invert(double k, double t, double *r_fast, double *r_precise);

#endif
