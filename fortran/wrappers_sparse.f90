!> The flat layer f2py sees for the sparse Cholesky factorization (module
!> sparse_cholesky): explicit-shape arrays, sizes passed in, error code last.  A
!> factor is created (analysed and factored) once and kept under an integer handle;
!> the other routines take the handle.  Error codes are module sparse_cholesky's
!> sp_* parameters.

!> Analyse and factor a symmetric positive definite matrix given by its lower triangle
!> (0-based compressed sparse columns, sorted) and keep the factor under a handle.  A
!> matrix that is not positive definite returns sp_err_definite, the failing column in
!> bad and no handle.
subroutine sparse_cholesky_create(n, nnz, column_start, row_index, values, ordering, method, &
                                  handle, bad, ierr)
  use kinds, only: dp, ik
  use sparse_cholesky, only: sparse_factor, sparse_factor_create, sparse_factor_free, &
                             keep_sparse_factor, sp_ok
  implicit none
  integer(ik), intent(in) :: n                       !< order of the matrix [-]
  integer(ik), intent(in) :: nnz                     !< entries of the lower triangle [-]
  integer(ik), intent(in) :: column_start(n + 1)     !< column starts, 0-based (indptr) [-]
  integer(ik), intent(in) :: row_index(nnz)          !< rows, 0-based (indices) [-]
  real(dp), intent(in) :: values(nnz)                !< the lower triangle's values [matrix units]
  integer(ik), intent(in) :: ordering                !< 0 auto, 1 natural, 2 AMD [-]
  integer(ik), intent(in) :: method                  !< 0 auto, 1 simplicial, 2 supernodal [-]
  integer(ik), intent(out) :: handle                 !< the factor's handle, 0 on error [-]
  integer(ik), intent(out) :: bad                    !< column not positive definite (1-based), 0 if none [-]
  integer(ik), intent(out) :: ierr                   !< error code (0 = ok)
  type(sparse_factor) :: factor

  handle = 0
  call sparse_factor_create(n, column_start, row_index, values, ordering, method, factor, &
                            bad, ierr)
  if (ierr /= sp_ok) then
    call sparse_factor_free(factor)
    return
  end if
  call keep_sparse_factor(factor, handle, ierr)
  if (ierr /= sp_ok) call sparse_factor_free(factor)
end subroutine sparse_cholesky_create

!> New values on the factor's pattern: numeric factorization only.
subroutine sparse_cholesky_refactor(handle, nnz, values, bad, ierr)
  use kinds, only: dp, ik
  use sparse_cholesky, only: sparse_factor, sparse_factor_at, sparse_factor_refactor, sp_ok, &
                             sp_err_pattern
  implicit none
  integer(ik), intent(in) :: handle                  !< handle from sparse_cholesky_create [-]
  integer(ik), intent(in) :: nnz                     !< entries of the lower triangle [-]
  real(dp), intent(in) :: values(nnz)                !< new values, same pattern [matrix units]
  integer(ik), intent(out) :: bad                    !< column not positive definite (1-based), 0 if none [-]
  integer(ik), intent(out) :: ierr                   !< error code (0 = ok)
  type(sparse_factor), pointer :: factor

  bad = 0
  call sparse_factor_at(handle, factor, ierr)
  if (ierr /= sp_ok) return
  ierr = sp_err_pattern
  if (nnz /= factor%nnz) return
  call sparse_factor_refactor(factor, values, bad, ierr)
end subroutine sparse_cholesky_refactor

!> Solve A X = B for k right-hand sides, in place.
subroutine sparse_cholesky_solve(handle, n, k, rhs, ierr)
  use kinds, only: dp, ik
  use sparse_cholesky, only: sparse_factor, sparse_factor_at, sparse_factor_solve_columns, sp_ok
  implicit none
  integer(ik), intent(in) :: handle                  !< handle from sparse_cholesky_create [-]
  integer(ik), intent(in) :: n                       !< order of the matrix [-]
  integer(ik), intent(in) :: k                       !< right-hand sides [-]
  real(dp), intent(inout) :: rhs(n, k)               !< B in, X out [rhs units]
  integer(ik), intent(out) :: ierr                   !< error code (0 = ok)
  type(sparse_factor), pointer :: factor

  call sparse_factor_at(handle, factor, ierr)
  if (ierr /= sp_ok) return
  call sparse_factor_solve_columns(factor, rhs, ierr)
end subroutine sparse_cholesky_solve

!> Timing loop for benchmarks: solves A x = b n_repeat times inside one call (b kept,
!> x overwritten) and returns the wall time of the loop alone (system_clock).
subroutine sparse_cholesky_solve_benchmark(handle, n, rhs, n_repeat, solution, elapsed, ierr)
  use kinds, only: dp, ik
  use sparse_cholesky, only: sparse_factor, sparse_factor_at, sparse_factor_solve, sp_ok
  implicit none
  integer(ik), intent(in) :: handle                  !< handle from sparse_cholesky_create [-]
  integer(ik), intent(in) :: n                       !< order of the matrix [-]
  real(dp), intent(in) :: rhs(n)                     !< b [rhs units]
  integer(ik), intent(in) :: n_repeat                !< solves [-]
  real(dp), intent(out) :: solution(n)               !< x of the last solve [solution units]
  real(dp), intent(out) :: elapsed                   !< wall time of all solves [s]
  integer(ik), intent(out) :: ierr                   !< error code (0 = ok)
  integer, parameter :: i8 = selected_int_kind(18)
  type(sparse_factor), pointer :: factor
  integer(i8) :: start, finish, rate
  integer(ik) :: r

  elapsed = 0.0_dp
  solution = 0.0_dp
  call sparse_factor_at(handle, factor, ierr)
  if (ierr /= sp_ok) return
  call system_clock(start, rate)
  do r = 1, n_repeat
    solution = rhs
    call sparse_factor_solve(factor, solution, ierr)
    if (ierr /= sp_ok) return
  end do
  call system_clock(finish)
  elapsed = real(finish - start, dp) / real(rate, dp)
end subroutine sparse_cholesky_solve_benchmark

!> What the analysis chose for a factor.
subroutine sparse_cholesky_stats(handle, nnz_factor, ordering, supernodal, flops, ierr)
  use kinds, only: dp, ik
  use sparse_cholesky, only: sparse_factor, sparse_factor_at, sparse_factor_stats, sp_ok
  implicit none
  integer(ik), intent(in) :: handle                  !< handle from sparse_cholesky_create [-]
  integer(ik), intent(out) :: nnz_factor             !< nonzeros of L [-]
  integer(ik), intent(out) :: ordering               !< CHOLMOD's code: 0 natural, 2 AMD, 3 METIS, 4 NESDIS [-]
  integer(ik), intent(out) :: supernodal             !< 1 supernodal, 0 simplicial [-]
  real(dp), intent(out) :: flops                     !< floating-point operations of one factorization [-]
  integer(ik), intent(out) :: ierr                   !< error code (0 = ok)
  type(sparse_factor), pointer :: factor
  logical :: is_supernodal

  nnz_factor = 0
  ordering = -1
  supernodal = 0
  flops = 0.0_dp
  call sparse_factor_at(handle, factor, ierr)
  if (ierr /= sp_ok) return
  call sparse_factor_stats(factor, nnz_factor, ordering, is_supernodal, flops)
  if (is_supernodal) supernodal = 1
end subroutine sparse_cholesky_stats

!> Free a factor and its handle.
subroutine sparse_cholesky_free(handle, ierr)
  use kinds, only: ik
  use sparse_cholesky, only: free_sparse_factor
  implicit none
  integer(ik), intent(in) :: handle                  !< handle from sparse_cholesky_create [-]
  integer(ik), intent(out) :: ierr                   !< error code (0 = ok)
  call free_sparse_factor(handle, ierr)
end subroutine sparse_cholesky_free

!> 1 when the kernel was built with CHOLMOD, else 0.
subroutine sparse_cholesky_available_flag(available)
  use kinds, only: ik
  use sparse_cholesky, only: sparse_cholesky_available
  implicit none
  integer(ik), intent(out) :: available              !< 1 available, 0 not [-]
  available = 0
  if (sparse_cholesky_available()) available = 1
end subroutine sparse_cholesky_available_flag
