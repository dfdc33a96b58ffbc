/* mat.c - small matrices, solve and pseudo-inverse (fc/mat.h). One source. */
#include "fc/mat.h"

#define MAT_X_MAT FC_SHIFT(MAT, MAT, MAT)

static bool size_fits(int rows, int cols)
{
    return rows >= 0 && cols >= 0 && rows <= FC_MAT_MAX_ROWS && cols <= FC_MAT_MAX_COLS;
}

fc_mat_status fc_mat_zero(fc_mat *m, int rows, int cols)
{
    for (int i = 0; i < FC_MAT_MAX_ROWS; i++) {
        for (int j = 0; j < FC_MAT_MAX_COLS; j++) {
            m->a[i][j] = FC_INT(0, MAT);
        }
    }
    if (!size_fits(rows, cols)) {
        m->rows = 0u;
        m->cols = 0u;
        return FC_MAT_BAD_SIZE;
    }
    m->rows = (uint8_t)rows;
    m->cols = (uint8_t)cols;
    return FC_MAT_OK;
}

fc_mat_status fc_mat_identity(fc_mat *m, int n)
{
    const fc_mat_status status = fc_mat_zero(m, n, n);
    for (int i = 0; i < m->rows; i++) {
        m->a[i][i] = FC_INT(1, MAT);
    }
    return status;
}

void fc_mat_transpose(const fc_mat *a, fc_mat *out)
{
    (void)fc_mat_zero(out, a->cols, a->rows);
    for (int i = 0; i < a->rows; i++) {
        for (int j = 0; j < a->cols; j++) {
            out->a[j][i] = a->a[i][j];
        }
    }
}

fc_mat_status fc_mat_mul(fc_arith *ar, const fc_mat *a, const fc_mat *b, fc_mat *out)
{
    if (a->cols != b->rows) {
        (void)fc_mat_zero(out, 0, 0);
        return FC_MAT_BAD_SIZE;
    }
    (void)fc_mat_zero(out, a->rows, b->cols);
    for (int i = 0; i < a->rows; i++) {
        for (int j = 0; j < b->cols; j++) {
            fc_acc sum = fc_acc_zero();
            for (int k = 0; k < a->cols; k++) {
                sum = fc_acc_mac(sum, a->a[i][k], b->a[k][j]);
            }
            out->a[i][j] = fc_acc_result(ar, sum, MAT_X_MAT);
        }
    }
    return FC_MAT_OK;
}

void fc_mat_mul_vec(fc_arith *ar, const fc_mat *a, const fc_real *x, fc_real *y)
{
    for (int i = 0; i < a->rows; i++) {
        fc_acc sum = fc_acc_zero();
        for (int k = 0; k < a->cols; k++) {
            sum = fc_acc_mac(sum, a->a[i][k], x[k]);
        }
        /* MAT times the format of x, back to the format of x */
        y[i] = fc_acc_result(ar, sum, FC_MAT_FRAC);
    }
}

static fc_real largest_magnitude(fc_arith *ar, const fc_mat *m)
{
    fc_real largest = FC_INT(0, MAT);
    for (int i = 0; i < m->rows; i++) {
        for (int j = 0; j < m->cols; j++) {
            largest = fc_max(largest, fc_abs(ar, m->a[i][j]));
        }
    }
    return largest;
}

static void swap_rows(fc_mat *m, int r1, int r2)
{
    for (int j = 0; j < m->cols; j++) {
        const fc_real t = m->a[r1][j];
        m->a[r1][j] = m->a[r2][j];
        m->a[r2][j] = t;
    }
}

/* row[target] -= factor * row[source] */
static void subtract_scaled_row(fc_arith *ar, fc_mat *m, int target, int source, fc_real factor)
{
    for (int j = 0; j < m->cols; j++) {
        m->a[target][j] = fc_sub(ar, m->a[target][j], fc_mul(ar, factor, m->a[source][j], MAT_X_MAT));
    }
}

static void divide_row(fc_arith *ar, fc_mat *m, int row, fc_real divisor)
{
    for (int j = 0; j < m->cols; j++) {
        m->a[row][j] = fc_div(ar, m->a[row][j], divisor, FC_DIV_SHIFT(MAT, MAT, MAT));
    }
}

fc_mat_status fc_mat_solve(fc_arith *ar, const fc_mat *a, const fc_mat *b, fc_mat *x)
{
    const int n = a->rows;
    if (a->cols != n || b->rows != n) {
        (void)fc_mat_zero(x, 0, 0);
        return FC_MAT_BAD_SIZE;
    }
    fc_mat work = *a;
    *x = *b;
    /* pivots smaller than this (relative to the largest entry) mean rank deficiency */
    const fc_real tolerance = fc_mul(ar, largest_magnitude(ar, a), FC_C(1.0e-5f, UNIT),
                                     FC_SHIFT(MAT, UNIT, MAT));
    for (int col = 0; col < n; col++) {
        int pivot_row = col;
        for (int r = col + 1; r < n; r++) {
            if (fc_abs(ar, work.a[r][col]) > fc_abs(ar, work.a[pivot_row][col])) {
                pivot_row = r;
            }
        }
        const fc_real pivot = work.a[pivot_row][col];
        if (!(fc_abs(ar, pivot) > tolerance) || !fc_is_finite(pivot)) {
            (void)fc_mat_zero(x, b->rows, b->cols);
            return FC_MAT_RANK_DEFICIENT;
        }
        swap_rows(&work, col, pivot_row);
        swap_rows(x, col, pivot_row);
        divide_row(ar, &work, col, pivot);
        divide_row(ar, x, col, pivot);
        for (int r = 0; r < n; r++) {
            if (r != col) {
                const fc_real factor = work.a[r][col];
                subtract_scaled_row(ar, &work, r, col, factor);
                subtract_scaled_row(ar, x, r, col, factor);
            }
        }
    }
    return FC_MAT_OK;
}

/* sum_k<count a[ra][k] b[rb][k] in MAT (one rounding) */
static fc_real row_dot(fc_arith *ar, const fc_mat *a, int ra, const fc_mat *b, int rb, int count)
{
    fc_acc sum = fc_acc_zero();
    for (int k = 0; k < count; k++) {
        sum = fc_acc_mac(sum, a->a[ra][k], b->a[rb][k]);
    }
    return fc_acc_result(ar, sum, MAT_X_MAT);
}

/*
 * x = G^-1 B for a symmetric positive definite G by Cholesky, G = L L^T, then
 * L y = B and L^T x = y. Unlike Gauss-Jordan, every intermediate is bounded:
 * |l_ij| <= sqrt(max g_ii) and |y| <= |B| / sqrt(lambda_min(G)), so a Gram
 * matrix whose inverse fits MAT is solved without leaving the format. A pivot
 * g_jj - sum l_jk^2 below 1e-5 of the largest entry of G is rank deficiency.
 */
static fc_mat_status solve_symmetric_positive_definite(fc_arith *ar, const fc_mat *g, const fc_mat *b, fc_mat *x)
{
    const int n = g->rows;
    fc_mat l;       /* the Cholesky factor, lower triangle */
    fc_mat y_t;     /* y transposed: row c is the solution column c */
    (void)fc_mat_zero(&l, n, n);
    (void)fc_mat_zero(&y_t, b->cols, n);
    const fc_real tolerance = fc_mul(ar, largest_magnitude(ar, g), FC_C(1.0e-5f, UNIT), FC_SHIFT(MAT, UNIT, MAT));
    fc_real inv_diag[FC_MAT_MAX_ROWS];
    for (int j = 0; j < n; j++) {
        const fc_real pivot = fc_sub(ar, g->a[j][j], row_dot(ar, &l, j, &l, j, j));
        if (!(pivot > tolerance) || !fc_is_finite(pivot)) {
            (void)fc_mat_zero(x, b->rows, b->cols);
            return FC_MAT_RANK_DEFICIENT;
        }
        l.a[j][j] = fc_sqrt(ar, pivot, FC_MAT_FRAC);
        inv_diag[j] = fc_div(ar, FC_INT(1, MAT), l.a[j][j], FC_DIV_SHIFT(MAT, MAT, MAT));
        for (int i = j + 1; i < n; i++) {
            const fc_real residual = fc_sub(ar, g->a[i][j], row_dot(ar, &l, i, &l, j, j));
            l.a[i][j] = fc_mul(ar, residual, inv_diag[j], MAT_X_MAT);
        }
    }
    /* forward: L y = b, one right-hand column at a time */
    for (int c = 0; c < b->cols; c++) {
        for (int i = 0; i < n; i++) {
            const fc_real residual = fc_sub(ar, b->a[i][c], row_dot(ar, &l, i, &y_t, c, i));
            y_t.a[c][i] = fc_mul(ar, residual, inv_diag[i], MAT_X_MAT);
        }
    }
    /* backward: L^T x = y */
    (void)fc_mat_zero(x, n, b->cols);
    for (int c = 0; c < b->cols; c++) {
        for (int i = n - 1; i >= 0; i--) {
            fc_acc sum = fc_acc_zero();
            for (int k = i + 1; k < n; k++) {
                sum = fc_acc_mac(sum, l.a[k][i], x->a[k][c]);
            }
            const fc_real residual = fc_sub(ar, y_t.a[c][i], fc_acc_result(ar, sum, MAT_X_MAT));
            x->a[i][c] = fc_mul(ar, residual, inv_diag[i], MAT_X_MAT);
        }
    }
    return FC_MAT_OK;
}

fc_mat_status fc_mat_pinv(fc_arith *ar, const fc_mat *a, fc_mat *out)
{
    fc_mat a_t;
    fc_mat gram;
    fc_mat_transpose(a, &a_t);
    if (a->rows <= a->cols) {
        /* full row rank: A+ = A^T (A A^T)^-1 = ((A A^T)^-1 A)^T, A A^T symmetric */
        fc_mat gram_inv_a;
        (void)fc_mat_mul(ar, a, &a_t, &gram);
        const fc_mat_status status = solve_symmetric_positive_definite(ar, &gram, a, &gram_inv_a);
        if (status != FC_MAT_OK) {
            (void)fc_mat_zero(out, a->cols, a->rows);
            return status;
        }
        fc_mat_transpose(&gram_inv_a, out);
        return FC_MAT_OK;
    }
    /* full column rank: A+ = (A^T A)^-1 A^T */
    (void)fc_mat_mul(ar, &a_t, a, &gram);
    const fc_mat_status status = solve_symmetric_positive_definite(ar, &gram, &a_t, out);
    if (status != FC_MAT_OK) {
        (void)fc_mat_zero(out, a->cols, a->rows);
    }
    return status;
}
