!> What one transient problem is, for the Newmark kernel (module newmark): the band
!> matrices, the settings, the meshes (sparse deflection and angle vectors, mean
!> stiffness, contact signs, a copy of the tooth-contact table), the members the
!> drive and load act on and their torque laws.  Python creates a problem once
!> (checked, with Khat at mean stiffness formed) and then starts and advances runs
!> of it by handle (module handles); a run's state stays with the caller.
!>
!> The problem holds its own copy of the tooth-contact table, with the meshes' k-bar
!> (the stiffness inside K0) as the table's mean stiffness: the table may then be
!> freed while the problem lives, and a run may shift the table's phases as it
!> rebases its rotation (newmark_advance takes the phases with the state).
!>
!> With tooth separation each mesh has a backlash (+inf: no coast flank) and a coast
!> phase offset (module flank_contact).
!>
!> Every mesh names its damper c_m, the share c_m b_m b_m^T of C that acts along its
!> line of action (beta kbar_m of Rayleigh damping beta K0).  C keeps it; with tooth
!> separation the kernel takes it out again by the equivalent load while the mesh's
!> flanks are apart (module newmark), so no damper force acts across an open gap.
!>
!> A problem on the dense path (iparam(ip_solver) = solver_dense, module newmark_dense)
!> also keeps its dense operator at mean mesh stiffness and the meshes' deflections of
!> its columns, formed once here; on the refined dense path (solver_refined) also the
!> residual operator and s Khat^-1 at mean mesh stiffness.  A problem on the sparse path
!> (solver_sparse, module newmark_sparse) holds M, C and K0 on one sparse pattern instead of the bands (kd = 0,
!> its band arrays unused) and the CHOLMOD factors of Khat and M, made here and released
!> with the problem.
!>
!> Rotor terms (gyroscopic force at a speed, unbalance; module newmark_gyroscopic) are
!> attached to a created problem by handle (wrappers_gyroscopic.f90); without them the
!> kernel takes its paths unchanged.
module newmark_problem
  use kinds, only: dp, ik
  use handles, only: handle_registry, keep_item, find_item, release_item, hd_ok, hd_err_full
  use contact_table, only: tooth_contact_table, contact_table_at, ct_ok, ct_err_handle
  use newmark_support, only: sparse_rows, torque_laws, effective_band, rows_fit, check_laws, &
                             n_rparam, n_iparam, rp_dt, rp_beta, rp_gamma, rp_alpha_m, rp_alpha_f, &
                             rp_tolerance, rp_deflection, ip_mode, ip_varying, ip_separation, &
                             ip_restart, ip_solver, mode_linear, mode_refactor, solver_banded, &
                             solver_dense, solver_sparse, solver_refined, nm_ok, nm_err_argument, &
                             nm_err_definite, nm_err_mass, nm_err_handle, nm_err_full, &
                             nm_err_unavailable, band_multiply
  use newmark_dense, only: dense_columns, mean_operator, refined_operators
  use newmark_gyroscopic, only: rotor_terms
  use rolling_bearing, only: bearing_set
  use newmark_sparse, only: sparse_operators, pattern_fits, factor_operators, free_operators, &
                            symmetric_multiply, symmetric_multiply_pair, so_ok, so_err_definite, &
                            so_err_mass, so_err_unavailable
  implicit none
  private

  public :: transient_problem, create_transient_problem, free_transient_problem, &
            transient_problem_at, problem_multiply, problem_restoring
  public :: matrix_mass, matrix_damping, matrix_stiffness

  integer(ik), parameter :: matrix_mass = 1       !< M, for problem_multiply
  integer(ik), parameter :: matrix_damping = 2    !< C
  integer(ik), parameter :: matrix_stiffness = 3  !< K0

  !> One transient problem; band matrices in LAPACK lower storage, RCM DOF order.
  type :: transient_problem
    integer(ik) :: n = 0                                 !< DOFs [-]
    integer(ik) :: kd = 0                                !< band subdiagonals [-]
    integer(ik) :: n_mesh = 0                            !< meshes [-]
    real(dp), allocatable :: mass_band(:, :)             !< (kd + 1, n) M [kg, kg m^2]
    real(dp), allocatable :: damping_band(:, :)          !< (kd + 1, n) C [N s/m, N m s/rad]
    real(dp), allocatable :: stiffness_band(:, :)        !< (kd + 1, n) K0 [N/m, N m/rad]
    real(dp), allocatable :: khat_band(:, :)             !< (kd + 1, n) Khat at mean stiffness [N/m]
    real(dp) :: rparam(n_rparam) = 0.0_dp                !< real settings (see layout) [SI]
    integer(ik) :: iparam(n_iparam) = 0                  !< integer settings (see layout) [-]
    type(sparse_rows) :: mesh                            !< n_mesh rows b_m, delta_m = b_m . q [m/m, m/rad]
    type(sparse_rows) :: angle                           !< n_mesh rows w_m, theta_m = w_m . q [rad/rad]
    real(dp), allocatable :: mean_stiffness(:)           !< kbar_m [N/m]
    integer(ik), allocatable :: contact_sign(:)          !< s_m = +1 or -1 [-]
    real(dp), allocatable :: backlash(:)                 !< b_m >= 0 on the line of action, +inf none [m]
    real(dp), allocatable :: coast_phase(:)              !< coast-flank phase offset [mesh cycles]
    real(dp), allocatable :: mesh_damping(:)             !< c_m >= 0, the mesh's damper inside C [N s/m]
    logical :: has_table = .false.                       !< a tooth-contact table is held [-]
    type(tooth_contact_table) :: table                   !< the meshes' table (time-varying stiffness)
    type(sparse_rows) :: members                         !< input (1) and output (2) member rotations [rad/rad]
    type(torque_laws) :: laws                            !< drive and load torque laws
    real(dp), allocatable :: dense_operator(:, :)        !< (3n + n_mesh + 2, n) dense path: X0^T [SI]
    real(dp), allocatable :: dense_mesh_products(:, :)   !< (n_mesh, 3n + n_mesh + 2) dense path: B X0 [SI]
    real(dp), allocatable :: refined_operator(:, :)      !< (4n, n) refined path: [-C, -K0, -Khat / s, -M]^T [SI]
    real(dp), allocatable :: refined_inverse(:, :)       !< (n, n) refined path: s Khat^-1, transposed [1/kg]
    type(sparse_operators) :: sparse                     !< sparse path: M, C, K0 and the factors
    type(rotor_terms) :: rotor                           !< gyroscopic and unbalance loads (module newmark_gyroscopic)
    type(bearing_set) :: bearings                        !< rolling bearings (module rolling_bearing), none by default
  end type transient_problem

  type(handle_registry), target :: registry  !< the problems Python holds handles of
  real(dp), parameter :: max_phase = 2.0_dp**50  !< |coast phase| beyond loses the cycle's digits

contains

  !> Check a problem, attach the contact table table_handle names (0: none) and keep
  !> it under a new handle with Khat formed.  bad names the first wrong entry (rparam
  !> index, iparam index + 100, or a law-table column + 1000).
  subroutine create_transient_problem(problem, table_handle, handle, bad, ierr)
    type(transient_problem), intent(in) :: problem  !< the problem (khat_band and table unset)
    integer(ik), intent(in) :: table_handle         !< contact table, 0 for constant stiffness [-]
    integer(ik), intent(out) :: handle              !< the problem's handle, 0 on error [-]
    integer(ik), intent(out) :: bad                 !< first wrong entry [-]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)
    type(tooth_contact_table), pointer :: table
    type(transient_problem) :: kept
    integer(ik) :: info

    handle = 0
    call check_problem(problem, bad, ierr)
    if (ierr /= nm_ok) return
    kept = problem
    if (table_handle /= 0) then
      call contact_table_at(table_handle, problem%n_mesh, table, ierr)
      if (ierr /= ct_ok) then
        ierr = merge(nm_err_handle, nm_err_argument, ierr == ct_err_handle)
        return
      end if
      kept%table = table
      kept%table%mean_stiffness = problem%mean_stiffness
      kept%has_table = .true.
    else if (problem%iparam(ip_varying) /= 0) then
      bad = 100 + ip_varying
      ierr = nm_err_argument
      return
    end if
    if (kept%iparam(ip_solver) == solver_sparse) then  ! the CHOLMOD factors of Khat and M
      kept%sparse%n = kept%n
      call factor_operators(kept%sparse, (1.0_dp - kept%rparam(rp_alpha_m)) / ((1.0_dp - &
                            kept%rparam(rp_alpha_f)) * kept%rparam(rp_beta) * kept%rparam(rp_dt)**2), &
                            kept%rparam(rp_gamma) / (kept%rparam(rp_beta) * kept%rparam(rp_dt)), &
                            kept%mean_stiffness, bad, info)
      if (info /= so_ok) then
        if (info == so_err_definite) then
          ierr = nm_err_definite
        else if (info == so_err_mass) then
          ierr = nm_err_mass
        else if (info == so_err_unavailable) then
          ierr = nm_err_unavailable
        else
          ierr = nm_err_argument
        end if
        return
      end if
      call keep_item(registry, kept, handle, ierr)
      if (ierr /= hd_ok) then
        call free_operators(kept%sparse)
        ierr = merge(nm_err_full, nm_err_handle, ierr == hd_err_full)
      end if
      return
    end if
    allocate (kept%khat_band(kept%kd + 1, kept%n))
    call effective_band(kept%n, kept%kd, kept%mass_band, kept%damping_band, kept%stiffness_band, &
                        kept%rparam, kept%khat_band)
    if (kept%iparam(ip_solver) == solver_dense .or. kept%iparam(ip_solver) == solver_refined) then
      allocate (kept%dense_operator(dense_columns(kept%n, kept%n_mesh), kept%n))
      allocate (kept%dense_mesh_products(kept%n_mesh, dense_columns(kept%n, kept%n_mesh)))
      call mean_operator(kept%n, kept%kd, kept%n_mesh, kept%mass_band, kept%damping_band, &
                         kept%stiffness_band, kept%khat_band, kept%members, kept%mesh, &
                         1.0_dp / ((1.0_dp - kept%rparam(rp_alpha_f)) * kept%rparam(rp_beta) &
                                   * kept%rparam(rp_dt) * kept%rparam(rp_dt)), &
                         kept%dense_operator, kept%dense_mesh_products, info)
      if (info /= 0) then  ! Khat is not positive definite
        ierr = merge(nm_err_definite, nm_err_argument, info > 0)
        bad = max(info, 0_ik)
        return
      end if
    end if
    if (kept%iparam(ip_solver) == solver_refined) then
      allocate (kept%refined_operator(4 * kept%n, kept%n), kept%refined_inverse(kept%n, kept%n))
      call refined_operators(kept%n, kept%kd, kept%n_mesh, kept%mass_band, kept%damping_band, &
                             kept%stiffness_band, kept%khat_band, kept%mesh, &
                             1.0_dp / ((1.0_dp - kept%rparam(rp_alpha_f)) * kept%rparam(rp_beta) &
                                       * kept%rparam(rp_dt) * kept%rparam(rp_dt)), &
                             kept%refined_operator, kept%refined_inverse, info)
      if (info /= 0) then
        ierr = merge(nm_err_definite, nm_err_argument, info > 0)
        bad = max(info, 0_ik)
        return
      end if
    end if
    call keep_item(registry, kept, handle, ierr)
    if (ierr /= hd_ok) ierr = merge(nm_err_full, nm_err_handle, ierr == hd_err_full)
  end subroutine create_transient_problem

  !> Release a problem; its handle is no longer valid.
  subroutine free_transient_problem(handle, ierr)
    integer(ik), intent(in) :: handle   !< handle from create_transient_problem [-]
    integer(ik), intent(out) :: ierr    !< error code (0 = ok)
    class(*), pointer :: item

    call find_item(registry, handle, item, ierr)
    if (associated(item)) then  ! the CHOLMOD factors live outside the registry
      select type (item)
      type is (transient_problem)
        call free_operators(item%sparse)
      end select
    end if
    call release_item(registry, handle, ierr)
    if (ierr /= hd_ok) ierr = nm_err_handle
  end subroutine free_transient_problem

  !> The problem a handle names, for as long as no problem is created or freed; n, kd
  !> and n_mesh must be the sizes of the caller's state arrays.
  subroutine transient_problem_at(handle, n, kd, n_mesh, problem, ierr)
    integer(ik), intent(in) :: handle                         !< handle from create_transient_problem [-]
    integer(ik), intent(in) :: n                              !< DOFs the caller expects [-]
    integer(ik), intent(in) :: kd                             !< subdiagonals the caller expects [-]
    integer(ik), intent(in) :: n_mesh                         !< meshes the caller expects [-]
    type(transient_problem), pointer, intent(out) :: problem  !< the problem, null on error
    integer(ik), intent(out) :: ierr                          !< error code (0 = ok)
    class(*), pointer :: item

    nullify (problem)
    call find_item(registry, handle, item, ierr)
    ierr = nm_err_handle
    if (.not. associated(item)) return
    select type (item)
    type is (transient_problem)
      ierr = nm_err_argument
      if (item%n /= n .or. item%kd /= kd .or. item%n_mesh /= n_mesh) return
      problem => item
      ierr = nm_ok
    end select
  end subroutine transient_problem_at

  !> Check sizes, indices and settings of a problem; bad names the first wrong entry.
  pure subroutine check_problem(problem, bad, ierr)
    type(transient_problem), intent(in) :: problem  !< the problem to check
    integer(ik), intent(out) :: bad                 !< first wrong entry [-]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)

    ierr = nm_err_argument
    bad = 0
    associate (n => problem%n, kd => problem%kd, n_mesh => problem%n_mesh, &
               rparam => problem%rparam, iparam => problem%iparam)
      if (n < 1 .or. kd < 0 .or. kd > n - 1 .or. n_mesh < 0) return
      if (.not. bands_fit(problem)) return
      if (iparam(ip_solver) == solver_sparse) then  ! one sparse pattern, no band
        if (kd /= 0 .or. problem%sparse%n /= n .or. .not. pattern_fits(problem%sparse)) return
      end if
      if (.not. (rparam(rp_dt) > 0.0_dp .and. rparam(rp_dt) < huge(1.0_dp))) then
        bad = rp_dt
        return
      end if
      if (.not. (rparam(rp_beta) > 0.0_dp)) then
        bad = rp_beta
        return
      end if
      if (.not. (rparam(rp_gamma) >= 0.0_dp)) then
        bad = rp_gamma
        return
      end if
      if (.not. (rparam(rp_alpha_m) < 1.0_dp)) then
        bad = rp_alpha_m
        return
      end if
      if (.not. (rparam(rp_alpha_f) >= 0.0_dp .and. rparam(rp_alpha_f) < 1.0_dp)) then
        bad = rp_alpha_f
        return
      end if
      if (.not. (rparam(rp_tolerance) > 0.0_dp)) then
        bad = rp_tolerance
        return
      end if
      if (.not. (rparam(rp_deflection) > 0.0_dp)) then
        bad = rp_deflection
        return
      end if
      if (iparam(ip_mode) < mode_linear .or. iparam(ip_mode) > mode_refactor) then
        bad = 100 + ip_mode
        return
      end if
      if (iparam(ip_solver) /= solver_banded .and. iparam(ip_solver) /= solver_dense .and. &
          iparam(ip_solver) /= solver_sparse .and. iparam(ip_solver) /= solver_refined) then
        bad = 100 + ip_solver
        return
      end if
      ! a restart solves the equation of motion at a step instant: average acceleration
      ! only (alpha_m = alpha_f = 0), and not with tooth separation (its zero stiffness
      ! is a contact state, not a table jump)
      if (iparam(ip_restart) < 0 .or. iparam(ip_restart) > 1 .or. (iparam(ip_restart) == 1 .and. &
          (rparam(rp_alpha_m) /= 0.0_dp .or. rparam(rp_alpha_f) /= 0.0_dp .or. &
           iparam(ip_separation) /= 0))) then
        bad = 100 + ip_restart
        return
      end if
      if (.not. (rows_fit(problem%mesh, n_mesh, n) .and. rows_fit(problem%angle, n_mesh, n) .and. &
                 rows_fit(problem%members, 2_ik, n))) return
      if (.not. (allocated(problem%mean_stiffness) .and. allocated(problem%contact_sign))) return
      if (size(problem%mean_stiffness) /= n_mesh .or. size(problem%contact_sign) /= n_mesh) return
      if (any(abs(problem%contact_sign) /= 1)) return
      if (.not. (allocated(problem%backlash) .and. allocated(problem%coast_phase))) return
      if (size(problem%backlash) /= n_mesh .or. size(problem%coast_phase) /= n_mesh) return
      ! NaN fails both tests; +inf backlash is allowed (no coast flank)
      if (.not. all(problem%backlash >= 0.0_dp)) return
      if (.not. all(abs(problem%coast_phase) < max_phase)) return
      if (.not. allocated(problem%mesh_damping)) return
      if (size(problem%mesh_damping) /= n_mesh) return
      if (.not. all(problem%mesh_damping >= 0.0_dp .and. problem%mesh_damping <= huge(1.0_dp))) &
        return
    end associate
    call check_laws(problem%laws, bad, ierr)
  end subroutine check_problem

  !> y = y + scale A x with A the problem's M, C or K0 (matrix_mass, matrix_damping,
  !> matrix_stiffness), band or sparse.
  pure subroutine problem_multiply(problem, matrix, x, scale, y)
    type(transient_problem), intent(in) :: problem  !< a checked problem
    integer(ik), intent(in) :: matrix               !< which matrix [-]
    real(dp), intent(in) :: x(problem%n)            !< vector [m, rad or per second]
    real(dp), intent(in) :: scale                   !< factor on A x [-]
    real(dp), intent(inout) :: y(problem%n)         !< accumulator [N, N m]

    if (problem%iparam(ip_solver) == solver_sparse) then
      select case (matrix)
      case (matrix_mass)
        call symmetric_multiply(problem%sparse, problem%sparse%mass, x, scale, y)
      case (matrix_damping)
        call symmetric_multiply(problem%sparse, problem%sparse%damping, x, scale, y)
      case default
        call symmetric_multiply(problem%sparse, problem%sparse%stiffness, x, scale, y)
      end select
    else
      select case (matrix)
      case (matrix_mass)
        call band_multiply(problem%n, problem%kd, problem%mass_band, x, scale, y)
      case (matrix_damping)
        call band_multiply(problem%n, problem%kd, problem%damping_band, x, scale, y)
      case default
        call band_multiply(problem%n, problem%kd, problem%stiffness_band, x, scale, y)
      end select
    end if
  end subroutine problem_multiply

  !> y = y - C v - K0 q, the damping and elastic forces at mean mesh stiffness; on the
  !> sparse path both products in one pass over the pattern.
  pure subroutine problem_restoring(problem, v, q, y)
    type(transient_problem), intent(in) :: problem  !< a checked problem
    real(dp), intent(in) :: v(problem%n)            !< velocities [m/s, rad/s]
    real(dp), intent(in) :: q(problem%n)            !< displacements [m, rad]
    real(dp), intent(inout) :: y(problem%n)         !< accumulator [N, N m]

    if (problem%iparam(ip_solver) == solver_sparse) then
      call symmetric_multiply_pair(problem%sparse, problem%sparse%damping, v, &
                                   problem%sparse%stiffness, q, -1.0_dp, y)
    else
      call problem_multiply(problem, matrix_damping, v, -1.0_dp, y)
      call problem_multiply(problem, matrix_stiffness, q, -1.0_dp, y)
    end if
  end subroutine problem_restoring

  !> The three band matrices are allocated with kd + 1 rows and n columns.
  pure logical function bands_fit(problem)
    type(transient_problem), intent(in) :: problem  !< the problem to inspect

    bands_fit = .false.
    if (.not. (allocated(problem%mass_band) .and. allocated(problem%damping_band) .and. &
               allocated(problem%stiffness_band))) return
    associate (band => [problem%kd + 1, problem%n])
      if (any(shape(problem%mass_band) /= band) .or. any(shape(problem%damping_band) /= band) .or. &
          any(shape(problem%stiffness_band) /= band)) return
    end associate
    bands_fit = .true.
  end function bands_fit
end module newmark_problem
