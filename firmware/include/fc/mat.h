/*
 * fc/mat.h - small fixed-size matrices for control allocation.
 *
 * Storage is fixed at compile time (FC_MAT_MAX_ROWS x FC_MAT_MAX_COLS); a
 * matrix uses the top-left rows x cols block. Entries are in MAT format
 * (Q7.24 in fixed: [-128, 128), resolution 6e-8): a caller whose entries have
 * other units scales its rows first (allocation normalises rows, so the
 * effectiveness matrix and its inverse stay inside that range).
 *
 * The solve and the pseudo-inverse divide and are meant for init time.
 */
#ifndef FC_MAT_H
#define FC_MAT_H

#include "fc/scalar.h"

#define FC_MAT_MAX_ROWS 8
#define FC_MAT_MAX_COLS 8

typedef struct fc_mat {
    uint8_t rows, cols;
    fc_real a[FC_MAT_MAX_ROWS][FC_MAT_MAX_COLS];
} fc_mat;

typedef enum fc_mat_status {
    FC_MAT_OK = 0,
    FC_MAT_BAD_SIZE,     /* dimensions too large or not compatible */
    FC_MAT_RANK_DEFICIENT /* a pivot fell below the rank tolerance */
} fc_mat_status;

/* rows x cols of zeros; FC_MAT_BAD_SIZE (and a 0 x 0 matrix) when too large. */
fc_mat_status fc_mat_zero(fc_mat *m, int rows, int cols);

/* n x n identity. */
fc_mat_status fc_mat_identity(fc_mat *m, int n);

/* out = a^T; out must not alias a. */
void fc_mat_transpose(const fc_mat *a, fc_mat *out);

/* out = a b. out must not alias a or b. */
fc_mat_status fc_mat_mul(fc_arith *ar, const fc_mat *a, const fc_mat *b, fc_mat *out);

/* y = A x for a vector x of a.cols entries in any format; y in the format of
 * x (the MAT factor is shifted out). */
void fc_mat_mul_vec(fc_arith *ar, const fc_mat *a, const fc_real *x, fc_real *y);

/* x = A^-1 B for square A (Gauss-Jordan with partial pivoting). A pivot whose
 * size is below 1e-5 of the largest entry of A is rank deficiency. In fixed the
 * intermediates (rows divided by their pivots) must stay inside MAT as well as
 * the result: fine for diagonally dominant A, not for any A whose inverse fits. */
fc_mat_status fc_mat_solve(fc_arith *ar, const fc_mat *a, const fc_mat *b, fc_mat *x);

/* Moore-Penrose pseudo-inverse of a full-rank matrix: A^T (A A^T)^-1 when
 * rows <= cols (full row rank), (A^T A)^-1 A^T otherwise, the Gram matrix
 * solved by Cholesky (its intermediates stay bounded, unlike Gauss-Jordan's).
 * Rank deficiency is a Cholesky pivot below 1e-5 of the Gram matrix's largest
 * entry (a singular value below ~3e-3 of the largest). Rank-deficient
 * input gives FC_MAT_RANK_DEFICIENT and leaves out as a zero matrix. */
fc_mat_status fc_mat_pinv(fc_arith *ar, const fc_mat *a, fc_mat *out);

#endif /* FC_MAT_H */
