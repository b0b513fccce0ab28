!> The dense path of the Newmark kernel (module newmark), for models small enough or with
!> a band so nearly full that band storage saves nothing.
!>
!> A step solves Khat a = s (r0 + (1 - alpha_f)(F - N)) (module newmark).  The dense path
!> never forms r0: it keeps the operator
!>     X = s Khat^-1 [-C, -K0, w_in, w_out, b_1 .. b_M, -M]       (n rows, 3n + M + 2 columns)
!> with s = 1 / ((1 - alpha_f) beta dt^2), w_in and w_out the members the drive and load
!> act on and b_m the meshes' deflection vectors, so that a step is two matrix-vector
!> products (BLAS dgemv):
!>     a_0 = X_C w_c + X_K w_k (+ X_M alpha_m a_n),                once per step,
!>     a   = a_0 + X_L [T_drive; -T_load; -g_1 .. -g_M],           once per iteration,
!> with w_c, w_k the velocity and displacement r0 weights (module newmark) and the load
!> coefficients holding the alpha_f shares of the previous step's loads; with one solve
!> per step (modes linear and predictor) the two are one product with [X_C X_K X_L].  In
!> exact arithmetic the banded and the dense path give the same a; they round
!> differently (a product with a computed inverse against two triangular solves).
!>
!> X0, the operator at mean mesh stiffness, is formed once per problem from the banded
!> Cholesky factor of Khat (dpbtrs with the columns of s [-C, -K0, w_in, w_out, B^T, -M]
!> as right-hand sides).  A refactor to mesh stiffness kf changes Khat by B^T D B, D =
!> diag(kf - kbar), and the Sherman-Morrison-Woodbury identity gives the new operator
!> without a factorization of Khat:
!>     X = X0 - Y (I + D B Y)^-1 D Z,   Y = Khat0^-1 B^T = X0_L(meshes) / s,   Z = B X0,
!> an M x M solve and an n x M x (3n + M + 2) product (Golub & Van Loan, Matrix
!> Computations, 4th ed., 2013, sec. 2.1.4).  I + D B Y is nonsingular whenever the new
!> Khat is (the determinant lemma), and every refactor starts again from X0, so no
!> rounding accumulates over refactors.
!>
!> Column blocks of X: 1..n C, n+1..2n K0, then the load block (drive, load, meshes),
!> then M.  X is kept transposed, X^T with 3n + M + 2 rows and n columns, so that each
!> product is a transposed dgemv over consecutive rows of X^T (faster than X x at these
!> sizes: one dot product per column).
!>
!> The refined dense path (iparam(ip_solver) = solver_refined) follows each product with
!> one step of iterative refinement against Khat itself:
!>     r = r0 + l - Khat a / s,   a = a + s Khat^-1 r,
!> with r0 = -C w_c - K0 w_k (- alpha_m M a_n) and l the loads [T_drive; -T_load; -g]
!> on their members and meshes (their alpha_f shares included), so that s (r0 + l) is
!> the right-hand side of Khat a = s (r0 + (1 - alpha_f)(F - N)) (module newmark).
!> A product with a computed inverse is not backward stable: its residual is of order
!> kappa(Khat) u |X| |f| (u the unit round-off), and X_K r, X_C r for a rigid rotation r
!> are not 0 but fixed errors that the growing angles and the speed multiply, so over a
!> long run the rigid mode's torque balance drifts (3.6e-8 of the speed after 1e6 steps
!> of the study case at 2000 rpm, against 4e-11 on the band factor).  After one step of
!> refinement the step's residual is that of forming r0 + l and Khat a / s in floating
!> point, of order u (|C| |w_c| + |K0| |w_k| + |l| + |Khat| |a| / s): the step is
!> backward stable, as a factorization's, as long as kappa(Khat) u << 1 (Higham,
!> Accuracy and Stability of Numerical Algorithms, 2nd ed., 2002, sec. 12.2 on
!> fixed-precision refinement, sec. 14.1 on solving with an inverse).
!> The residual is formed in the banded path's order: r0 from the unscaled -C and -K0
!> (s K0 in floating point would no longer hold the rigid rotation in its null space to
!> the round-off K0 itself does), the loads added to the rows they act on, then
!> -Khat a / s.  Summed in the same product as r0, the last term rounded the rigid
!> rotation's balance to 1.4e-9 of the speed in that run, against 4e-11 in this order:
!> both are within the worst-case bound (6e-8 there, u r^T |K0| |q| at 16 rad over the
!> damping's restoring torque), but only this order keeps the 1e-9 the long runs hold.
!> The operator is kept transposed, R^T = [-C, -K0, -Khat / s, -M]^T (4n rows, n
!> columns), with s Khat^-1 transposed beside it; a refactor to mesh stiffness kf forms
!> the Khat block and s Khat^-1 again at kf (refined_stiffness: band Cholesky of Khat at
!> kf, solved for s I), while X follows by the Woodbury identity.
module newmark_dense
  use kinds, only: dp, ik
  use newmark_support, only: sparse_rows
  use band_lapack, only: band_cholesky_factor, band_cholesky_solve_columns, &
                         dense_multiply_transposed
  implicit none
  private

  public :: dense_columns, load_block, mass_block, mean_operator, stiffness_update
  public :: refined_operators, refined_stiffness, refine_solution

contains

  !> Columns of the dense operator X [-].
  pure integer(ik) function dense_columns(n, n_mesh)
    integer(ik), intent(in) :: n       !< DOFs [-]
    integer(ik), intent(in) :: n_mesh  !< meshes [-]
    dense_columns = 3 * n + n_mesh + 2
  end function dense_columns

  !> Column before the load block of X (drive, load, then one column per mesh) [-].
  pure integer(ik) function load_block(n)
    integer(ik), intent(in) :: n  !< DOFs [-]
    load_block = 2 * n
  end function load_block

  !> Column before the mass block of X [-].
  pure integer(ik) function mass_block(n, n_mesh)
    integer(ik), intent(in) :: n       !< DOFs [-]
    integer(ik), intent(in) :: n_mesh  !< meshes [-]
    mass_block = 2 * n + n_mesh + 2
  end function mass_block

  !> R^T = [-C, -K0, -Khat / s, -M]^T and s Khat^-1 (transposed) at mean mesh
  !> stiffness, for the refined dense path (module header).
  subroutine refined_operators(n, kd, n_mesh, mass_band, damping_band, stiffness_band, &
                               khat_band, mesh, scale, operator, inverse, info)
    integer(ik), intent(in) :: n                           !< DOFs [-]
    integer(ik), intent(in) :: kd                          !< band subdiagonals [-]
    integer(ik), intent(in) :: n_mesh                      !< meshes [-]
    real(dp), intent(in) :: mass_band(kd + 1, n)           !< M [kg, kg m^2]
    real(dp), intent(in) :: damping_band(kd + 1, n)        !< C [N s/m, N m s/rad]
    real(dp), intent(in) :: stiffness_band(kd + 1, n)      !< K0 [N/m, N m/rad]
    real(dp), intent(in) :: khat_band(kd + 1, n)           !< Khat at mean mesh stiffness [N/m]
    type(sparse_rows), intent(in) :: mesh                  !< n_mesh rows b_m [m/m, m/rad]
    real(dp), intent(in) :: scale                          !< s = 1 / ((1 - alpha_f) beta dt^2) [1/s^2]
    real(dp), intent(out) :: operator(4 * n, n)            !< R^T [SI]
    real(dp), intent(out) :: inverse(n, n)                 !< s Khat^-1, transposed [1/kg]
    integer(ik), intent(out) :: info   !< 0; > 0 Khat not positive definite at that DOF; < 0 LAPACK argument [-]
    real(dp) :: unchanged(n_mesh)

    operator = 0.0_dp
    call negated_block(damping_band, 0_ik)
    call negated_block(stiffness_band, n)
    call negated_block(mass_band, 3 * n)
    unchanged = 0.0_dp
    call refined_stiffness(n, kd, n_mesh, khat_band, mesh, unchanged, scale, operator, inverse, &
                           info)

  contains

    !> operator(first + 1 : first + n, :) = -A for a symmetric band matrix A.
    subroutine negated_block(band, first)
      real(dp), intent(in) :: band(:, :)    !< (kd + 1, n) band of A [units of A]
      integer(ik), intent(in) :: first      !< rows of operator before the block [-]
      integer(ik) :: i, j
      do j = 1, n
        do i = j, min(n, j + kd)
          operator(first + i, j) = -band(i - j + 1, j)
          operator(first + j, i) = -band(i - j + 1, j)
        end do
      end do
    end subroutine negated_block
  end subroutine refined_operators

  !> One step of iterative refinement of a = X f against Khat: r = r0 + l - Khat a / s,
  !> a = a + s Khat^-1 r (module header).
  subroutine refine_solution(n, n_mesh, operator, inverse, weights, members, mesh, alpha_m, &
                             inertia, a, residual)
    integer(ik), intent(in) :: n                           !< DOFs [-]
    integer(ik), intent(in) :: n_mesh                      !< meshes [-]
    real(dp), intent(in) :: operator(4 * n, n)             !< R^T at the factored stiffness [SI]
    real(dp), intent(in) :: inverse(n, n)                  !< s Khat^-1 there, transposed [1/kg]
    real(dp), intent(in) :: weights(mass_block(n, n_mesh)) !< [w_c; w_k; l] of the dense product [SI]
    type(sparse_rows), intent(in) :: members               !< input (1) and output (2) member rotations [rad/rad]
    type(sparse_rows), intent(in) :: mesh                  !< n_mesh rows b_m [m/m, m/rad]
    real(dp), intent(in) :: alpha_m                        !< weight of the mass block [-]
    real(dp), intent(in) :: inertia(n)                     !< a_n, the mass block's vector [m/s^2, rad/s^2]
    real(dp), intent(inout) :: a(n)                        !< X f in, refined out [m/s^2, rad/s^2]
    real(dp), intent(out) :: residual(n)                   !< r [N, N m]
    integer(ik) :: loads, row, e

    loads = load_block(n)
    residual = 0.0_dp
    call dense_multiply_transposed(loads, n, operator, 4 * n, 0_ik, weights(1:loads), 0.0_dp, &
                                   residual)
    if (alpha_m /= 0.0_dp) call dense_multiply_transposed(n, n, operator, 4 * n, 3 * n, &
                                                          alpha_m * inertia, 1.0_dp, residual)
    do row = 1, 2  ! drive and load on their members, as the banded path adds them
      do e = members%ptr(row) + 1, members%ptr(row + 1)
        residual(members%index(e)) = residual(members%index(e)) + weights(loads + row) &
                                     * members%value(e)
      end do
    end do
    do row = 1, n_mesh
      do e = mesh%ptr(row) + 1, mesh%ptr(row + 1)
        residual(mesh%index(e)) = residual(mesh%index(e)) + weights(loads + 2 + row) &
                                  * mesh%value(e)
      end do
    end do
    call dense_multiply_transposed(n, n, operator, 4 * n, 2 * n, a, 1.0_dp, residual)
    call dense_multiply_transposed(n, n, inverse, n, 0_ik, residual, 1.0_dp, a)
  end subroutine refine_solution

  !> The -Khat / s block of R^T and s Khat^-1 (transposed) at mesh stiffness kbar +
  !> change, for the refined dense path (module header).
  subroutine refined_stiffness(n, kd, n_mesh, khat_band, mesh, change, scale, operator, &
                               inverse, info)
    integer(ik), intent(in) :: n                           !< DOFs [-]
    integer(ik), intent(in) :: kd                          !< band subdiagonals [-]
    integer(ik), intent(in) :: n_mesh                      !< meshes [-]
    real(dp), intent(in) :: khat_band(kd + 1, n)           !< Khat at mean mesh stiffness [N/m]
    type(sparse_rows), intent(in) :: mesh                  !< n_mesh rows b_m [m/m, m/rad]
    real(dp), intent(in) :: change(n_mesh)                 !< kf - kbar per mesh [N/m]
    real(dp), intent(in) :: scale                          !< s [1/s^2]
    real(dp), intent(inout) :: operator(4 * n, n)          !< R^T, its -Khat / s block set [SI]
    real(dp), intent(out) :: inverse(n, n)                 !< s Khat^-1, transposed [1/kg]
    integer(ik), intent(out) :: info   !< 0; > 0 Khat not positive definite at that DOF; < 0 LAPACK argument [-]
    real(dp), allocatable :: band(:, :), solution(:, :)
    integer(ik) :: m, p, r, i, j

    allocate (band(kd + 1, n), solution(n, n))
    band = khat_band
    do m = 1, n_mesh  ! Khat + sum_m (kf_m - kbar_m) b_m b_m^T (the band holds the couplings)
      if (change(m) == 0.0_dp) cycle
      do p = mesh%ptr(m) + 1, mesh%ptr(m + 1)
        do r = mesh%ptr(m) + 1, mesh%ptr(m + 1)
          i = mesh%index(r)
          j = mesh%index(p)
          if (i >= j) band(i - j + 1, j) = band(i - j + 1, j) + change(m) * mesh%value(r) &
                                           * mesh%value(p)
        end do
      end do
    end do
    operator(2 * n + 1:3 * n, :) = 0.0_dp
    do j = 1, n
      do i = j, min(n, j + kd)
        operator(2 * n + i, j) = -band(i - j + 1, j) / scale
        operator(2 * n + j, i) = -band(i - j + 1, j) / scale
      end do
    end do
    solution = 0.0_dp
    do j = 1, n
      solution(j, j) = scale
    end do
    call band_cholesky_factor(n, kd, band, info)
    if (info /= 0) return
    call band_cholesky_solve_columns(n, kd, band, n, solution, info)
    if (info /= 0) return
    inverse = transpose(solution)
  end subroutine refined_stiffness

  !> X0^T, the operator at mean mesh stiffness, and Z = B X0 (the meshes' deflections of
  !> its columns), from the band matrices of a problem.
  subroutine mean_operator(n, kd, n_mesh, mass_band, damping_band, stiffness_band, khat_band, &
                           members, mesh, scale, operator, mesh_products, info)
    integer(ik), intent(in) :: n                           !< DOFs [-]
    integer(ik), intent(in) :: kd                          !< band subdiagonals [-]
    integer(ik), intent(in) :: n_mesh                      !< meshes [-]
    real(dp), intent(in) :: mass_band(kd + 1, n)           !< M [kg, kg m^2]
    real(dp), intent(in) :: damping_band(kd + 1, n)        !< C [N s/m, N m s/rad]
    real(dp), intent(in) :: stiffness_band(kd + 1, n)      !< K0 [N/m, N m/rad]
    real(dp), intent(in) :: khat_band(kd + 1, n)           !< Khat at mean mesh stiffness [N/m]
    type(sparse_rows), intent(in) :: members               !< input (1) and output (2) member rotations [rad/rad]
    type(sparse_rows), intent(in) :: mesh                  !< n_mesh rows b_m [m/m, m/rad]
    real(dp), intent(in) :: scale                          !< s = 1 / ((1 - alpha_f) beta dt^2) [1/s^2]
    real(dp), intent(out) :: operator(dense_columns(n, n_mesh), n)       !< X0^T [SI]
    real(dp), intent(out) :: mesh_products(n_mesh, dense_columns(n, n_mesh)) !< Z = B X0 [SI]
    integer(ik), intent(out) :: info   !< 0; > 0 Khat not positive definite at that DOF; < 0 LAPACK argument [-]
    real(dp), allocatable :: factor(:, :), solution(:, :)
    integer(ik) :: columns, m, e, c

    columns = dense_columns(n, n_mesh)
    operator = 0.0_dp
    mesh_products = 0.0_dp
    allocate (factor(kd + 1, n), solution(n, columns))
    factor = khat_band
    call band_cholesky_factor(n, kd, factor, info)
    if (info /= 0) return
    call right_sides(n, kd, n_mesh, mass_band, damping_band, stiffness_band, members, mesh, &
                     scale, solution)
    call band_cholesky_solve_columns(n, kd, factor, columns, solution, info)
    if (info /= 0) return
    operator = transpose(solution)
    do c = 1, columns
      do m = 1, n_mesh
        do e = mesh%ptr(m) + 1, mesh%ptr(m + 1)
          mesh_products(m, c) = mesh_products(m, c) + mesh%value(e) * solution(mesh%index(e), c)
        end do
      end do
    end do
  end subroutine mean_operator

  !> X^T at mesh stiffness kbar + change, from X0^T and Z = B X0 by the Woodbury identity
  !> (see the module header).  info > 0: I + D B Y is singular (the new Khat is).
  pure subroutine stiffness_update(n, n_mesh, operator0, mesh_products, change, scale, &
                                   operator, info)
    integer(ik), intent(in) :: n                            !< DOFs [-]
    integer(ik), intent(in) :: n_mesh                       !< meshes [-]
    real(dp), intent(in) :: operator0(dense_columns(n, n_mesh), n)          !< X0^T [SI]
    real(dp), intent(in) :: mesh_products(n_mesh, dense_columns(n, n_mesh)) !< Z = B X0 [SI]
    real(dp), intent(in) :: change(n_mesh)                  !< kf - kbar per mesh [N/m]
    real(dp), intent(in) :: scale                           !< s [1/s^2]
    real(dp), intent(out) :: operator(dense_columns(n, n_mesh), n)          !< X^T [SI]
    integer(ik), intent(out) :: info                        !< 0, or the singular pivot [-]
    real(dp) :: capacitance(n_mesh, n_mesh), weights(n_mesh, dense_columns(n, n_mesh))
    real(dp) :: weights_t(dense_columns(n, n_mesh), n_mesh), y_im
    integer(ik) :: columns, loads, m, i

    columns = dense_columns(n, n_mesh)
    loads = load_block(n)
    ! I + D B Y with B Y = Z(:, mesh columns) / s; right-hand sides D Z
    do m = 1, n_mesh
      capacitance(m, :) = change(m) / scale * mesh_products(m, loads + 3:loads + 2 + n_mesh)
      capacitance(m, m) = capacitance(m, m) + 1.0_dp
      weights(m, :) = change(m) * mesh_products(m, :)
    end do
    call solve_small(n_mesh, capacitance, columns, weights, info)
    if (info /= 0) return
    ! X^T = X0^T - W^T Y^T, Y(i, m) = X0^T(mesh row m, i) / s; column by column of X^T
    weights_t = transpose(weights)
    operator = operator0
    do i = 1, n
      do m = 1, n_mesh
        y_im = operator0(loads + 2 + m, i) / scale
        operator(:, i) = operator(:, i) - y_im * weights_t(:, m)
      end do
    end do
  end subroutine stiffness_update

  !> Solve A X = B in place by Gaussian elimination with partial pivoting (A small and
  !> general); info is the first zero pivot, 0 if none.
  pure subroutine solve_small(m, a, columns, b, info)
    integer(ik), intent(in) :: m                   !< order [-]
    real(dp), intent(inout) :: a(m, m)             !< matrix, destroyed [-]
    integer(ik), intent(in) :: columns             !< right-hand sides [-]
    real(dp), intent(inout) :: b(m, columns)       !< right-hand sides in, solutions out [SI]
    integer(ik), intent(out) :: info               !< 0, or the first zero pivot [-]
    real(dp) :: row(max(m, columns)), factor
    integer(ik) :: k, i, pivot

    info = 0
    do k = 1, m
      pivot = k - 1 + int(maxloc(abs(a(k:m, k)), 1), ik)
      if (.not. (abs(a(pivot, k)) > 0.0_dp)) then
        info = k
        return
      end if
      if (pivot /= k) then
        row(1:m) = a(k, :)
        a(k, :) = a(pivot, :)
        a(pivot, :) = row(1:m)
        row(1:columns) = b(k, :)
        b(k, :) = b(pivot, :)
        b(pivot, :) = row(1:columns)
      end if
      do i = k + 1, m
        factor = a(i, k) / a(k, k)
        a(i, k + 1:) = a(i, k + 1:) - factor * a(k, k + 1:)
        b(i, :) = b(i, :) - factor * b(k, :)
      end do
    end do
    do k = m, 1, -1
      b(k, :) = (b(k, :) - matmul(a(k, k + 1:), b(k + 1:, :))) / a(k, k)
    end do
  end subroutine solve_small

  !> The right-hand sides s [-C, -K0, w_in, w_out, B^T, -M] of the dense operator.
  pure subroutine right_sides(n, kd, n_mesh, mass_band, damping_band, stiffness_band, members, &
                              mesh, scale, sides)
    integer(ik), intent(in) :: n                           !< DOFs [-]
    integer(ik), intent(in) :: kd                          !< band subdiagonals [-]
    integer(ik), intent(in) :: n_mesh                      !< meshes [-]
    real(dp), intent(in) :: mass_band(kd + 1, n)           !< M [kg, kg m^2]
    real(dp), intent(in) :: damping_band(kd + 1, n)        !< C [N s/m, N m s/rad]
    real(dp), intent(in) :: stiffness_band(kd + 1, n)      !< K0 [N/m, N m/rad]
    type(sparse_rows), intent(in) :: members               !< input (1) and output (2) member rotations [rad/rad]
    type(sparse_rows), intent(in) :: mesh                  !< n_mesh rows b_m [m/m, m/rad]
    real(dp), intent(in) :: scale                          !< s [1/s^2]
    real(dp), intent(out) :: sides(n, dense_columns(n, n_mesh))  !< right-hand sides [SI / s^2]
    integer(ik) :: row, e, loads, masses

    loads = load_block(n)
    masses = mass_block(n, n_mesh)
    sides = 0.0_dp
    call dense_band(-scale, damping_band, sides(:, 1:n))
    call dense_band(-scale, stiffness_band, sides(:, n + 1:2 * n))
    call dense_band(-scale, mass_band, sides(:, masses + 1:masses + n))
    do row = 1, 2
      do e = members%ptr(row) + 1, members%ptr(row + 1)
        sides(members%index(e), loads + row) = sides(members%index(e), loads + row) &
                                               + scale * members%value(e)
      end do
    end do
    do row = 1, n_mesh
      do e = mesh%ptr(row) + 1, mesh%ptr(row + 1)
        sides(mesh%index(e), loads + 2 + row) = sides(mesh%index(e), loads + 2 + row) &
                                                + scale * mesh%value(e)
      end do
    end do

  contains

    !> full = factor A for a symmetric band matrix A in lower storage.
    pure subroutine dense_band(factor, band, full)
      real(dp), intent(in) :: factor         !< scale [-]
      real(dp), intent(in) :: band(:, :)     !< (kd + 1, n) band of A [units of A]
      real(dp), intent(out) :: full(:, :)    !< (n, n) A [units of A]
      integer(ik) :: i, j
      full = 0.0_dp
      do j = 1, n
        do i = j, min(n, j + kd)
          full(i, j) = factor * band(i - j + 1, j)
          full(j, i) = full(i, j)
        end do
      end do
    end subroutine dense_band
  end subroutine right_sides
end module newmark_dense
