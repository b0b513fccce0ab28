!> Banded implicit time integration of M qdd + C qd + K0 q = F(t) - N(q, t)
!> (docs/model.md sections 5 and 6).
!>
!> Scheme: generalized-alpha (Chung & Hulbert) with parameters beta, gamma, alpha_m,
!> alpha_f; alpha_m = alpha_f = 0, beta = 1/4, gamma = 1/2 is the average-acceleration
!> Newmark method, alpha_m = 0 is HHT-alpha.  Unknown per step: the acceleration
!> a = q''(t_n+1).  With the predictors qt = q + dt v + dt^2 (1/2 - beta) a_n and
!> vt = v + dt (1 - gamma) a_n, q_n+1 = qt + beta dt^2 a and v_n+1 = vt + gamma dt a,
!> and the equation of motion at the generalized midpoint becomes
!>     Khat a = s (r0 + (1 - alpha_f) (F_n+1 - N_n+1)),   s = 1 / ((1 - alpha_f) beta dt^2),
!>     Khat = K0 + (1 - alpha_m) s M + gamma / (beta dt) C,
!>     r0 = -alpha_m M a_n - C ((1-alpha_f) vt + alpha_f v_n) - K0 ((1-alpha_f) qt + alpha_f q_n)
!>          + alpha_f (F_n - N_n).
!> Solving for a keeps the unknowns small while q grows with the rotation.
!>
!> Matrices are symmetric band matrices in LAPACK lower storage (ab(1 + i - j, j) =
!> A(i, j), j <= i <= j + kd); Khat is factored with dpbtrf and solved with dpbtrs
!> (module band_lapack), or, on the dense path (iparam(ip_solver) = solver_dense), each
!> solve is a product with a dense operator (module newmark_dense) that the problem
!> keeps at mean mesh stiffness; an advance forms it at the run's k_factored when a
!> refactor moved that, so the run's state stays the same on both paths (khat_factor,
!> the band factor, is used on the banded path only).  The refined dense path
!> (solver_refined) follows each product with one step of iterative refinement against
!> Khat, which makes the step backward stable (module newmark_dense).  On the sparse path
!> (solver_sparse, module newmark_sparse) the matrices are sparse and each solve uses
!> the problem's CHOLMOD factor of Khat, refactored numerically in refactor mode (and
!> first to the run's k_factored when another run left it elsewhere).
!> The DOF order is the caller's (reverse Cuthill-McKee in pygear).
!>
!> Meshes (equivalent load, the paper's eq. 25): mesh m has a sparse deflection
!> vector b_m (delta_m = b_m . q), mean stiffness kbar_m and contact sign s_m;
!> N(q, t) = sum_m (k_m - kbar_m) b_m delta_m with k_m the tooth-contact table's
!> stiffness at theta_m = w_m . q (time-varying mesh stiffness) or kbar_m.  With tooth
!> separation the mesh force is piecewise (module flank_contact): k_m delta_m on the
!> drive flank (s_m delta_m > 0), 0 inside the backlash b_m, k_coast_m (delta_m - o_m)
!> on the coast flank (s_m delta_m < -b_m, o_m = -s_m b_m, k_coast_m the table at the
!> coast phase), so that N_m = (k_m - kbar_m) delta_m - k_m o_m with k_m the stiffness
!> of the flank in contact (0 in free flight).  The stiffness in the factor, kf_m,
!> is kbar_m unless a refactor changed it; each evaluation then contributes the
!> lagged load g_m = N_m - (kf_m - kbar_m)(delta_m - deltat_m).
!> Mesh dampers: C holds each mesh's damper c_m b_m b_m^T (c_m = beta kbar_m of Rayleigh
!> damping); with tooth separation the damper acts only while a flank is in contact,
!> as the spring does, so N_m gains -c_m ddelta_m while the mesh flies free
!> (ddelta_m = b_m . v, 0 in contact): C v + N then holds no damper force across the
!> gap.  The factor keeps c_m (its share gamma c_m / (beta dt) of Khat is switched by
!> the same lagged load; Khat less the whole mesh term stays positive definite, so the
!> iteration contracts), and a mesh with c_m = 0, or any mesh without separation,
!> takes the path without the term.  When the teeth touch within a step, the step may
!> have no end state whose damper matches its flank: with the damper on, its force
!> c_m v throws the teeth back into the gap, with it off they end pressed in (for one
!> mass mu at speed v, when the gap left is between dt v (1 + c_m dt / (4 mu)) /
!> (1 + c_m dt / (2 mu)) and dt v).  A damper that switched twice within the step's
!> iteration therefore stays off for that step: it engages one step late, and never
!> acts across an open gap.  (The predictor mode, one evaluation, takes the damper's
!> state from the predicted flank as it does the spring's.)
!> A mesh whose table carries a displacement excitation e_m(s) (module contact_table)
!> has the force k_m (delta_m - s_m e_m): its offset o_m gains s_m e_m, and with tooth
!> separation the flank law reads delta_m - s_m e_m (drive contact while
!> s_m delta_m > e_m).
!> The table is evaluated once per step at the predicted angles (the mesh cycle is
!> the slow variable; a second call for the coast flanks when a mesh has a finite
!> backlash); deflections and the flank in contact follow the iterates.
!> Modes: predictor (one evaluation at the Newmark predictor qt, i.e. a_n+1 = 0 in
!> the mesh term: the paper's explicit equivalent load; extrapolating with a_n
!> instead excites the highest modes more), iterate (fixed point on the same
!> factor from that start), refactor (iterate; refactor Khat with the current
!> stiffness when it moved too far or the iteration does not converge).
!> Convergence test (iterate, refactor): an iterate is accepted when no lagged load
!> moved by more than tolerance * max_m(kbar_m |delta_m|) (floor kbar pico) and
!> neither torque by more than tolerance * max(|drive|, |load|).  A flank switch
!> (contact, free flight, coast) is a jump of g_m, so the step iterates until the
!> flank of every mesh is the same for two iterates; the equation of motion then
!> holds at t_n+1 with the piecewise force up to that tolerance, and with average
!> acceleration the discrete energy balance (kinetic energy plus the trapezoidal work
!> of the mesh, K0 and damping forces, a mesh damper's counted only where its flanks
!> touch, equals the trapezoidal work of the loads) closes to that tolerance times the
!> step's deflection change, per step (and, in a step whose damper engages late, to
!> that damper's end work).
!>
!> Rolling bearings (module rolling_bearing), when a problem has them: each bearing's
!> lagged load F_b - k_r (x, y) joins the meshes' in the equivalent load, from the same
!> predictor-plus-increment state, and in the convergence test against the larger of
!> its elements' force and its spring's; the factor keeps the body's spring k_r.  A
!> bearing's contact dampers read the rings' rates b.vt + gamma dt b.x, as the mesh
!> dampers read theirs.
!>
!> Loads: a drive torque on the input member and a load torque against the output
!> member, each a law of time (constant, ramp, table) or, for the load, of the
!> output speed switched on at t_s, the first instant the input speed reaches
!> omega_0 (the paper's eq. 31).  Members are sparse vectors over the DOFs.
!>
!> The problem (matrices, settings, meshes, loads) is a transient_problem (module
!> newmark_problem), created and checked once; newmark_start and newmark_advance take
!> it with the run's state, which the caller keeps between chunks.
!>
!> Rotor terms (module newmark_gyroscopic): the gyroscopic force -Omega G v and
!> unbalance forces enter the step equation as loads, the gyroscopic one at the
!> iterate's velocity inside the same iteration (modes linear and predictor iterate
!> too when a problem has them), accepted when it moved by at most tolerance times its
!> largest entry.  On the dense path their share s Khat^-1 f is -X_M M^-1 f, with X_M
!> the operator's mass block at the run's k_factored and M's band factor.
!>
!> Errors are returned as codes with the offending DOF, mesh or step; nothing stops.
module newmark
  use kinds, only: dp, ik
  use contact_table, only: tooth_contact_table, evaluate_contact, evaluate_excitation, &
                           has_excitation, ct_ok
  use flank_contact, only: flank_force_law, flank_compression, flank_coast, flank_free
  use newmark_support  ! codes, layouts, band and sparse helpers, torque laws
  use newmark_problem, only: transient_problem, problem_multiply, problem_restoring, matrix_mass
  use newmark_sparse, only: solve_khat, solve_mass, refactor_khat, so_ok
  use newmark_probes, only: record_probes
  use band_lapack, only: band_cholesky_factor, band_cholesky_solve, dense_multiply_transposed
  use newmark_dense, only: dense_columns, load_block, mass_block, stiffness_update, &
                           refined_stiffness, refine_solution
  use newmark_gyroscopic, only: add_rotor_load, add_gyroscopic_force, rotor_speed
  use rolling_bearing, only: bearing_rows, bearing_loads, add_bearing_loads, add_state_bearing_loads, &
                             bp_spring, bp_damping
  implicit none
  private

  public :: newmark_start, newmark_advance

contains

  !> Factor Khat, compute the initial acceleration from the equation of motion at
  !> t = 0 and the initial mesh and load state.
  subroutine newmark_start(problem, q, v, a, k_used, mesh_var, k_factored, khat_factor, rstate, &
                           istate, bad, ierr)
    type(transient_problem), intent(in) :: problem                    !< a checked problem
    real(dp), intent(in) :: q(problem%n)                              !< initial displacements [m, rad]
    real(dp), intent(in) :: v(problem%n)                              !< initial velocities [m/s, rad/s]
    real(dp), intent(out) :: a(problem%n)                             !< initial accelerations [m/s^2, rad/s^2]
    real(dp), intent(out) :: k_used(problem%n_mesh)                   !< mesh stiffness in force [N/m]
    real(dp), intent(out) :: mesh_var(problem%n_mesh)                 !< equivalent mesh load N_m at the state [N]
    real(dp), intent(out) :: k_factored(problem%n_mesh)               !< stiffness in the factor kf_m [N/m]
    real(dp), intent(out) :: khat_factor(problem%kd + 1, problem%n)   !< Cholesky factor of Khat [N/m]
    real(dp), intent(out) :: rstate(n_rstate)                         !< t_s [s], drive and load torque [N m]
    integer(ik), intent(out) :: istate(n_istate)                      !< counters (see layout) [-]
    integer(ik), intent(out) :: bad                                   !< offending index for ierr [-]
    integer(ik), intent(out) :: ierr                                  !< error code (0 = ok)
    real(dp), allocatable :: work(:, :), rhs(:), delta(:), offset(:)
    real(dp) :: speed
    integer(ik) :: info, j, n, kd, n_mesh
    logical :: on, coast_flank, sparse, damped
    logical, allocatable :: free(:)

    n = problem%n
    kd = problem%kd
    n_mesh = problem%n_mesh
    coast_flank = problem%iparam(ip_separation) /= 0 .and. any(problem%backlash <= huge(1.0_dp))
    damped = problem%iparam(ip_separation) /= 0 .and. any(problem%mesh_damping > 0.0_dp)
    a = 0.0_dp
    k_used = problem%mean_stiffness
    mesh_var = 0.0_dp
    k_factored = problem%mean_stiffness
    khat_factor = 0.0_dp
    rstate = [-1.0_dp, 0.0_dp, 0.0_dp]
    istate = 0
    bad = 0
    ierr = nm_ok
    if (.not. (all(abs(q) <= huge(1.0_dp)) .and. all(abs(v) <= huge(1.0_dp)))) then
      ierr = nm_err_not_finite
      bad = first_bad(q, v)
      return
    end if

    sparse = problem%iparam(ip_solver) == solver_sparse
    if (.not. sparse) then  ! the sparse path's factor is the problem's
      khat_factor = problem%khat_band
      call band_cholesky_factor(n, kd, khat_factor, info)
      if (info /= 0) then
        ierr = nm_err_definite
        bad = int(max(info, 0), ik)
        return
      end if
    end if

    ! loads and mesh state at t = 0
    speed = member_speed(problem%members, 1, v)
    on = problem%rparam(rp_speed) <= 0.0_dp
    if (.not. on .and. speed >= problem%rparam(rp_speed)) then
      on = .true.
      rstate(rs_t_s) = 0.0_dp
    end if
    if (on) istate(is_load_on) = 1
    rstate(rs_drive) = law_torque(problem%laws, 1, 0.0_dp, speed, on)
    rstate(rs_load) = law_torque(problem%laws, 2, 0.0_dp, member_speed(problem%members, 2, v), &
                              on)

    allocate (rhs(n), delta(n_mesh), offset(n_mesh), free(n_mesh))
    rhs = 0.0_dp
    call add_member(problem%members, 1, rstate(rs_drive), rhs)
    call add_member(problem%members, 2, -rstate(rs_load), rhs)
    call problem_restoring(problem, v, q, rhs)
    if (problem%rotor%active) call add_rotor_load(problem%rotor, 0.0_dp, v, 1.0_dp, .true., rhs)
    if (problem%iparam(ip_mode) /= mode_linear .and. n_mesh > 0) then
      call deflections(q, delta)
      call mesh_stiffness(q, delta, k_used, offset, free, ierr)
      if (ierr /= nm_ok) return
      mesh_var = (k_used - problem%mean_stiffness) * delta - k_used * offset
      if (damped) then  ! no damper force across an open gap
        do j = 1, n_mesh
          if (free(j)) mesh_var(j) = mesh_var(j) - problem%mesh_damping(j) * &
                                     sparse_dot(problem%mesh, j, v)
        end do
      end if
      do j = 1, n_mesh
        call add_sparse(problem%mesh, j, -mesh_var(j), rhs)
      end do
      ! rolling bearings (module rolling_bearing): their Hertz law in place of the spring
      if (problem%bearings%n_bearing > 0) call add_state_bearing_loads(problem%bearings, q, v, &
                                                                        -1.0_dp, rhs)
    end if
    if (sparse) then  ! M's factor is the problem's
      call solve_mass(problem%sparse, rhs, info)
      if (info /= so_ok) then
        ierr = nm_err_solve
        return
      end if
      a = rhs
      return
    end if
    allocate (work(kd + 1, n))
    work = problem%mass_band
    call band_cholesky_factor(n, kd, work, info)
    if (info /= 0) then
      ierr = nm_err_mass
      bad = int(max(info, 0), ik)
      return
    end if
    call band_cholesky_solve(n, kd, work, rhs, info)
    if (info /= 0) then
      ierr = nm_err_solve
      return
    end if
    a = rhs

  contains

    subroutine deflections(x, d)
      real(dp), intent(in) :: x(:)   !< displacements [m, rad]
      real(dp), intent(out) :: d(:)  !< mesh deflections [m]
      integer(ik) :: m
      do m = 1, n_mesh
        d(m) = sparse_dot(problem%mesh, m, x)
      end do
    end subroutine deflections

    subroutine mesh_stiffness(x, d, k, o, apart, code)
      real(dp), intent(in) :: x(:)      !< displacements [m, rad]
      real(dp), intent(in) :: d(:)      !< mesh deflections [m]
      real(dp), intent(out) :: k(:)     !< stiffness of the flank in contact [N/m]
      real(dp), intent(out) :: o(:)     !< deflection offsets of the flank forces [m]
      logical, intent(out) :: apart(:)  !< the mesh's flanks are apart (free flight) [-]
      integer(ik), intent(out) :: code  !< error code
      real(dp) :: theta(problem%n_mesh), pos(problem%table%max_pairs, problem%n_mesh)
      real(dp) :: k_drive(problem%n_mesh), k_coast(problem%n_mesh), shift(problem%n_mesh)
      integer(ik) :: pairs(problem%n_mesh), loaded(problem%n_mesh), m, flank
      integer(ik) :: tooth(2, problem%table%max_pairs, problem%n_mesh)
      type(tooth_contact_table) :: coast
      code = nm_ok
      o = 0.0_dp
      shift = 0.0_dp
      apart = .false.
      if (problem%iparam(ip_varying) /= 0) then
        do m = 1, n_mesh
          theta(m) = sparse_dot(problem%angle, m, x)
        end do
        call evaluate_contact(problem%table, theta, k, pairs, loaded, pos, tooth, code)
        istate(is_contact) = istate(is_contact) + 1
        k_coast = k
        if (code == ct_ok .and. coast_flank) then  ! the same table at the coast phase
          coast = problem%table
          coast%phase = coast%phase + problem%coast_phase
          call evaluate_contact(coast, theta, k_coast, pairs, loaded, pos, tooth, code)
          istate(is_contact) = istate(is_contact) + 1
        end if
        if (code == ct_ok .and. has_excitation(problem%table)) then  ! e_m along delta_m
          call evaluate_excitation(problem%table, theta, shift, code)
          shift = real(problem%contact_sign, dp) * shift
        end if
        if (code /= ct_ok) then
          code = nm_err_contact
          return
        end if
      else
        k = problem%mean_stiffness
        k_coast = k
      end if
      if (problem%iparam(ip_separation) /= 0) then
        k_drive = k
        do m = 1, n_mesh
          call flank_force_law(problem%contact_sign(m), d(m) - shift(m), problem%backlash(m), &
                               k_drive(m), k_coast(m), k(m), o(m), flank)
          apart(m) = flank == flank_free
        end do
      end if
      o = o + shift
    end subroutine mesh_stiffness
  end subroutine newmark_start

  !> Advance n_steps steps from the state (q, v, a) at step istate(1), recording the
  !> probes every decimation steps (and the state itself when it is step 0) and
  !> summing the velocities from step window_first_step on (0: no window).  phase and
  !> tooth_offset replace the table's (a rebased run shifts them).  On an error the
  !> state is the last good one and istate(1) the last completed step.
  subroutine newmark_advance(problem, probe_kind, probes, n_steps, decimation, window_first_step, &
                             phase, tooth_offset, q, v, a, k_used, mesh_var, k_factored, &
                             khat_factor, velocity_sum, rstate, istate, samples, n_samples, bad, ierr)
    type(transient_problem), intent(in) :: problem                    !< a checked problem
    integer(ik), intent(in) :: probe_kind(:)                          !< probe codes [-]
    type(sparse_rows), intent(in) :: probes                           !< probe weights (a mesh for mesh kinds) [-]
    integer(ik), intent(in) :: n_steps                                !< steps to advance [-]
    integer(ik), intent(in) :: decimation                             !< steps per recorded sample [-]
    integer(ik), intent(in) :: window_first_step                      !< first step summed into velocity_sum [-]
    real(dp), intent(in) :: phase(problem%n_mesh)                     !< the table's gamma now [mesh cycles]
    integer(ik), intent(in) :: tooth_offset(2, problem%n_mesh)        !< the table's i0, j0 now [-]
    real(dp), intent(inout) :: q(problem%n)                           !< displacements [m, rad]
    real(dp), intent(inout) :: v(problem%n)                           !< velocities [m/s, rad/s]
    real(dp), intent(inout) :: a(problem%n)                           !< accelerations [m/s^2, rad/s^2]
    real(dp), intent(inout) :: k_used(problem%n_mesh)                 !< mesh stiffness in force [N/m]
    real(dp), intent(inout) :: mesh_var(problem%n_mesh)               !< equivalent mesh load N_m at the state [N]
    real(dp), intent(inout) :: k_factored(problem%n_mesh)             !< stiffness in the factor [N/m]
    real(dp), intent(inout) :: khat_factor(problem%kd + 1, problem%n) !< factor of Khat at k_factored (banded path) [N/m]
    real(dp), intent(inout) :: velocity_sum(problem%n)                !< sum of v over the window [m/s, rad/s]
    real(dp), intent(inout) :: rstate(n_rstate)                       !< t_s [s], drive, load torque [N m]
    integer(ik), intent(inout) :: istate(n_istate)                    !< counters (see layout) [-]
    real(dp), intent(inout), contiguous :: samples(:, :)              !< (probes, columns) channels [channel units]
    integer(ik), intent(out) :: n_samples                             !< columns written [-]
    integer(ik), intent(out) :: bad                                   !< offending DOF, mesh or index [-]
    integer(ik), intent(out) :: ierr                                  !< error code (0 = ok)

    real(dp), allocatable :: qt(:), vt(:), r0(:), rhs(:), a_new(:), v_new(:), wc(:), wk(:)
    real(dp), allocatable :: delta(:), delta_t(:), k_eff(:), k_step(:), g(:), g_new(:), compression(:)
    real(dp), allocatable :: theta(:), position(:, :), mass_factor(:, :), k_coast(:), offset(:)
    real(dp), allocatable :: fused(:), a_base(:), load_old(:), x_transposed(:, :)
    real(dp), allocatable :: rate(:), rate_t(:), c_off(:), excite(:)
    real(dp), allocatable :: refine_operator(:, :), refine_inverse(:, :), refine_work(:)
    real(dp), allocatable :: rotor_fixed(:), rotor_force(:), rotor_last(:)
    integer(ik), allocatable :: pairs(:), loaded(:), tooth(:, :, :), flank(:), flips(:)
    logical, allocatable :: damper_on(:)
    type(tooth_contact_table) :: table, coast_table
    real(dp) :: dt, beta, gamma, alpha_m, alpha_f, scale_k, t_new, t_old, drive, load, drive_new, &
                load_new, speed_old, speed_new, omega_0, force_scale, change, torque_change
    integer(ik) :: step, it, m, refactors, mode, max_iterations, worst
    integer(ik) :: info, n, kd, n_mesh, n_probe
    integer(ik) :: loads, masses, columns
    logical :: nonlinear, converged, load_on, restart, separation, coast_flank, dense, single, sparse
    logical :: damped, refined, rotor, rotor_ok, bearings, excited
    real(dp), allocatable :: bearing_p(:), bearing_pt(:), gb(:, :), gb_trial(:, :), bearing_force(:, :)
    real(dp), allocatable :: bearing_v(:), bearing_vt(:)
    logical, allocatable :: element_contact(:, :)
    integer(ik), allocatable :: element_flips(:, :)
    integer(ik), allocatable :: bearing_loaded(:)
    real(dp) :: bearing_change, bearing_scale
    real(dp), parameter :: landing = 1.0e-6_dp  !< switch-on-step tolerance [steps]

    n = problem%n
    kd = problem%kd
    n_mesh = problem%n_mesh
    n_probe = int(size(probe_kind), ik)
    n_samples = 0
    speed_old = 0.0_dp
    bad = 0
    ierr = nm_ok
    if (n_steps < 0 .or. size(samples, 1) /= n_probe .or. .not. rows_fit(probes, n_probe, 0_ik)) then
      ierr = nm_err_argument
      return
    end if
    if (decimation < 1 .or. window_first_step < 0) then
      ierr = nm_err_argument
      return
    end if
    if (problem%has_table) then  ! the table at this run's phases
      table = problem%table
      table%phase = phase
      table%tooth_offset = tooth_offset
    end if
    separation = problem%iparam(ip_separation) /= 0
    coast_flank = separation .and. any(problem%backlash <= huge(1.0_dp))
    if (problem%has_table .and. coast_flank) then  ! the same table at the coast phase
      coast_table = table
      coast_table%phase = phase + problem%coast_phase
    end if
    dt = problem%rparam(rp_dt)
    beta = problem%rparam(rp_beta)
    gamma = problem%rparam(rp_gamma)
    alpha_m = problem%rparam(rp_alpha_m)
    alpha_f = problem%rparam(rp_alpha_f)
    omega_0 = problem%rparam(rp_speed)
    scale_k = 1.0_dp / ((1.0_dp - alpha_f) * beta * dt * dt)
    mode = problem%iparam(ip_mode)
    max_iterations = max(problem%iparam(ip_iterations), 1)
    nonlinear = mode /= mode_linear .and. n_mesh > 0
    load_on = istate(is_load_on) /= 0
    ! mesh dampers that follow the flanks (module header); without, the path of constant C
    damped = nonlinear .and. separation .and. any(problem%mesh_damping > 0.0_dp)
    ! rolling bearings join the meshes' equivalent load (not on the dense path: checked)
    bearings = nonlinear .and. problem%bearings%n_bearing > 0
    allocate (bearing_p(4 * problem%bearings%n_bearing), bearing_pt(4 * problem%bearings%n_bearing))
    allocate (bearing_v(4 * problem%bearings%n_bearing), bearing_vt(4 * problem%bearings%n_bearing))
    bearing_v = 0.0_dp
    bearing_vt = 0.0_dp
    ! each element's contact and damper switches within a step (module rolling_bearing)
    if (problem%bearings%n_bearing > 0) then
      allocate (element_contact(maxval(problem%bearings%elements), problem%bearings%n_bearing))
    else
      allocate (element_contact(1, 0))
    end if
    allocate (element_flips(size(element_contact, 1), problem%bearings%n_bearing))
    element_contact = .false.
    element_flips = 0
    allocate (gb(2, problem%bearings%n_bearing), gb_trial(2, problem%bearings%n_bearing))
    allocate (bearing_force(2, problem%bearings%n_bearing), bearing_loaded(problem%bearings%n_bearing))
    gb = 0.0_dp
    gb_trial = 0.0_dp
    bearing_change = 0.0_dp
    bearing_scale = 0.0_dp

    allocate (qt(n), vt(n), r0(n), rhs(n), a_new(n), v_new(n), wc(n), wk(n))
    allocate (delta(n_mesh), delta_t(n_mesh), k_eff(n_mesh), k_step(n_mesh), g(n_mesh), g_new(n_mesh))
    allocate (compression(n_mesh), k_coast(n_mesh), offset(n_mesh), flank(n_mesh))
    allocate (rate(n_mesh), rate_t(n_mesh), c_off(n_mesh), flips(n_mesh), damper_on(n_mesh))
    flips = 0
    damper_on = .true.
    offset = 0.0_dp
    ! displacement excitations s_m e_m along delta_m (module header), 0 without
    allocate (excite(n_mesh))
    excite = 0.0_dp
    excited = nonlinear .and. problem%has_table .and. problem%iparam(ip_varying) /= 0
    if (excited) excited = has_excitation(problem%table)
    rate = 0.0_dp
    c_off = 0.0_dp
    allocate (theta(n_mesh), position(problem%table%max_pairs, n_mesh), pairs(n_mesh), loaded(n_mesh))
    allocate (tooth(2, problem%table%max_pairs, n_mesh))
    refined = problem%iparam(ip_solver) == solver_refined
    dense = problem%iparam(ip_solver) == solver_dense .or. refined
    sparse = problem%iparam(ip_solver) == solver_sparse
    rotor = problem%rotor%active  ! gyroscopic and unbalance loads (module newmark_gyroscopic)
    if (rotor) allocate (rotor_fixed(n), rotor_force(n), rotor_last(n))
    rotor_ok = .true.
    loads = load_block(n)
    masses = mass_block(n, n_mesh)
    columns = dense_columns(n, n_mesh)
    ! one solve per step: on the dense path one product with X's state and load blocks
    single = mode == mode_linear .or. mode == mode_predictor
    allocate (fused(masses), a_base(n), load_old(n_mesh + 2))
    load_old = 0.0_dp
    if (dense) then  ! X^T at this run's k_factored (module newmark_dense)
      allocate (x_transposed(columns, n))
      if (any(k_factored /= problem%mean_stiffness)) then
        call stiffness_update(n, n_mesh, problem%dense_operator, problem%dense_mesh_products, &
                              k_factored - problem%mean_stiffness, scale_k, x_transposed, info)
        if (info /= 0) then
          ierr = nm_err_definite
          return
        end if
      else
        x_transposed = problem%dense_operator
      end if
    end if
    if (refined) then  ! its residual operator and s Khat^-1 at this run's k_factored
      refine_operator = problem%refined_operator
      refine_inverse = problem%refined_inverse
      allocate (refine_work(n))
      if (any(k_factored /= problem%mean_stiffness)) then
        call refined_stiffness(n, kd, n_mesh, problem%khat_band, problem%mesh, &
                               k_factored - problem%mean_stiffness, scale_k, refine_operator, &
                               refine_inverse, info)
        if (info /= 0) then
          ierr = nm_err_definite
          return
        end if
      end if
    end if
    if (sparse) then  ! the problem's factor at this run's k_factored
      if (any(k_factored /= problem%sparse%factor_stiffness)) then
        call refactor_khat(problem%sparse, problem%mesh, problem%mean_stiffness, k_factored, &
                           bad, info)
        if (info /= so_ok) then
          ierr = nm_err_definite
          return
        end if
      end if
    end if
    restart = problem%iparam(ip_restart) /= 0 .and. nonlinear .and. problem%iparam(ip_varying) /= 0
    if (restart .and. .not. sparse) then  ! M's factor for the restarts, once per call
      allocate (mass_factor(kd + 1, n))
      mass_factor = problem%mass_band
      call band_cholesky_factor(n, kd, mass_factor, info)
      if (info /= 0) then
        ierr = nm_err_definite
        bad = int(max(info, 0), ik)
        return
      end if
    end if

    if (excited) then  ! the excitation at the state the run starts from
      call sparse_products(problem%angle, q, theta)
      call evaluate_excitation(table, theta, excite, info)
      if (info /= ct_ok) then
        ierr = nm_err_contact
        return
      end if
      excite = real(problem%contact_sign, dp) * excite
    end if
    if (istate(is_step) == 0) then  ! the dampers of the touching flanks (probes' test)
      call record_probes(problem, probe_kind, probes, q, v, a, k_used, problem%mesh_damping, &
                         rstate, samples, n_samples, ierr, excite)
      if (ierr /= nm_ok) return
    end if

    do step = 1, n_steps
      t_old = real(istate(is_step), dp) * dt
      t_new = real(istate(is_step) + 1, dp) * dt
      qt = q + dt * v + (dt * dt * (0.5_dp - beta)) * a
      vt = v + (dt * (1.0_dp - gamma)) * a
      ! r0: everything on the right that does not change within the step (dense path:
      ! its weights wc, wk in fused(1:2n), a_0 = X_C wc + X_K wk + X_M alpha_m a and the
      ! old loads' shares)
      if (dense) then
        if (alpha_f == 0.0_dp) then
          fused(1:n) = vt
          fused(n + 1:loads) = qt
        else
          fused(1:n) = (1.0_dp - alpha_f) * vt + alpha_f * v
          fused(n + 1:loads) = (1.0_dp - alpha_f) * qt + alpha_f * q
        end if
        if (.not. single) call state_product()
        if (alpha_f /= 0.0_dp) then  ! else load_old stays 0
          load_old(1) = alpha_f * rstate(rs_drive)
          load_old(2) = -alpha_f * rstate(rs_load)
          if (nonlinear) load_old(3:) = -alpha_f * mesh_var
        end if
      else
        wc = (1.0_dp - alpha_f) * vt + alpha_f * v
        wk = (1.0_dp - alpha_f) * qt + alpha_f * q
        r0 = 0.0_dp
        call problem_restoring(problem, wc, wk, r0)
        if (alpha_m /= 0.0_dp) call problem_multiply(problem, matrix_mass, a, -alpha_m, r0)
      end if
      if (alpha_f /= 0.0_dp .and. .not. dense) then
        call add_member(problem%members, 1, alpha_f * rstate(rs_drive), r0)
        call add_member(problem%members, 2, -alpha_f * rstate(rs_load), r0)
        if (nonlinear) then
          do m = 1, n_mesh
            call add_sparse(problem%mesh, m, -alpha_f * mesh_var(m), r0)
          end do
        end if
        if (bearings) call add_state_bearing_loads(problem%bearings, q, v, -alpha_f, r0)
      end if
      if (omega_0 > 0.0_dp .and. .not. load_on) speed_old = member_speed(problem%members, 1, v)
      if (rotor) call rotor_step()

      ! first evaluation at the Newmark predictor (a = 0: q = qt; evaluate reads no x)
      call evaluate(a_new, .true., drive, load, g)
      if (ierr /= nm_ok) return
      gb = gb_trial
      if (restart) then
        if (any(abs(k_step - k_used) > problem%rparam(rp_refactor) * problem%mean_stiffness)) then
          call restart_acceleration()
          if (ierr /= nm_ok) return
          call evaluate(a_new, .true., drive, load, g)
          if (ierr /= nm_ok) return
          gb = gb_trial
        end if
      end if
      refactors = 0
      if (mode == mode_refactor) then
        if (any(abs(k_step - k_factored) > problem%rparam(rp_refactor) * problem%mean_stiffness)) then
          call refactor(k_step)
          if (ierr /= nm_ok) return
          a_new = 0.0_dp  ! still the predictor
          call evaluate(a_new, .false., drive, load, g)
          if (ierr /= nm_ok) return
          gb = gb_trial
        end if
      end if

      converged = .false.
      worst = 0
      it = 0
      do
        it = it + 1
        if (dense) then  ! a = a_0 + X_L [drive; -load; -g]
          fused(loads + 1) = load_old(1) + (1.0_dp - alpha_f) * drive
          fused(loads + 2) = load_old(2) - (1.0_dp - alpha_f) * load
          fused(loads + 3:) = load_old(3:) - (1.0_dp - alpha_f) * g
          if (single) then  ! a_0 and the loads in one product
            a_new = 0.0_dp
            call dense_multiply_transposed(masses, n, x_transposed, columns, 0_ik, fused, 1.0_dp, &
                                           a_new)
            if (alpha_m /= 0.0_dp) call dense_multiply_transposed(n, n, x_transposed, columns, &
                                                                  masses, alpha_m * a, 1.0_dp, a_new)
          else
            a_new = a_base
            call dense_multiply_transposed(n_mesh + 2, n, x_transposed, columns, loads, &
                                           fused(loads + 1:), 1.0_dp, a_new)
          end if
          if (refined) call refine_solution(n, n_mesh, refine_operator, refine_inverse, fused, &
                                            problem%members, problem%mesh, alpha_m, a, a_new, &
                                            refine_work)
          ! the rotor's share after the refinement: the refinement's residual holds the
          ! dense product's loads only, and would take a share added before it back out
          if (rotor) call dense_rotor_share()
          if (ierr /= nm_ok) return
        else
          rhs = r0
          call add_member(problem%members, 1, (1.0_dp - alpha_f) * drive, rhs)
          call add_member(problem%members, 2, -(1.0_dp - alpha_f) * load, rhs)
          if (nonlinear) then
            do m = 1, n_mesh
              call add_sparse(problem%mesh, m, -(1.0_dp - alpha_f) * g(m), rhs)
            end do
          end if
          if (rotor) rhs = rhs + rotor_force
          if (bearings) call add_bearing_loads(problem%bearings, gb, -(1.0_dp - alpha_f), rhs)
          rhs = scale_k * rhs
          if (sparse) then
            call solve_khat(problem%sparse, rhs, info)
          else
            call band_cholesky_solve(n, kd, khat_factor, rhs, info)
          end if
          if (info /= 0) then
            ierr = nm_err_solve
            return
          end if
          a_new = rhs
        end if
        if (mode == mode_linear .or. mode == mode_predictor) then
          converged = .true.
          if (rotor) converged = rotor_settled(a_new)  ! the gyroscopic force iterates
          if (converged .or. it >= max_iterations) exit
          cycle
        end if
        call evaluate(a_new, .false., drive_new, load_new, g_new)
        if (ierr /= nm_ok) return
        force_scale = max(maxval(problem%mean_stiffness * abs(delta)), &
                          maxval(problem%mean_stiffness) * pico)
        change = maxval(abs(g_new - g))
        worst = int(maxloc(abs(g_new - g), 1), ik)
        torque_change = max(abs(drive_new - drive), abs(load_new - load))
        if (bearings) then  ! a bearing's load against its elements' force or its spring's
          bearing_change = maxval(abs(gb_trial - gb))
          bearing_scale = max(maxval(abs(bearing_force)), &
                              maxval(problem%bearings%param(bp_spring, :) * abs(bearing_p(1::4))), &
                              maxval(problem%bearings%param(bp_spring, :) * abs(bearing_p(2::4))), &
                              pico)
          if (bearing_change > problem%rparam(rp_tolerance) * bearing_scale) &
            worst = n_mesh + int(maxloc(maxval(abs(gb_trial - gb), 1), 1), ik)
          gb = gb_trial
        end if
        g = g_new
        drive = drive_new
        load = load_new
        if (rotor) rotor_ok = rotor_settled(a_new)
        ! the gyroscopic force alone still moves: no mesh to name (bad = 0)
        if (.not. rotor_ok .and. change <= problem%rparam(rp_tolerance) * force_scale) worst = 0
        if (change <= problem%rparam(rp_tolerance) * force_scale .and. torque_change <= &
            problem%rparam(rp_tolerance) * max(abs(drive), abs(load), tiny(1.0_dp)) .and. &
            rotor_ok .and. bearing_change <= problem%rparam(rp_tolerance) * bearing_scale) then
          converged = .true.
          exit
        end if
        if (it >= max_iterations) then
          if (mode == mode_refactor .and. refactors < problem%iparam(ip_refactors)) then
            call refactor(k_eff)
            if (ierr /= nm_ok) return
            call evaluate(a_new, .false., drive, load, g)
            if (ierr /= nm_ok) return
            gb = gb_trial
            it = 0
          else
            exit
          end if
        end if
      end do
      istate(is_iterations) = istate(is_iterations) + it
      istate(is_max_iterations) = max(istate(is_max_iterations), it)
      if (.not. converged) then
        ierr = nm_err_convergence
        bad = worst
        return
      end if

      ! accept the step (the state stays the last good one until every check passed)
      if (.not. (maxval(abs(a_new)) <= problem%rparam(rp_acceleration))) then
        v_new = vt + (gamma * dt) * a_new
        ierr = nm_err_not_finite
        bad = first_bad(a_new, v_new)
        return
      end if
      if (nonlinear) then
        call sparse_products(problem%mesh, a_new, delta)
        if (damped) rate = rate_t + (gamma * dt) * delta
        delta = delta_t + (beta * dt * dt) * delta
        ! inside the backlash the teeth may gape; only the flank in contact runs away
        if (separation) then
          do m = 1, n_mesh
            compression(m) = flank_compression(problem%contact_sign(m), delta(m), &
                                               problem%backlash(m))
          end do
        else
          compression = abs(delta)
        end if
        if (any(compression > problem%rparam(rp_deflection))) then
          ierr = nm_err_deflection
          bad = int(maxloc(compression, 1), ik)
          return
        end if
        k_used = k_eff
        if (separation .or. excited) then
          mesh_var = (k_eff - problem%mean_stiffness) * delta - k_eff * offset
        else
          mesh_var = (k_eff - problem%mean_stiffness) * delta
        end if
        if (damped) mesh_var = mesh_var - c_off * rate
        istate(is_separated) = istate(is_separated) + &
                               count(k_eff == 0.0_dp .and. problem%mean_stiffness > 0.0_dp)
        if (separation) istate(is_coast) = istate(is_coast) + count(flank == flank_coast)
      end if
      q = qt + (beta * dt * dt) * a_new
      v = vt + (gamma * dt) * a_new
      a = a_new
      rstate(rs_drive) = drive
      rstate(rs_load) = load
      istate(is_step) = istate(is_step) + 1

      ! t_s: the first instant the input speed reaches omega_0 (linear in the step)
      if (omega_0 > 0.0_dp .and. .not. load_on) then
        speed_new = member_speed(problem%members, 1, v)
        if (speed_new >= omega_0) then
          load_on = .true.
          istate(is_load_on) = 1
          rstate(rs_t_s) = t_old + dt * (omega_0 - speed_old) / (speed_new - speed_old)
        end if
      end if
      if (window_first_step > 0 .and. istate(is_step) >= window_first_step) then
        velocity_sum = velocity_sum + v
        istate(is_window) = istate(is_window) + 1
      end if
      if (decimation == 1 .or. modulo(istate(is_step), decimation) == 0) then
        call record_probes(problem, probe_kind, probes, q, v, a, k_used, &
                           problem%mesh_damping - c_off, rstate, samples, n_samples, ierr, excite)
        if (ierr /= nm_ok) return
      end if
    end do

  contains

    !> The rotor loads of a step (module newmark_gyroscopic): rotor_fixed holds the
    !> alpha_f share at t_n and the unbalance at t_n+1, rotor_force adds the gyroscopic
    !> force at t_n+1 and the velocities the last acceleration would give, vt + gamma dt
    !> a_n (off by gamma dt (a_n+1 - a_n), a step's change, where vt alone is off by
    !> gamma dt a_n+1: the iteration then starts closer).
    subroutine rotor_step()
      rotor_fixed = 0.0_dp
      if (alpha_f /= 0.0_dp) call add_rotor_load(problem%rotor, t_old, v, alpha_f, .true., &
                                                 rotor_fixed)
      call add_rotor_load(problem%rotor, t_new, vt, 1.0_dp - alpha_f, .false., rotor_fixed)
      v_new = vt + (gamma * dt) * a
      call rotor_update(v_new)
    end subroutine rotor_step

    !> rotor_force at t_n+1 with the gyroscopic force at velocities x.
    subroutine rotor_update(x)
      real(dp), intent(in) :: x(:)  !< velocities at t_n+1 [m/s, rad/s]
      real(dp) :: speed, rate, angle
      call rotor_speed(problem%rotor, t_new, x, speed, rate, angle)
      rotor_force = rotor_fixed
      call add_gyroscopic_force(problem%rotor, speed, x, 1.0_dp - alpha_f, rotor_force)
    end subroutine rotor_update

    !> Update rotor_force to the iterate's velocities (x the trial acceleration); true
    !> when it moved by at most tolerance times its largest entry.
    logical function rotor_settled(x)
      real(dp), intent(in) :: x(:)  !< trial acceleration [m/s^2, rad/s^2]
      rotor_last = rotor_force
      v_new = vt + (gamma * dt) * x
      call rotor_update(v_new)
      rotor_settled = maxval(abs(rotor_force - rotor_last)) <= problem%rparam(rp_tolerance) * &
                      max(maxval(abs(rotor_force)), tiny(1.0_dp))
    end function rotor_settled

    !> Dense path: a_new = a_new + s Khat^-1 rotor_force = a_new - X_M M^-1 rotor_force.
    subroutine dense_rotor_share()
      rhs = rotor_force
      call band_cholesky_solve(n, kd, problem%rotor%mass_factor, rhs, info)
      if (info /= 0) then
        ierr = nm_err_solve
        return
      end if
      rhs = -rhs
      call dense_multiply_transposed(n, n, x_transposed, columns, masses, rhs, 1.0_dp, a_new)
    end subroutine dense_rotor_share

    !> A mesh stiffness jumped between the last step and this one (a tooth pair
    !> entered or left contact): take the acceleration at t_n from the equation of
    !> motion with the new stiffness, M (a+ - a) = -sum_m ((k_m - kbar_m) delta_m -
    !> mesh_var_m) b_m, and rebuild the predictor.  When steps land on the switching
    !> instants this keeps the trapezoidal rule second order across the jump.
    subroutine restart_acceleration()
      integer(ik) :: mm
      real(dp) :: delta_n
      rhs = 0.0_dp
      do mm = 1, n_mesh
        delta_n = sparse_dot(problem%mesh, mm, q)
        call add_sparse(problem%mesh, mm, &
                        -((k_step(mm) - problem%mean_stiffness(mm)) * delta_n &
                          - k_step(mm) * excite(mm) - mesh_var(mm)), rhs)
        mesh_var(mm) = (k_step(mm) - problem%mean_stiffness(mm)) * delta_n - k_step(mm) * excite(mm)
      end do
      if (sparse) then
        call solve_mass(problem%sparse, rhs, info)
      else
        call band_cholesky_solve(n, kd, mass_factor, rhs, info)
      end if
      if (info /= 0) then
        ierr = nm_err_solve
        return
      end if
      a = a + rhs
      k_used = k_step
      istate(is_restarts) = istate(is_restarts) + 1
      qt = q + dt * v + (dt * dt * (0.5_dp - beta)) * a
      vt = v + (dt * (1.0_dp - gamma)) * a
      if (dense) then  ! alpha_m = alpha_f = 0 (checked)
        fused(1:n) = vt
        fused(n + 1:loads) = qt
        if (.not. single) call state_product()
      else
        r0 = 0.0_dp
        call problem_restoring(problem, vt, qt, r0)
      end if
    end subroutine restart_acceleration

    !> a_0 = X_C w_c + X_K w_k (+ X_M alpha_m a_n) on the dense path (fused(1:2n) = [w_c; w_k]).
    subroutine state_product()
      a_base = 0.0_dp
      call dense_multiply_transposed(loads, n, x_transposed, columns, 0_ik, fused(1:loads), 1.0_dp, &
                                     a_base)
      if (alpha_m /= 0.0_dp) call dense_multiply_transposed(n, n, x_transposed, columns, masses, &
                                                            alpha_m * a, 1.0_dp, a_base)
    end subroutine state_product

    !> Loads and lagged mesh loads at the state a step-acceleration x gives.  The
    !> table's stiffness is a function of the slow mesh-cycle position: it is
    !> evaluated once per step, at the predictor (first = .true.); the deflections
    !> and the flank in contact (tooth separation) follow every iterate.
    subroutine evaluate(x, first, drive_x, load_x, g_x)
      real(dp), intent(in) :: x(:)        !< trial acceleration [m/s^2, rad/s^2]
      logical, intent(in) :: first        !< first evaluation of the step [-]
      real(dp), intent(out) :: drive_x    !< drive torque [N m]
      real(dp), intent(out) :: load_x     !< load torque [N m]
      real(dp), intent(out) :: g_x(:)     !< lagged mesh loads [N]
      integer(ik) :: mm, code
      real(dp) :: speeds(2)
      logical :: on
      if (first) then  ! x = 0: the predictor itself
        call sparse_products(problem%members, vt, speeds)
      else
        v_new = vt + (gamma * dt) * x
        call sparse_products(problem%members, v_new, speeds)
      end if
      drive_x = law_torque(problem%laws, 1, t_new, speeds(1), load_on)
      load_x = law_torque(problem%laws, 2, t_new, speeds(2), load_on)
      if (bearings) then  ! rings as the deflections: qt's products plus exact increments
        if (first) then
          call bearing_rows(problem%bearings, qt, bearing_pt)
          bearing_p = bearing_pt
          ! contact dampers: the rates b.vt + gamma dt b.x, as the rings' positions
          if (any(problem%bearings%param(bp_damping, :) > 0.0_dp)) &
            call bearing_rows(problem%bearings, vt, bearing_vt)
          bearing_v = bearing_vt
          element_flips = 0
        else
          call bearing_rows(problem%bearings, x, bearing_p)
          bearing_v = bearing_vt + (gamma * dt) * bearing_p
          bearing_p = bearing_pt + (beta * dt * dt) * bearing_p
        end if
        call bearing_loads(problem%bearings, bearing_p, bearing_v, gb_trial, bearing_force, &
                           bearing_loaded, element_contact, element_flips, .not. first)
      end if
      if (.not. nonlinear) then
        g_x = 0.0_dp
        return
      end if
      ! delta = b.qt + beta dt^2 b.x: iterates differ by exact small increments, not by
      ! the rounding of b.q (q grows with the rotation, delta stays near 1e-8 m)
      if (first) then
        call sparse_products(problem%mesh, qt, delta_t)
        delta = delta_t
        if (damped) then  ! deflection rates b.vt + gamma dt b.x, as the deflections
          call sparse_products(problem%mesh, vt, rate_t)
          rate = rate_t
        end if
      else
        call sparse_products(problem%mesh, x, delta)
        if (damped) rate = rate_t + (gamma * dt) * delta
        delta = delta_t + (beta * dt * dt) * delta
      end if
      if (first) then
        if (problem%iparam(ip_varying) /= 0) then
          call sparse_products(problem%angle, qt, theta)
          if (restart) then
            ! a switch within a millionth of a step of the step's end counts as on it:
            ! the step then sees the old stiffness and the next one restarts with the new
            do mm = 1, n_mesh
              theta(mm) = theta(mm) - landing * (theta(mm) - &
                          sparse_dot(problem%angle, mm, q))
            end do
          end if
          call evaluate_contact(table, theta, k_step, pairs, loaded, position, tooth, code)
          istate(is_contact) = istate(is_contact) + 1
          if (code == ct_ok .and. coast_flank) then
            call evaluate_contact(coast_table, theta, k_coast, pairs, loaded, position, tooth, &
                                  code)
            istate(is_contact) = istate(is_contact) + 1
          else if (separation) then
            k_coast = k_step
          end if
          if (code == ct_ok .and. excited) then
            call evaluate_excitation(table, theta, excite, code)
            excite = real(problem%contact_sign, dp) * excite
          end if
          if (code /= ct_ok) then
            ierr = nm_err_contact
            bad = 0
            return
          end if
        else
          k_step = problem%mean_stiffness
          k_coast = k_step
        end if
      end if
      ! the flank force law sets k_eff and offset with tooth separation; offset stays 0
      ! without, and k_factored stays k-bar unless a refactor changed it
      k_eff = k_step
      if (separation) then
        do mm = 1, n_mesh
          call flank_force_law(problem%contact_sign(mm), delta(mm) - excite(mm), &
                               problem%backlash(mm), k_step(mm), k_coast(mm), k_eff(mm), &
                               offset(mm), flank(mm))
        end do
        if (excited) offset = offset + excite
        g_x = (k_eff - problem%mean_stiffness) * delta - k_eff * offset
      else if (excited) then
        offset = excite
        g_x = (k_eff - problem%mean_stiffness) * delta - k_eff * offset
      else
        g_x = (k_eff - problem%mean_stiffness) * delta
      end if
      if (damped) then  ! the damper C holds is taken out while the flanks are apart
        if (first) flips = 0
        do mm = 1, n_mesh
          on = flank(mm) /= flank_free
          if (.not. first .and. (on .neqv. damper_on(mm))) flips(mm) = flips(mm) + 1
          ! a damper that switched twice has no end state of the step that matches its
          ! flank: the teeth touch within the step and the damper's force c_m v at
          ! contact throws them back; it stays off for this step (module header)
          if (flips(mm) >= 2) on = .false.
          damper_on(mm) = on
          c_off(mm) = merge(0.0_dp, problem%mesh_damping(mm), on)
        end do
        g_x = g_x - c_off * rate
      end if
      if (mode == mode_refactor) g_x = g_x - (k_factored - problem%mean_stiffness) * (delta - delta_t)
    end subroutine evaluate

    !> Refactor Khat with mesh stiffness k_new: the table's at the step start (the
    !> separation state stays in the convergent lagged term, putting an open contact
    !> into the factor makes the iteration chatter), the full contact state only
    !> when the iteration failed to converge.
    subroutine refactor(k_new)
      real(dp), intent(in) :: k_new(:)  !< mesh stiffness for the factor [N/m]
      integer(ik) :: mm, i, j, p, r
      refactors = refactors + 1
      istate(is_refactors) = istate(is_refactors) + 1
      k_factored = k_new
      if (dense) then  ! the operator from X0 (Woodbury), and a_0 with it
        call stiffness_update(n, n_mesh, problem%dense_operator, problem%dense_mesh_products, &
                              k_factored - problem%mean_stiffness, scale_k, x_transposed, info)
        if (info /= 0) then
          ierr = nm_err_definite
          bad = 0
          return
        end if
        call state_product()
        if (refined) then
          call refined_stiffness(n, kd, n_mesh, problem%khat_band, problem%mesh, &
                                 k_factored - problem%mean_stiffness, scale_k, refine_operator, &
                                 refine_inverse, info)
          if (info /= 0) then
            ierr = nm_err_definite
            bad = int(max(info, 0), ik)
          end if
        end if
        return
      end if
      if (sparse) then  ! CHOLMOD refactors the problem's factor numerically
        call refactor_khat(problem%sparse, problem%mesh, problem%mean_stiffness, k_factored, &
                           bad, info)
        if (info /= so_ok) ierr = nm_err_definite
        return
      end if
      khat_factor = problem%khat_band
      do mm = 1, n_mesh
        do p = problem%mesh%ptr(mm) + 1, problem%mesh%ptr(mm + 1)
          do r = problem%mesh%ptr(mm) + 1, problem%mesh%ptr(mm + 1)
            i = problem%mesh%index(r)
            j = problem%mesh%index(p)
            if (i >= j) khat_factor(i - j + 1, j) = khat_factor(i - j + 1, j) + &
                (k_factored(mm) - problem%mean_stiffness(mm)) * problem%mesh%value(r) * problem%mesh%value(p)
          end do
        end do
      end do
      call band_cholesky_factor(n, kd, khat_factor, info)
      if (info /= 0) then
        ierr = nm_err_definite
        bad = int(max(info, 0), ik)
      end if
    end subroutine refactor
  end subroutine newmark_advance

end module newmark
