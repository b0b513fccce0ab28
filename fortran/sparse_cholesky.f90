!> Sparse Cholesky factorization A = L L' of a symmetric positive definite matrix, by
!> SuiteSparse's CHOLMOD (Chen, Davis, Hager & Rajamanickam, "Algorithm 887: CHOLMOD,
!> supernodal sparse Cholesky factorization and update/downdate", ACM TOMS 35(3), 2008)
!> through the C layer fortran/cholmod_shim.c.
!>
!> A factor is analysed (fill-reducing ordering, symbolic factorization) once, when it
!> is created; sparse_factor_refactor computes a new numeric factorization for new
!> values on the same pattern, and the solves reuse the factor's buffers, so that a
!> time-stepping loop allocates nothing once its first solve has run.  The matrix
!> crosses as its lower triangle in compressed sparse columns, 0-based and sorted
!> within each column: scipy's indptr and indices of scipy.sparse.tril(A).tocsc().
!>
!> A build without CHOLMOD keeps this module: sparse_cholesky_available() is then
!> false and every call returns sp_err_unavailable.
module sparse_cholesky
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_int, c_int64_t, c_double, &
                                         c_associated
  use kinds, only: dp, ik
  use handles, only: handle_registry, keep_item, find_item, release_item, hd_ok, hd_err_full
  implicit none
  private

  public :: sparse_factor, sparse_factor_create, sparse_factor_refactor, &
            sparse_factor_solve, sparse_factor_solve_columns, sparse_factor_free, &
            sparse_factor_stats, sparse_cholesky_available, &
            sp_ok, sp_err_unavailable, sp_err_memory, sp_err_definite, sp_err_pattern, &
            sp_err_argument, sp_err_failed, sp_err_unfactored
  public :: keep_sparse_factor, sparse_factor_at, free_sparse_factor, sp_err_handle, sp_err_full
  public :: sp_ordering_auto, sp_ordering_natural, sp_ordering_amd
  public :: sp_method_auto, sp_method_simplicial, sp_method_supernodal

  ! Error codes: the same numbers as the PYGEAR_SP_* codes of cholmod_shim.c.
  integer(ik), parameter :: sp_ok = 0               !< success
  integer(ik), parameter :: sp_err_unavailable = 1  !< built without CHOLMOD
  integer(ik), parameter :: sp_err_memory = 2       !< out of memory
  integer(ik), parameter :: sp_err_definite = 3     !< not positive definite (bad names the column)
  integer(ik), parameter :: sp_err_pattern = 4      !< not a sorted 0-based lower-triangle CSC
  integer(ik), parameter :: sp_err_argument = 5     !< no factor, a size that does not match, nrhs < 1
  integer(ik), parameter :: sp_err_failed = 6       !< any other CHOLMOD failure
  integer(ik), parameter :: sp_err_unfactored = 7   !< the last factorization failed: nothing to solve with
  integer(ik), parameter :: sp_err_handle = 8       !< not the handle of a live factor
  integer(ik), parameter :: sp_err_full = 9         !< the factor registry is full

  ! Orderings (the ordering argument of sparse_factor_create).
  integer(ik), parameter :: sp_ordering_auto = 0     !< CHOLMOD's choice: AMD, METIS when AMD fills much
  integer(ik), parameter :: sp_ordering_natural = 1  !< no permutation (a banded matrix keeps its band)
  integer(ik), parameter :: sp_ordering_amd = 2      !< approximate minimum degree
  ! Methods (the method argument of sparse_factor_create).
  integer(ik), parameter :: sp_method_auto = 0         !< CHOLMOD chooses by flops per nonzero
  integer(ik), parameter :: sp_method_simplicial = 1   !< column by column, up-looking
  integer(ik), parameter :: sp_method_supernodal = 2   !< dense blocks through the BLAS

  !> One factorization: the shim's object and the order of the matrix.
  type :: sparse_factor
    type(c_ptr) :: handle = c_null_ptr  !< the shim's factor object, null when none
    integer(ik) :: n = 0                !< order of the matrix [-]
    integer(ik) :: nnz = 0              !< stored entries of the lower triangle [-]
  end type sparse_factor

  !> Factors that Python uses, kept under handles (module handles).
  type(handle_registry), save :: registry

  interface
    function shim_available() result(available) bind(c, name='pygear_cholmod_available')
      import :: c_int
      integer(c_int) :: available
    end function shim_available

    function shim_create(n, column_start, row_index, values, ordering, method, handle, &
                         bad_column) result(status) bind(c, name='pygear_cholmod_create')
      import :: c_int, c_double, c_ptr
      integer(c_int), value :: n                   !< order of the matrix [-]
      integer(c_int), intent(in) :: column_start(*)  !< column starts, 0-based [-]
      integer(c_int), intent(in) :: row_index(*)     !< row indices, 0-based [-]
      real(c_double), intent(in) :: values(*)        !< lower-triangle values [matrix units]
      integer(c_int), value :: ordering            !< ordering code [-]
      integer(c_int), value :: method              !< method code [-]
      type(c_ptr), intent(out) :: handle           !< the factor object, null on error
      integer(c_int), intent(out) :: bad_column    !< failing column, 0-based, -1 none [-]
      integer(c_int) :: status
    end function shim_create

    function shim_refactor(handle, values, bad_column) result(status) &
        bind(c, name='pygear_cholmod_refactor')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: handle                 !< the factor object
      real(c_double), intent(in) :: values(*)      !< lower-triangle values [matrix units]
      integer(c_int), intent(out) :: bad_column    !< failing column, 0-based, -1 none [-]
      integer(c_int) :: status
    end function shim_refactor

    function shim_solve(handle, n, nrhs, rhs) result(status) bind(c, name='pygear_cholmod_solve')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: handle                 !< the factor object
      integer(c_int), value :: n                   !< order of the matrix [-]
      integer(c_int), value :: nrhs                !< right-hand sides [-]
      real(c_double), intent(inout) :: rhs(*)      !< b in, x out, n x nrhs [rhs units]
      integer(c_int) :: status
    end function shim_solve

    function shim_stats(handle, nnz_factor, ordering, supernodal, flops) result(status) &
        bind(c, name='pygear_cholmod_stats')
      import :: c_int, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: handle                    !< the factor object
      integer(c_int64_t), intent(out) :: nnz_factor   !< nonzeros of L [-]
      integer(c_int), intent(out) :: ordering         !< CHOLMOD's code of the ordering used [-]
      integer(c_int), intent(out) :: supernodal       !< 1 supernodal, 0 simplicial [-]
      real(c_double), intent(out) :: flops            !< flops of the factorization [-]
      integer(c_int) :: status
    end function shim_stats

    function shim_free(handle) result(status) bind(c, name='pygear_cholmod_free')
      import :: c_int, c_ptr
      type(c_ptr), value :: handle                 !< the factor object
      integer(c_int) :: status
    end function shim_free
  end interface

contains

  !> True when the kernel was built with CHOLMOD.
  logical function sparse_cholesky_available()
    sparse_cholesky_available = shim_available() /= 0
  end function sparse_cholesky_available

  !> Analyse and factor the matrix whose lower triangle column_start, row_index and
  !> values hold.  On sp_err_definite the factor is kept (a refactor with other values
  !> may succeed) and bad names the column; on any other error factor stays empty.
  subroutine sparse_factor_create(n, column_start, row_index, values, ordering, method, &
                                  factor, bad, ierr)
    integer(ik), intent(in) :: n                    !< order of the matrix [-]
    integer(ik), intent(in) :: column_start(:)      !< n+1 column starts, 0-based (indptr) [-]
    integer(ik), intent(in) :: row_index(:)         !< row of each value, 0-based (indices) [-]
    real(dp), intent(in) :: values(:)               !< the lower triangle's values [matrix units]
    integer(ik), intent(in) :: ordering             !< sp_ordering_* code [-]
    integer(ik), intent(in) :: method               !< sp_method_* code [-]
    type(sparse_factor), intent(inout) :: factor    !< the new factor (an old one is freed first)
    integer(ik), intent(out) :: bad                 !< column not positive definite (1-based), 0 if none [-]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)
    integer(c_int) :: bad_column
    integer(ik) :: nnz

    call sparse_factor_free(factor)
    bad = 0
    ierr = sp_err_pattern
    if (n < 1 .or. size(column_start) /= n + 1) return
    if (column_start(1) /= 0) return
    nnz = column_start(n + 1)
    if (nnz < 0 .or. size(row_index) < nnz .or. size(values) < nnz) return
    ierr = int(shim_create(int(n, c_int), column_start, row_index, values, &
                           int(ordering, c_int), int(method, c_int), factor%handle, &
                           bad_column), ik)
    if (c_associated(factor%handle)) then
      factor%n = n
      factor%nnz = nnz
    end if
    if (ierr == sp_err_definite) bad = int(bad_column, ik) + 1
  end subroutine sparse_factor_create

  !> New numeric factorization on the same pattern (values in the order of the
  !> row_index given to sparse_factor_create).
  subroutine sparse_factor_refactor(factor, values, bad, ierr)
    type(sparse_factor), intent(inout) :: factor    !< a factor from sparse_factor_create
    real(dp), intent(in) :: values(:)               !< the lower triangle's new values [matrix units]
    integer(ik), intent(out) :: bad                 !< column not positive definite (1-based), 0 if none [-]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)
    integer(c_int) :: bad_column

    bad = 0
    ierr = sp_err_argument
    if (.not. c_associated(factor%handle) .or. size(values) < factor%nnz) return
    ierr = int(shim_refactor(factor%handle, values, bad_column), ik)
    if (ierr == sp_err_definite) bad = int(bad_column, ik) + 1
  end subroutine sparse_factor_refactor

  !> Solve A x = b for one right-hand side, in place.
  subroutine sparse_factor_solve(factor, rhs, ierr)
    type(sparse_factor), intent(inout) :: factor     !< a factored sparse_factor
    real(dp), contiguous, intent(inout) :: rhs(:)    !< b in, x out (size n) [rhs units]
    integer(ik), intent(out) :: ierr                 !< error code (0 = ok)

    ierr = sp_err_argument
    if (.not. c_associated(factor%handle) .or. size(rhs) /= factor%n) return
    ierr = int(shim_solve(factor%handle, int(factor%n, c_int), 1_c_int, rhs), ik)
  end subroutine sparse_factor_solve

  !> Solve A X = B for the columns of B, in place.
  subroutine sparse_factor_solve_columns(factor, rhs, ierr)
    type(sparse_factor), intent(inout) :: factor       !< a factored sparse_factor
    real(dp), contiguous, intent(inout) :: rhs(:, :)   !< B in, X out (n x k) [rhs units]
    integer(ik), intent(out) :: ierr                   !< error code (0 = ok)

    ierr = sp_err_argument
    if (.not. c_associated(factor%handle) .or. size(rhs, 1) /= factor%n .or. size(rhs, 2) < 1) return
    ierr = int(shim_solve(factor%handle, int(factor%n, c_int), int(size(rhs, 2), c_int), rhs), ik)
  end subroutine sparse_factor_solve_columns

  !> Release the factor's memory; an empty factor is left alone.
  subroutine sparse_factor_free(factor)
    type(sparse_factor), intent(inout) :: factor   !< the factor, empty afterwards
    integer(c_int) :: status

    if (c_associated(factor%handle)) status = shim_free(factor%handle)
    factor%handle = c_null_ptr
    factor%n = 0
    factor%nnz = 0
  end subroutine sparse_factor_free

  !> What the analysis chose: fill, ordering and method (zeros and -1 for an empty factor).
  subroutine sparse_factor_stats(factor, nnz_factor, ordering, supernodal, flops)
    type(sparse_factor), intent(in) :: factor      !< a factor from sparse_factor_create
    integer(ik), intent(out) :: nnz_factor         !< nonzeros of L, diagonal included [-]
    integer(ik), intent(out) :: ordering           !< CHOLMOD's code: 0 natural, 2 AMD, 3 METIS, 4 NESDIS [-]
    logical, intent(out) :: supernodal             !< true for a supernodal factor
    real(dp), intent(out), optional :: flops       !< floating-point operations of one factorization [-]
    integer(c_int64_t) :: nnz_long
    integer(c_int) :: ordering_code, supernodal_flag, status
    real(c_double) :: flop_count

    nnz_factor = 0
    ordering = -1
    supernodal = .false.
    if (present(flops)) flops = 0.0_dp
    if (.not. c_associated(factor%handle)) return
    status = shim_stats(factor%handle, nnz_long, ordering_code, supernodal_flag, flop_count)
    if (status /= 0) return
    nnz_factor = int(min(nnz_long, int(huge(nnz_factor), c_int64_t)), ik)
    ordering = int(ordering_code, ik)
    supernodal = supernodal_flag /= 0
    if (present(flops)) flops = real(flop_count, dp)
  end subroutine sparse_factor_stats

  !> Keep a factor under a new handle; the registry owns it from now on (free it with
  !> free_sparse_factor, not sparse_factor_free).
  subroutine keep_sparse_factor(factor, handle, ierr)
    type(sparse_factor), intent(in) :: factor      !< a factor from sparse_factor_create
    integer(ik), intent(out) :: handle             !< its handle, 0 on error [-]
    integer(ik), intent(out) :: ierr               !< error code (0 = ok)

    call keep_item(registry, factor, handle, ierr)
    if (ierr == hd_err_full) ierr = sp_err_full
  end subroutine keep_sparse_factor

  !> The factor a handle names, for as long as no factor is kept or freed.
  subroutine sparse_factor_at(handle, factor, ierr)
    integer(ik), intent(in) :: handle                          !< handle from keep_sparse_factor [-]
    type(sparse_factor), pointer, intent(out) :: factor        !< the factor, null on error
    integer(ik), intent(out) :: ierr                           !< error code (0 = ok)
    class(*), pointer :: item

    nullify (factor)
    call find_item(registry, handle, item, ierr)
    ierr = sp_err_handle
    if (.not. associated(item)) return
    select type (item)
    type is (sparse_factor)
      factor => item
      ierr = sp_ok
    end select
  end subroutine sparse_factor_at

  !> Free the factor a handle names and the handle with it.
  subroutine free_sparse_factor(handle, ierr)
    integer(ik), intent(in) :: handle              !< handle from keep_sparse_factor [-]
    integer(ik), intent(out) :: ierr               !< error code (0 = ok)
    type(sparse_factor), pointer :: factor

    call sparse_factor_at(handle, factor, ierr)
    if (ierr /= sp_ok) return
    call sparse_factor_free(factor)
    call release_item(registry, handle, ierr)
    if (ierr /= hd_ok) ierr = sp_err_handle
  end subroutine free_sparse_factor
end module sparse_cholesky
