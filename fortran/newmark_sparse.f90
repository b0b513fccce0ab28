!> The sparse path of the Newmark kernel (module newmark), for flexible drivetrains whose
!> matrices are large and not banded.
!>
!> M, C and K0 share one pattern: the lower triangle (diagonal included) of the union of
!> their patterns and of the meshes' couplings, in compressed sparse columns with 0-based
!> indices (SciPy's indptr and indices), each matrix with its own values.  Khat = K0 +
!> (1 - alpha_m) s M + gamma / (beta dt) C, s = 1 / ((1 - alpha_f) beta dt^2), then has the
!> same pattern; CHOLMOD (module sparse_cholesky) analyses it once, with a fill-reducing
!> ordering, and factors it once per problem, and every solve is two sparse triangular
!> solves.  M is factored the same way for the initial acceleration and the restarts at
!> stiffness jumps.  Mesh-stiffness changes enter as the equivalent load (module newmark);
!> in equivalent-load mode refactor, a refactor to mesh stiffness kf adds
!> sum_m (kf_m - kbar_m) b_m b_m^T to Khat on the same pattern (it holds the meshes'
!> couplings) and CHOLMOD refactors numerically, keeping its analysis.  The factor is the
!> problem's, shared by its runs: it records the stiffness it holds, and a run whose own
!> k_factored differs (another run refactored in between) refactors it back first.
!>
!> A product with a symmetric matrix reads each stored off-diagonal entry twice (A(i, j)
!> x(j) into y(i) and A(i, j) x(i) into y(j)): about 2 nnz multiplications.
module newmark_sparse
  use kinds, only: dp, ik
  use sparse_cholesky, only: sparse_factor, sparse_factor_create, sparse_factor_solve, &
                             sparse_factor_refactor, sparse_factor_free, sp_ok, &
                             sp_err_unavailable, sp_err_definite
  use newmark_support, only: sparse_rows
  implicit none
  private

  public :: sparse_operators, symmetric_multiply, symmetric_multiply_pair, pattern_fits, &
            factor_operators, free_operators, solve_khat, solve_mass, refactor_khat
  public :: so_ok, so_err_pattern, so_err_definite, so_err_mass, so_err_unavailable, so_err_solve

  integer(ik), parameter :: so_ok = 0               !< success
  integer(ik), parameter :: so_err_pattern = 1      !< the pattern is not a lower triangle in CSC
  integer(ik), parameter :: so_err_definite = 2     !< Khat not positive definite (bad = column)
  integer(ik), parameter :: so_err_mass = 3         !< M not positive definite (bad = column)
  integer(ik), parameter :: so_err_unavailable = 4  !< built without CHOLMOD
  integer(ik), parameter :: so_err_solve = 5        !< a CHOLMOD solve failed

  integer(ik), parameter :: ordering_default = 0    !< CHOLMOD's own choice (AMD, METIS)
  integer(ik), parameter :: method_auto = 0         !< simplicial or supernodal by CHOLMOD

  !> M, C and K0 on one lower-triangle pattern, and the CHOLMOD factors of Khat and M.
  type :: sparse_operators
    integer(ik) :: n = 0                            !< DOFs [-]
    integer(ik), allocatable :: column_start(:)     !< (n + 1) 0-based column pointers [-]
    integer(ik), allocatable :: row_index(:)        !< (nnz) 0-based rows, row >= column [-]
    real(dp), allocatable :: mass(:)                !< (nnz) M [kg, kg m^2]
    real(dp), allocatable :: damping(:)             !< (nnz) C [N s/m, N m s/rad]
    real(dp), allocatable :: stiffness(:)           !< (nnz) K0 [N/m, N m/rad]
    real(dp), allocatable :: khat(:)                !< (nnz) Khat at mean mesh stiffness [N/m]
    type(sparse_factor) :: khat_factor              !< Khat at the stiffness factor_stiffness holds
    type(sparse_factor) :: mass_factor              !< M
    !> mesh stiffness in khat_factor [N/m]; a pointer, so that a run may refactor the
    !> problem's factor while the problem itself stays read-only (intent(in))
    real(dp), pointer :: factor_stiffness(:) => null()
  end type sparse_operators

contains

  !> y = y + scale A x for a symmetric A stored as its lower triangle on ops' pattern.
  pure subroutine symmetric_multiply(ops, values, x, scale, y)
    type(sparse_operators), intent(in) :: ops  !< the pattern
    real(dp), intent(in) :: values(:)          !< A's entries on the pattern [units of A]
    real(dp), intent(in) :: x(ops%n)           !< vector [units of x]
    real(dp), intent(in) :: scale              !< factor on A x [-]
    real(dp), intent(inout) :: y(ops%n)        !< accumulator [units of A x]
    integer(ik) :: i, j, p
    real(dp) :: xj, column

    do j = 1, ops%n
      xj = scale * x(j)
      column = 0.0_dp
      do p = ops%column_start(j) + 1, ops%column_start(j + 1)
        i = ops%row_index(p) + 1
        if (i == j) then
          column = column + values(p) * x(j)
        else
          y(i) = y(i) + values(p) * xj
          column = column + values(p) * x(i)
        end if
      end do
      y(j) = y(j) + scale * column
    end do
  end subroutine symmetric_multiply

  !> y = y + scale (A x + B z) for symmetric A and B stored as lower triangles on ops'
  !> pattern: one pass over the pattern for the two products (C v + K0 q of every step).
  pure subroutine symmetric_multiply_pair(ops, a_values, x, b_values, z, scale, y)
    type(sparse_operators), intent(in) :: ops  !< the pattern
    real(dp), intent(in) :: a_values(:)        !< A's entries on the pattern [units of A]
    real(dp), intent(in) :: x(ops%n)           !< vector A multiplies [units of x]
    real(dp), intent(in) :: b_values(:)        !< B's entries on the pattern [units of B]
    real(dp), intent(in) :: z(ops%n)           !< vector B multiplies [units of z]
    real(dp), intent(in) :: scale              !< factor on A x + B z [-]
    real(dp), intent(inout) :: y(ops%n)        !< accumulator [units of A x]
    integer(ik) :: i, j, p
    real(dp) :: xj, zj, column

    do j = 1, ops%n
      xj = scale * x(j)
      zj = scale * z(j)
      column = 0.0_dp
      do p = ops%column_start(j) + 1, ops%column_start(j + 1)
        i = ops%row_index(p) + 1
        if (i == j) then
          column = column + a_values(p) * x(j) + b_values(p) * z(j)
        else
          y(i) = y(i) + a_values(p) * xj + b_values(p) * zj
          column = column + a_values(p) * x(i) + b_values(p) * z(i)
        end if
      end do
      y(j) = y(j) + scale * column
    end do
  end subroutine symmetric_multiply_pair

  !> The pattern is n + 1 non-decreasing pointers from 0 and, per column, increasing
  !> rows from the column down, and the three value arrays match it.
  pure logical function pattern_fits(ops)
    type(sparse_operators), intent(in) :: ops  !< the operators to inspect
    integer(ik) :: j, p, nnz

    pattern_fits = .false.
    if (ops%n < 1) return
    if (.not. (allocated(ops%column_start) .and. allocated(ops%row_index) .and. &
               allocated(ops%mass) .and. allocated(ops%damping) .and. allocated(ops%stiffness))) return
    if (size(ops%column_start) /= ops%n + 1) return
    if (ops%column_start(1) /= 0) return
    nnz = ops%column_start(ops%n + 1)
    if (nnz < ops%n .or. size(ops%row_index) < nnz) return
    if (size(ops%mass) < nnz .or. size(ops%damping) < nnz .or. size(ops%stiffness) < nnz) return
    do j = 1, ops%n
      if (ops%column_start(j + 1) < ops%column_start(j)) return
      do p = ops%column_start(j) + 1, ops%column_start(j + 1)
        if (ops%row_index(p) < j - 1 .or. ops%row_index(p) > ops%n - 1) return
        if (p > ops%column_start(j) + 1) then
          if (ops%row_index(p) <= ops%row_index(p - 1)) return
        end if
      end do
    end do
    pattern_fits = .true.
  end function pattern_fits

  !> Form Khat from M, C, K0 and the step's coefficients and factor it and M.
  subroutine factor_operators(ops, mass_coefficient, damping_coefficient, mean_stiffness, &
                              bad, ierr)
    type(sparse_operators), intent(inout) :: ops   !< the operators (factors set on success)
    real(dp), intent(in) :: mass_coefficient       !< (1 - alpha_m) s [1/s^2]
    real(dp), intent(in) :: damping_coefficient    !< gamma / (beta dt) [1/s]
    real(dp), intent(in) :: mean_stiffness(:)      !< kbar_m, the meshes' stiffness in Khat [N/m]
    integer(ik), intent(out) :: bad                !< failing column (1-based), 0 none [-]
    integer(ik), intent(out) :: ierr               !< error code (0 = ok)
    real(dp), allocatable :: khat(:)
    integer(ik) :: nnz, info

    bad = 0
    nnz = ops%column_start(ops%n + 1)
    khat = ops%stiffness(1:nnz) + mass_coefficient * ops%mass(1:nnz) &
           + damping_coefficient * ops%damping(1:nnz)
    ops%khat = khat
    call sparse_factor_create(ops%n, ops%column_start, ops%row_index(1:nnz), khat, &
                              ordering_default, method_auto, ops%khat_factor, bad, info)
    if (info /= sp_ok) then
      ierr = translate(info, so_err_definite)
      return
    end if
    call sparse_factor_create(ops%n, ops%column_start, ops%row_index(1:nnz), ops%mass(1:nnz), &
                              ordering_default, method_auto, ops%mass_factor, bad, info)
    if (info /= sp_ok) then
      call sparse_factor_free(ops%khat_factor)
      ierr = translate(info, so_err_mass)
      return
    end if
    allocate (ops%factor_stiffness(size(mean_stiffness)))
    ops%factor_stiffness = mean_stiffness
    ierr = so_ok
  end subroutine factor_operators

  !> Release both factors (the pattern and values stay).
  subroutine free_operators(ops)
    type(sparse_operators), intent(inout) :: ops  !< the operators

    call sparse_factor_free(ops%khat_factor)
    call sparse_factor_free(ops%mass_factor)
    if (associated(ops%factor_stiffness)) deallocate (ops%factor_stiffness)
  end subroutine free_operators

  !> Refactor Khat numerically with mesh stiffness k_new: Khat at mean stiffness plus
  !> sum_m (k_new_m - kbar_m) b_m b_m^T on the pattern, CHOLMOD's analysis kept.
  subroutine refactor_khat(ops, mesh, mean_stiffness, k_new, bad, ierr)
    type(sparse_operators), intent(in) :: ops      !< factored operators (their factor changes)
    type(sparse_rows), intent(in) :: mesh          !< b_m, 1-based DOFs [m/m, m/rad]
    real(dp), intent(in) :: mean_stiffness(:)      !< kbar_m [N/m]
    real(dp), intent(in) :: k_new(:)               !< mesh stiffness for the factor [N/m]
    integer(ik), intent(out) :: bad                !< failing column (1-based), 0 none [-]
    integer(ik), intent(out) :: ierr               !< error code (0 = ok)
    type(sparse_factor) :: factor
    real(dp), allocatable :: values(:)
    integer(ik) :: m, p, r, i, j, position, info

    bad = 0
    values = ops%khat
    do m = 1, size(k_new)
      if (k_new(m) == mean_stiffness(m)) cycle
      do p = mesh%ptr(m) + 1, mesh%ptr(m + 1)
        do r = mesh%ptr(m) + 1, mesh%ptr(m + 1)
          i = mesh%index(r)
          j = mesh%index(p)
          if (i < j) cycle
          position = pattern_position(ops, i, j)
          if (position == 0) then  ! a mesh coupling outside the pattern
            ierr = so_err_pattern
            return
          end if
          values(position) = values(position) + (k_new(m) - mean_stiffness(m)) &
                             * mesh%value(r) * mesh%value(p)
        end do
      end do
    end do
    factor = ops%khat_factor  ! a copy of the handle: the refactor is behind it
    call sparse_factor_refactor(factor, values, bad, info)
    if (info /= sp_ok) then
      ierr = translate(info, so_err_definite)
      return
    end if
    ops%factor_stiffness = k_new
    ierr = so_ok
  end subroutine refactor_khat

  !> Position (1-based) of the entry (row i, column j), i >= j, in the pattern; 0 if absent.
  pure integer(ik) function pattern_position(ops, i, j)
    type(sparse_operators), intent(in) :: ops  !< the pattern
    integer(ik), intent(in) :: i               !< row, 1-based [-]
    integer(ik), intent(in) :: j               !< column, 1-based [-]
    integer(ik) :: low, high, middle

    pattern_position = 0
    low = ops%column_start(j) + 1
    high = ops%column_start(j + 1)
    do while (low <= high)  ! rows increase within a column
      middle = (low + high) / 2
      if (ops%row_index(middle) + 1 == i) then
        pattern_position = middle
        return
      else if (ops%row_index(middle) + 1 < i) then
        low = middle + 1
      else
        high = middle - 1
      end if
    end do
  end function pattern_position

  !> rhs = Khat^-1 rhs with the factor at mean mesh stiffness.
  subroutine solve_khat(ops, rhs, ierr)
    type(sparse_operators), intent(in) :: ops  !< factored operators
    real(dp), intent(inout) :: rhs(ops%n)      !< right-hand side in, solution out [SI]
    integer(ik), intent(out) :: ierr           !< error code (0 = ok)

    call solve_with(ops%khat_factor, rhs, ierr)
  end subroutine solve_khat

  !> rhs = M^-1 rhs.
  subroutine solve_mass(ops, rhs, ierr)
    type(sparse_operators), intent(in) :: ops  !< factored operators
    real(dp), intent(inout) :: rhs(ops%n)      !< right-hand side in, solution out [SI]
    integer(ik), intent(out) :: ierr           !< error code (0 = ok)

    call solve_with(ops%mass_factor, rhs, ierr)
  end subroutine solve_mass

  !> rhs = A^-1 rhs with a copy of a factor's handle, so that the operators holding the
  !> factor stay read-only (the solve's workspace lives behind the handle).
  subroutine solve_with(held, rhs, ierr)
    type(sparse_factor), intent(in) :: held  !< the operators' factor
    real(dp), intent(inout) :: rhs(:)        !< right-hand side in, solution out [SI]
    integer(ik), intent(out) :: ierr         !< error code (0 = ok)
    type(sparse_factor) :: factor
    integer(ik) :: info

    factor = held
    call sparse_factor_solve(factor, rhs, info)
    ierr = merge(so_ok, so_err_solve, info == sp_ok)
  end subroutine solve_with

  !> This module's code for a CHOLMOD status (definite: the code for a matrix that is
  !> not positive definite).
  pure integer(ik) function translate(info, definite)
    integer(ik), intent(in) :: info      !< sparse_cholesky status [-]
    integer(ik), intent(in) :: definite  !< code for "not positive definite" [-]

    if (info == sp_err_definite) then
      translate = definite
    else if (info == sp_err_unavailable) then
      translate = so_err_unavailable
    else
      translate = so_err_pattern
    end if
  end function translate
end module newmark_sparse
