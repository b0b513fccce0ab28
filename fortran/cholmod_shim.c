/*
 * A thin C layer over SuiteSparse's CHOLMOD (int32 interface, cholmod_*) for the
 * Fortran module sparse_cholesky, which binds these functions with ISO_C_BINDING.
 *
 * A factor object owns its own cholmod_common (so factors never share settings or
 * workspace), the lower triangle of the matrix (a cholmod_sparse holding the pattern and
 * the current values), the analysed and factored cholmod_factor, and the dense buffers
 * cholmod_solve2 reuses: once a solve with a given number of right-hand sides has run,
 * later solves with the same number allocate nothing (Davis, "User Guide for CHOLMOD",
 * SuiteSparse 5, section cholmod_solve2).  The factorization is LL' (Common->final_ll),
 * so a matrix that is not positive definite fails at the column where the pivot is not
 * positive.
 *
 * Compiled with -DPYGEAR_HAVE_CHOLMOD when the build found CHOLMOD; without it every
 * function returns PYGEAR_SP_UNAVAILABLE and the package still builds.
 *
 * Every function returns a status: 0 ok, otherwise one of the PYGEAR_SP_* codes below
 * (the same numbers as the sp_* parameters of module sparse_cholesky).
 */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define PYGEAR_SP_OK 0
#define PYGEAR_SP_UNAVAILABLE 1 /* built without CHOLMOD */
#define PYGEAR_SP_MEMORY 2      /* out of memory */
#define PYGEAR_SP_DEFINITE 3    /* not positive definite */
#define PYGEAR_SP_PATTERN 4     /* pattern not a sorted 0-based lower-triangle CSC */
#define PYGEAR_SP_ARGUMENT 5    /* null handle, size mismatch, nrhs < 1 */
#define PYGEAR_SP_FAILED 6      /* any other CHOLMOD failure */
#define PYGEAR_SP_UNFACTORED 7  /* the last factorization failed: no factor to solve with */

#ifdef PYGEAR_HAVE_CHOLMOD
#include <stdlib.h>
#include <cholmod.h>

/* One factor: its CHOLMOD state and the buffers its solves reuse. */
typedef struct {
    cholmod_common common;   /* this factor's own settings and workspace */
    cholmod_sparse *matrix;  /* lower triangle (stype -1): pattern and current values */
    cholmod_factor *factor;  /* analysed once, refactored in place */
    cholmod_dense *x;        /* solution buffer of cholmod_solve2 */
    cholmod_dense *y;        /* workspace of cholmod_solve2 */
    cholmod_dense *e;        /* workspace of cholmod_solve2 (supernodal) */
    int n;                   /* order of the matrix */
    int factored;            /* 1 when the last numeric factorization succeeded */
} pygear_cholmod_factor;

/* The status of a CHOLMOD call that failed, as a PYGEAR_SP_* code. */
static int failure_code(const cholmod_common *common)
{
    switch (common->status) {
    case CHOLMOD_OUT_OF_MEMORY:
    case CHOLMOD_TOO_LARGE:
        return PYGEAR_SP_MEMORY;
    case CHOLMOD_NOT_POSDEF:
        return PYGEAR_SP_DEFINITE;
    case CHOLMOD_INVALID:
        return PYGEAR_SP_PATTERN;
    default:
        return PYGEAR_SP_FAILED;
    }
}

/* Numeric factorization of the current values; *bad_column is the failing column of
 * the original matrix (0-based) when the matrix is not positive definite, else -1. */
static int factorize(pygear_cholmod_factor *self, int *bad_column)
{
    cholmod_common *common = &self->common;
    int ok = cholmod_factorize(self->matrix, self->factor, common);
    *bad_column = -1;
    self->factored = 0;
    if (!ok || common->status < CHOLMOD_OK) {
        return failure_code(common);
    }
    if (common->status == CHOLMOD_NOT_POSDEF || self->factor->minor < (size_t)self->n) {
        size_t minor = self->factor->minor;
        const int *perm = (const int *)self->factor->Perm;
        if (minor < (size_t)self->n) {
            *bad_column = perm != NULL ? perm[minor] : (int)minor;
        }
        return PYGEAR_SP_DEFINITE;
    }
    self->factored = 1;
    return PYGEAR_SP_OK;
}

/* 0 when column_start/row_index are a sorted, 0-based lower-triangle CSC of order n. */
static int check_pattern(int n, const int *column_start, const int *row_index)
{
    if (column_start[0] != 0) return PYGEAR_SP_PATTERN;
    for (int j = 0; j < n; j++) {
        if (column_start[j + 1] < column_start[j]) return PYGEAR_SP_PATTERN;
        for (int p = column_start[j]; p < column_start[j + 1]; p++) {
            int row = row_index[p];
            if (row < j || row >= n) return PYGEAR_SP_PATTERN;
            if (p > column_start[j] && row <= row_index[p - 1]) return PYGEAR_SP_PATTERN;
        }
    }
    return PYGEAR_SP_OK;
}

int pygear_cholmod_available(void) { return 1; }

int pygear_cholmod_create(int n, const int *column_start, const int *row_index,
                          const double *values, int ordering, int method, void **handle,
                          int *bad_column)
{
    pygear_cholmod_factor *self;
    cholmod_common *common;
    int status, nnz;

    *handle = NULL;
    *bad_column = -1;
    if (n < 1 || ordering < 0 || ordering > 2 || method < 0 || method > 2) {
        return PYGEAR_SP_ARGUMENT;
    }
    status = check_pattern(n, column_start, row_index);
    if (status != PYGEAR_SP_OK) return status;
    nnz = column_start[n];

    self = (pygear_cholmod_factor *)calloc(1, sizeof(pygear_cholmod_factor));
    if (self == NULL) return PYGEAR_SP_MEMORY;
    common = &self->common;
    if (!cholmod_start(common)) {
        free(self);
        return PYGEAR_SP_FAILED;
    }
    self->n = n;
    common->print = 0;              /* report through status codes, print nothing */
    common->error_handler = NULL;
    common->final_ll = 1;           /* LL': a non-positive pivot is an error */
    common->supernodal = method == 1   ? CHOLMOD_SIMPLICIAL
                         : method == 2 ? CHOLMOD_SUPERNODAL
                                       : CHOLMOD_AUTO;
    if (ordering == 1 || ordering == 2) {
        common->nmethods = 1;
        common->method[0].ordering = ordering == 1 ? CHOLMOD_NATURAL : CHOLMOD_AMD;
        common->postorder = ordering == 2; /* postordering would permute a natural order */
    }

    self->matrix = cholmod_allocate_sparse((size_t)n, (size_t)n, (size_t)nnz, 1, 1, -1,
                                           CHOLMOD_REAL, common);
    if (self->matrix == NULL) {
        status = failure_code(common);
        goto fail;
    }
    memcpy(self->matrix->p, column_start, sizeof(int) * (size_t)(n + 1));
    memcpy(self->matrix->i, row_index, sizeof(int) * (size_t)nnz);
    memcpy(self->matrix->x, values, sizeof(double) * (size_t)nnz);

    self->factor = cholmod_analyze(self->matrix, common);
    if (self->factor == NULL) {
        status = failure_code(common);
        goto fail;
    }
    status = factorize(self, bad_column);
    /* A matrix that is not positive definite still yields a factor object whose values
     * a refactor may repair; any other failure frees it. */
    if (status != PYGEAR_SP_OK && status != PYGEAR_SP_DEFINITE) goto fail;
    *handle = self;
    return status;

fail:
    cholmod_free_factor(&self->factor, common);
    cholmod_free_sparse(&self->matrix, common);
    cholmod_finish(common);
    free(self);
    return status;
}

int pygear_cholmod_refactor(void *handle, const double *values, int *bad_column)
{
    pygear_cholmod_factor *self = (pygear_cholmod_factor *)handle;
    *bad_column = -1;
    if (self == NULL) return PYGEAR_SP_ARGUMENT;
    memcpy(self->matrix->x, values,
           sizeof(double) * (size_t)((const int *)self->matrix->p)[self->n]);
    return factorize(self, bad_column);
}

int pygear_cholmod_solve(void *handle, int n, int nrhs, double *rhs)
{
    pygear_cholmod_factor *self = (pygear_cholmod_factor *)handle;
    cholmod_dense b;
    if (self == NULL || n != self->n || nrhs < 1) return PYGEAR_SP_ARGUMENT;
    if (!self->factored) return PYGEAR_SP_UNFACTORED;
    /* A header over the caller's array: B is read, never allocated or freed. */
    memset(&b, 0, sizeof(b));
    b.nrow = (size_t)n;
    b.ncol = (size_t)nrhs;
    b.nzmax = (size_t)n * (size_t)nrhs;
    b.d = (size_t)n;
    b.x = rhs;
    b.z = NULL;
    b.xtype = CHOLMOD_REAL;
    b.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A, self->factor, &b, NULL, &self->x, NULL, &self->y, &self->e,
                        &self->common)) {
        return failure_code(&self->common);
    }
    if (!self->factor->is_super && self->y != NULL) {
        /* The simplicial solve asks for Y as max(4, nrhs) x n (leading dimension the
         * same) and then shrinks Y's header to its last block of columns, so the next
         * call would find the "wrong" size and reallocate.  The block itself was
         * allocated at the full size in this call: restore the header to match it. */
        size_t rows = nrhs > 4 ? (size_t)nrhs : 4;
        self->y->nrow = rows;
        self->y->d = rows;
        self->y->nzmax = rows * (size_t)n;
    }
    memcpy(rhs, self->x->x, sizeof(double) * b.nzmax);
    return PYGEAR_SP_OK;
}

int pygear_cholmod_stats(void *handle, int64_t *nnz_factor, int *ordering, int *supernodal,
                         double *flops)
{
    pygear_cholmod_factor *self = (pygear_cholmod_factor *)handle;
    if (self == NULL) return PYGEAR_SP_ARGUMENT;
    *nnz_factor = (int64_t)self->common.lnz;
    *ordering = self->factor->ordering;
    *supernodal = self->factor->is_super ? 1 : 0;
    *flops = self->common.fl;
    return PYGEAR_SP_OK;
}

int pygear_cholmod_free(void *handle)
{
    pygear_cholmod_factor *self = (pygear_cholmod_factor *)handle;
    if (self == NULL) return PYGEAR_SP_OK;
    cholmod_free_dense(&self->x, &self->common);
    cholmod_free_dense(&self->y, &self->common);
    cholmod_free_dense(&self->e, &self->common);
    cholmod_free_factor(&self->factor, &self->common);
    cholmod_free_sparse(&self->matrix, &self->common);
    cholmod_finish(&self->common);
    free(self);
    return PYGEAR_SP_OK;
}

#else /* built without CHOLMOD: every call says so */

int pygear_cholmod_available(void) { return 0; }

int pygear_cholmod_create(int n, const int *column_start, const int *row_index,
                          const double *values, int ordering, int method, void **handle,
                          int *bad_column)
{
    (void)n, (void)column_start, (void)row_index, (void)values, (void)ordering, (void)method;
    *handle = NULL;
    *bad_column = -1;
    return PYGEAR_SP_UNAVAILABLE;
}

int pygear_cholmod_refactor(void *handle, const double *values, int *bad_column)
{
    (void)handle, (void)values;
    *bad_column = -1;
    return PYGEAR_SP_UNAVAILABLE;
}

int pygear_cholmod_solve(void *handle, int n, int nrhs, double *rhs)
{
    (void)handle, (void)n, (void)nrhs, (void)rhs;
    return PYGEAR_SP_UNAVAILABLE;
}

int pygear_cholmod_stats(void *handle, int64_t *nnz_factor, int *ordering, int *supernodal,
                         double *flops)
{
    (void)handle;
    *nnz_factor = 0;
    *ordering = -1;
    *supernodal = 0;
    *flops = 0.0;
    return PYGEAR_SP_UNAVAILABLE;
}

int pygear_cholmod_free(void *handle)
{
    (void)handle;
    return PYGEAR_SP_OK;
}

#endif
