!> Loaded tooth contact analysis (LTCA) of one gear mesh by the slice method
!> (Conry & Seireg 1973: the contact of elastic bodies as a problem in non-negative
!> loads; the documentation's contact page has the equations).
!>
!> The contact lines of the tooth pairs in mesh are cut into slices along the face.
!> Slice i of pair k at mesh position j has the structural compliance c_ik (tooth bending,
!> shear, axial compression and fillet foundation of both teeth, per slice width, from
!> the potential-energy law) and the Hertz compliance h_ik.  The slices of one tooth pair
!> are coupled as a Pasternak foundation (Ajmi & Velex 2005): springs 1/c_i to ground and
!> shear springs k_c between neighbours, k_c = kappa * 2 / (c_i + c_(i+1)), kappa =
!> (lambda / w)^2 the squared decay length over the slice width.  The tooth-pair
!> compliance matrix is C_k = K_k^-1 + diag(h_k), K_k the tridiagonal stiffness; the
!> shear springs carry nothing under a uniform deflection, so an unmodified spur pair
!> keeps the stiffness of the uncoupled slices exactly.
!>
!> At each position and load F the rigid-body approach delta (the loaded transmission
!> error along the transverse line of action) and the slice loads p solve
!>   g_i + (C p)_i = delta  where p_i > 0,   g_i + (C p)_i >= delta  where p_i = 0,
!>   sum p = F,  p >= 0,
!> g the initial separation (modifications, deviations, misalignment).  An active-set
!> iteration: solve the equalities on the active slices (pair by pair, Cholesky of the
!> active block, then delta from the load balance), drop slices with negative load,
!> add slices that penetrate, until neither happens.
module ltca
  use kinds, only: dp, ik
  implicit none
  private

  public :: ltca_ok, ltca_err_argument, ltca_err_size, ltca_err_no_contact
  public :: ltca_err_singular, ltca_err_converge
  public :: ltca_solve

  integer(ik), parameter :: ltca_ok = 0              !< success
  integer(ik), parameter :: ltca_err_argument = 1    !< an input value is out of range (bad_param)
  integer(ik), parameter :: ltca_err_size = 2        !< an array size is out of range
  integer(ik), parameter :: ltca_err_no_contact = 3  !< no slice in the path at a position (bad_param)
  integer(ik), parameter :: ltca_err_singular = 4    !< a compliance block is not positive definite
  integer(ik), parameter :: ltca_err_converge = 5    !< the active set did not settle (bad_param)

contains

  !> Solve the slice contact problem at every position and load.
  subroutine ltca_solve(n_slice, n_pair, n_pos, n_load, c_struct, c_hertz, in_path, gap, &
                        coupling, force, te_unloaded, te_loaded, load, iterations, &
                        bad_param, ierr)
    integer(ik), intent(in) :: n_slice                              !< slices along the face [-]
    integer(ik), intent(in) :: n_pair                               !< tooth pairs considered [-]
    integer(ik), intent(in) :: n_pos                                !< mesh positions [-]
    integer(ik), intent(in) :: n_load                               !< loads [-]
    real(dp), intent(in) :: c_struct(n_slice, n_pair, n_pos)        !< structural slice compliance [m/N]
    real(dp), intent(in) :: c_hertz(n_slice, n_pair, n_pos)         !< Hertz slice compliance [m/N]
    integer(ik), intent(in) :: in_path(n_slice, n_pair, n_pos)      !< 1: slice on the path of contact [-]
    real(dp), intent(in) :: gap(n_slice, n_pair, n_pos)             !< initial separation [m]
    real(dp), intent(in) :: coupling                                !< kappa = (lambda / w)^2, >= 0 [-]
    real(dp), intent(in) :: force(n_load)                           !< transmitted force, >= 0 [N]
    real(dp), intent(out) :: te_unloaded(n_pos)                     !< approach at first contact [m]
    real(dp), intent(out) :: te_loaded(n_pos, n_load)               !< loaded approach delta [m]
    real(dp), intent(out) :: load(n_slice, n_pair, n_pos, n_load)   !< slice loads [N]
    integer(ik), intent(out) :: iterations(n_pos, n_load)           !< active-set iterations [-]
    integer(ik), intent(out) :: bad_param                           !< offending entry, 0 if none [-]
    integer(ik), intent(out) :: ierr                                !< error code (0 = ok)

    real(dp), allocatable :: compliance(:, :, :), block(:, :), rhs(:, :), p(:)
    logical, allocatable :: active(:, :), candidate(:, :)
    integer(ik) :: j, l, n_iter
    integer :: k

    te_unloaded = 0
    te_loaded = 0
    load = 0
    iterations = 0
    bad_param = 0
    ierr = ltca_ok
    if (n_slice < 1 .or. n_pair < 1 .or. n_pos < 1 .or. n_load < 1) then
      ierr = ltca_err_size
      return
    end if
    if (.not. (coupling >= 0 .and. coupling < huge(1.0_dp))) then
      ierr = ltca_err_argument
      bad_param = 1
      return
    end if
    do l = 1, n_load
      if (.not. (force(l) >= 0 .and. force(l) < huge(1.0_dp))) then
        ierr = ltca_err_argument
        bad_param = 100 + l
        return
      end if
    end do
    if (.not. all(c_struct > 0 .and. c_struct < huge(1.0_dp))) then
      ierr = ltca_err_argument
      bad_param = 2
      return
    end if
    if (.not. all(c_hertz >= 0 .and. c_hertz < huge(1.0_dp))) then
      ierr = ltca_err_argument
      bad_param = 3
      return
    end if
    if (.not. all(abs(gap) < huge(1.0_dp))) then
      ierr = ltca_err_argument
      bad_param = 4
      return
    end if

    allocate(compliance(n_slice, n_slice, n_pair), block(n_slice, n_slice), &
             rhs(n_slice, 2), p(n_slice * n_pair))
    allocate(active(n_slice, n_pair), candidate(n_slice, n_pair))
    do j = 1, n_pos
      candidate = in_path(:, :, j) == 1
      if (.not. any(candidate)) then
        ierr = ltca_err_no_contact
        bad_param = j
        return
      end if
      do k = 1, n_pair
        call pair_compliance(n_slice, c_struct(:, k, j), c_hertz(:, k, j), coupling, &
                             compliance(:, :, k))
      end do
      te_unloaded(j) = minval(gap(:, :, j), mask=candidate)
      active = candidate
      do l = 1, n_load
        if (force(l) == 0) then
          te_loaded(j, l) = te_unloaded(j)
          cycle
        end if
        call solve_position(n_slice, n_pair, compliance, gap(:, :, j), candidate, active, &
                            force(l), te_loaded(j, l), load(:, :, j, l), block, rhs, &
                            n_iter, ierr)
        iterations(j, l) = n_iter
        if (ierr /= ltca_ok) then
          bad_param = j
          return
        end if
      end do
    end do
  end subroutine ltca_solve

  !> C = K^-1 + diag(h) of one tooth pair: K tridiagonal (slices on a Pasternak
  !> foundation), inverted column by column with the Thomas algorithm.
  subroutine pair_compliance(n, c, h, kappa, compliance)
    integer(ik), intent(in) :: n              !< slices [-]
    real(dp), intent(in) :: c(n)              !< structural slice compliance [m/N]
    real(dp), intent(in) :: h(n)              !< Hertz slice compliance [m/N]
    real(dp), intent(in) :: kappa             !< coupling (lambda / w)^2 [-]
    real(dp), intent(out) :: compliance(n, n) !< pair compliance matrix [m/N]
    real(dp) :: diag(n), off(n), factor(n), sub(n)
    integer :: i, col

    compliance = 0
    if (kappa == 0 .or. n == 1) then
      do i = 1, n
        compliance(i, i) = c(i) + h(i)
      end do
      return
    end if
    off = 0
    do i = 1, n - 1
      off(i) = -kappa * 2 / (c(i) + c(i + 1))
    end do
    do i = 1, n
      diag(i) = 1 / c(i)
      if (i > 1) diag(i) = diag(i) - off(i - 1)
      if (i < n) diag(i) = diag(i) - off(i)
    end do
    ! LDL^T-like forward elimination of the symmetric tridiagonal matrix
    factor(1) = diag(1)
    do i = 2, n
      sub(i) = off(i - 1) / factor(i - 1)
      factor(i) = diag(i) - sub(i) * off(i - 1)
    end do
    do col = 1, n
      compliance(col, col) = 1
      do i = col + 1, n
        compliance(i, col) = -sub(i) * compliance(i - 1, col)
      end do
      compliance(n, col) = compliance(n, col) / factor(n)
      do i = n - 1, 1, -1
        compliance(i, col) = (compliance(i, col) - off(i) * compliance(i + 1, col)) / factor(i)
      end do
    end do
    do i = 1, n
      compliance(i, i) = compliance(i, i) + h(i)
    end do
  end subroutine pair_compliance

  !> The active-set iteration at one position and load.
  subroutine solve_position(n, n_pair, compliance, gap, candidate, active, force, delta, p, &
                            block, rhs, n_iter, ierr)
    integer(ik), intent(in) :: n                            !< slices [-]
    integer(ik), intent(in) :: n_pair                       !< pairs [-]
    real(dp), intent(in) :: compliance(n, n, n_pair)        !< pair compliance matrices [m/N]
    real(dp), intent(in) :: gap(n, n_pair)                  !< initial separation [m]
    logical, intent(in) :: candidate(n, n_pair)             !< slices on the path [-]
    logical, intent(inout) :: active(n, n_pair)             !< slices in contact (start, result) [-]
    real(dp), intent(in) :: force                           !< transmitted force [N]
    real(dp), intent(out) :: delta                          !< approach [m]
    real(dp), intent(out) :: p(n, n_pair)                   !< slice loads [N]
    real(dp), intent(inout) :: block(n, n)                  !< work: active block [m/N]
    real(dp), intent(inout) :: rhs(n, 2)                    !< work [-, m]
    integer(ik), intent(out) :: n_iter                      !< iterations taken [-]
    integer(ik), intent(out) :: ierr                        !< error code
    real(dp) :: a(n, n_pair), b(n, n_pair), sum_a, sum_b, tol_p, tol_g, w, g0, scale
    integer :: idx(n), m, k, i, q, max_iter
    logical :: changed

    ierr = ltca_ok
    max_iter = 4 * n * n_pair + 20
    tol_p = 1e-12_dp * force / (n * n_pair)
    g0 = minval(gap, mask=candidate)
    scale = maxval(compliance) * force
    ! a start without slices whose separation exceeds the deflection scale
    where (candidate .and. gap - g0 > 2 * scale) active = .false.
    if (.not. any(active)) active = candidate .and. gap == g0
    do n_iter = 1, max_iter
      sum_a = 0
      sum_b = 0
      a = 0
      b = 0
      do k = 1, n_pair
        m = 0
        do i = 1, n
          if (active(i, k)) then
            m = m + 1
            idx(m) = i
          end if
        end do
        if (m == 0) cycle
        do q = 1, m
          block(1:m, q) = compliance(idx(1:m), idx(q), k)
          rhs(q, 1) = 1
          rhs(q, 2) = gap(idx(q), k)
        end do
        call cholesky_solve(m, block(1:m, 1:m), rhs(1:m, :), ierr)
        if (ierr /= ltca_ok) return
        a(idx(1:m), k) = rhs(1:m, 1)
        b(idx(1:m), k) = rhs(1:m, 2)
        sum_a = sum_a + sum(rhs(1:m, 1))
        sum_b = sum_b + sum(rhs(1:m, 2))
      end do
      delta = (force + sum_b) / sum_a
      p = merge(delta * a - b, 0.0_dp, active)
      ! drop every slice pulling
      changed = .false.
      do k = 1, n_pair
        do i = 1, n
          if (active(i, k) .and. p(i, k) < -tol_p) then
            active(i, k) = .false.
            changed = .true.
          end if
        end do
      end do
      if (changed) cycle
      ! add every slice that penetrates
      tol_g = 1e-10_dp * max(delta - g0, tiny(1.0_dp))
      do k = 1, n_pair
        do i = 1, n
          if (candidate(i, k) .and. .not. active(i, k)) then
            w = gap(i, k) + dot_product(compliance(i, :, k), p(:, k)) - delta
            if (w < -tol_g) then
              active(i, k) = .true.
              changed = .true.
            end if
          end if
        end do
      end do
      if (.not. changed) then
        p = max(p, 0.0_dp)
        return
      end if
    end do
    ierr = ltca_err_converge
  end subroutine solve_position

  !> Solve A x = rhs for symmetric positive definite A (Cholesky, A overwritten).
  subroutine cholesky_solve(m, a, rhs, ierr)
    integer, intent(in) :: m                  !< order [-]
    real(dp), intent(inout) :: a(m, m)        !< matrix, then its factor [m/N]
    real(dp), intent(inout) :: rhs(m, 2)      !< right-hand sides, then solutions [-, m]
    integer(ik), intent(out) :: ierr          !< error code
    integer :: i, j
    real(dp) :: s

    ierr = ltca_ok
    do j = 1, m
      s = a(j, j) - dot_product(a(j, 1:j - 1), a(j, 1:j - 1))
      if (.not. s > 0) then
        ierr = ltca_err_singular
        return
      end if
      a(j, j) = sqrt(s)
      do i = j + 1, m
        a(i, j) = (a(i, j) - dot_product(a(i, 1:j - 1), a(j, 1:j - 1))) / a(j, j)
      end do
    end do
    do j = 1, 2
      do i = 1, m
        rhs(i, j) = (rhs(i, j) - dot_product(a(i, 1:i - 1), rhs(1:i - 1, j))) / a(i, i)
      end do
      do i = m, 1, -1
        rhs(i, j) = (rhs(i, j) - dot_product(a(i + 1:m, i), rhs(i + 1:m, j))) / a(i, i)
      end do
    end do
  end subroutine cholesky_solve

end module ltca
