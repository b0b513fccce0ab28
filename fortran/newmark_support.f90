!> Building blocks of the Newmark kernel (module newmark): option and error codes,
!> the layouts of the settings and state arrays, symmetric band products, sparse
!> member and mesh vectors, torque laws and the check of every setting.
module newmark_support
  use kinds, only: dp, ik
  implicit none
  private

  public :: band_multiply, effective_band, torque_law, check_settings
  public :: sparse_dot, add_sparse, member_speed, add_member, first_bad
  public :: mode_linear, mode_predictor, mode_iterate, mode_refactor
  public :: law_none, law_constant, law_ramp, law_table, law_speed_power
  public :: probe_displacement, probe_velocity, probe_acceleration, probe_mesh_force, &
            probe_mesh_stiffness, probe_drive_torque, probe_load_torque
  public :: nm_ok, nm_err_argument, nm_err_definite, nm_err_mass, nm_err_not_finite, &
            nm_err_deflection, nm_err_convergence, nm_err_contact, nm_err_size, nm_err_solve
  public :: rp_dt, rp_beta, rp_gamma, rp_alpha_m, rp_alpha_f, rp_tolerance, rp_refactor, &
            rp_deflection, rp_speed, rp_acceleration
  public :: ip_mode, ip_iterations, ip_varying, ip_separation, ip_decimation, ip_window, &
            ip_refactors, ip_restart
  public :: is_step, is_load_on, is_iterations, is_refactors, is_max_iterations, is_window, &
            is_separated, is_contact, is_restarts
  public :: rs_t_s, rs_drive, rs_load, pico

  ! equivalent-load modes (iparam(ip_mode))
  integer(ik), parameter :: mode_linear = 0     !< no mesh terms: K0 only
  integer(ik), parameter :: mode_predictor = 1  !< one evaluation at the predictor (the paper)
  integer(ik), parameter :: mode_iterate = 2    !< fixed-point iteration on one factor
  integer(ik), parameter :: mode_refactor = 3   !< iteration with refactoring

  ! torque laws
  integer(ik), parameter :: law_none = 0         !< no torque
  integer(ik), parameter :: law_constant = 1     !< T = p1
  integer(ik), parameter :: law_ramp = 2         !< T = p1 min(max((t - p2)/p3, 0), 1)
  integer(ik), parameter :: law_table = 3        !< linear interpolation of (time, torque), held at the ends
  integer(ik), parameter :: law_speed_power = 4  !< after t_s: T = p1 |w/p2|^p3 sign(w), w the member speed

  ! probes (output channels)
  integer(ik), parameter :: probe_displacement = 1    !< w . q
  integer(ik), parameter :: probe_velocity = 2        !< w . v
  integer(ik), parameter :: probe_acceleration = 3    !< w . a
  integer(ik), parameter :: probe_mesh_force = 4      !< s_m k_m delta_m of mesh index(1), compression > 0
  integer(ik), parameter :: probe_mesh_stiffness = 5  !< k_m in force of mesh index(1)
  integer(ik), parameter :: probe_drive_torque = 6    !< drive torque on the input member
  integer(ik), parameter :: probe_load_torque = 7     !< load torque against the output member

  ! error codes
  integer(ik), parameter :: nm_ok = 0               !< success
  integer(ik), parameter :: nm_err_argument = 1     !< a setting or size is out of range (bad = its index)
  integer(ik), parameter :: nm_err_definite = 2     !< Khat not positive definite (bad = DOF)
  integer(ik), parameter :: nm_err_mass = 3         !< M not positive definite (bad = DOF)
  integer(ik), parameter :: nm_err_not_finite = 4   !< state not finite or beyond the limit (bad = DOF)
  integer(ik), parameter :: nm_err_deflection = 5   !< a mesh deflection beyond the limit (bad = mesh)
  integer(ik), parameter :: nm_err_convergence = 6  !< equivalent-load iteration did not converge (bad = mesh)
  integer(ik), parameter :: nm_err_contact = 7      !< the tooth-contact table failed
  integer(ik), parameter :: nm_err_size = 8         !< the sample buffer is too small
  integer(ik), parameter :: nm_err_solve = 9        !< dpbtrs failed

  ! rparam layout
  integer, parameter :: rp_dt = 1, rp_beta = 2, rp_gamma = 3, rp_alpha_m = 4, rp_alpha_f = 5, &
                        rp_tolerance = 6, rp_refactor = 7, rp_deflection = 8, rp_speed = 9, &
                        rp_acceleration = 10
  ! iparam layout
  integer, parameter :: ip_mode = 1, ip_iterations = 2, ip_varying = 3, ip_separation = 4, &
                        ip_decimation = 5, ip_window = 6, ip_refactors = 7, &
                        ip_restart = 8  ! restart a at mesh-stiffness jumps (0/1)
  ! istate layout
  integer, parameter :: is_step = 1, is_load_on = 2, is_iterations = 3, is_refactors = 4, &
                        is_max_iterations = 5, is_window = 6, is_separated = 7, &
                        is_contact = 8, &  ! tooth-contact table evaluations
                        is_restarts = 9    ! acceleration restarts at stiffness jumps
  ! rstate layout
  integer, parameter :: rs_t_s = 1, rs_drive = 2, rs_load = 3

  real(dp), parameter :: pico = 1.0e-12_dp  !< deflection floor of the convergence scale [m]

contains

  !> y = y + scale A x for a symmetric band matrix A in lower storage.
  pure subroutine band_multiply(n, kd, ab, x, scale, y)
    integer(ik), intent(in) :: n                 !< order [-]
    integer(ik), intent(in) :: kd                !< subdiagonals [-]
    real(dp), intent(in) :: ab(kd + 1, n)        !< band of A [units of A]
    real(dp), intent(in) :: x(n)                 !< vector [units of x]
    real(dp), intent(in) :: scale                !< factor on A x [-]
    real(dp), intent(inout) :: y(n)              !< accumulator [units of A x]
    integer(ik) :: i, j
    real(dp) :: xj, column

    do j = 1, n
      xj = scale * x(j)
      column = ab(1, j) * x(j)
      do i = j + 1, min(n, j + kd)
        y(i) = y(i) + ab(i - j + 1, j) * xj
        column = column + ab(i - j + 1, j) * x(i)
      end do
      y(j) = y(j) + scale * column
    end do
  end subroutine band_multiply

  !> Torque of a law at time t and member speed (the paper's eq. 31 for law_speed_power).
  pure function torque_law(kind, param, n_table, table, t, speed, load_on) result(torque)
    integer(ik), intent(in) :: kind           !< law code [-]
    real(dp), intent(in) :: param(4)          !< law parameters [N m, s, s or rad/s, -]
    integer(ik), intent(in) :: n_table        !< samples of the law's table [-]
    real(dp), intent(in) :: table(2, n_table) !< (time [s], torque [N m]) samples, time increasing
    real(dp), intent(in) :: t                 !< time [s]
    real(dp), intent(in) :: speed             !< member speed [rad/s]
    logical, intent(in) :: load_on            !< t >= t_s (speed law only) [-]
    real(dp) :: torque                        !< torque [N m]
    integer(ik) :: lo, hi, mid
    real(dp) :: w

    torque = 0.0_dp
    select case (kind)
    case (law_constant)
      torque = param(1)
    case (law_ramp)
      torque = param(1) * min(max((t - param(2)) / param(3), 0.0_dp), 1.0_dp)
    case (law_table)
      if (n_table < 1) return
      if (t <= table(1, 1)) then
        torque = table(2, 1)
      else if (t >= table(1, n_table)) then
        torque = table(2, n_table)
      else
        lo = 1
        hi = n_table
        do while (hi - lo > 1)
          mid = (lo + hi) / 2
          if (table(1, mid) <= t) then
            lo = mid
          else
            hi = mid
          end if
        end do
        w = (t - table(1, lo)) / (table(1, hi) - table(1, lo))
        torque = (1.0_dp - w) * table(2, lo) + w * table(2, hi)
      end if
    case (law_speed_power)
      if (load_on) torque = sign(param(1) * abs(speed / param(2))**param(3), speed)
    end select
  end function torque_law

  !> Khat = K0 + (1 - alpha_m) s M + gamma / (beta dt) C, s = 1 / ((1 - alpha_f) beta dt^2).
  pure subroutine effective_band(n, kd, mass_band, damping_band, stiffness_band, rparam, khat)
    integer(ik), intent(in) :: n                        !< DOFs [-]
    integer(ik), intent(in) :: kd                       !< subdiagonals [-]
    real(dp), intent(in) :: mass_band(kd + 1, n)        !< M [kg]
    real(dp), intent(in) :: damping_band(kd + 1, n)     !< C [N s/m]
    real(dp), intent(in) :: stiffness_band(kd + 1, n)   !< K0 [N/m]
    real(dp), intent(in) :: rparam(10)                  !< settings [SI]
    real(dp), intent(out) :: khat(kd + 1, n)            !< Khat [N/m]
    real(dp) :: dt, beta

    dt = rparam(rp_dt)
    beta = rparam(rp_beta)
    khat = stiffness_band &
           + (1.0_dp - rparam(rp_alpha_m)) / ((1.0_dp - rparam(rp_alpha_f)) * beta * dt * dt) * mass_band &
           + rparam(rp_gamma) / (beta * dt) * damping_band
  end subroutine effective_band

  !> Check sizes, indices and settings once per call; bad names the first wrong entry
  !> (rparam index, iparam index + 100, or a law-table column + 1000).
  pure subroutine check_settings(n, kd, rparam, iparam, n_mesh, mesh_ptr, n_mesh_nz, mesh_index, &
                                 angle_ptr, n_angle_nz, angle_index, contact_sign, load_ptr, &
                                 n_load_nz, load_index, law_kind, law_param, law_start, law_size, &
                                 n_table, law_table, bad, ierr)
    integer(ik), intent(in) :: n, kd                     !< DOFs, subdiagonals [-]
    real(dp), intent(in) :: rparam(10)                   !< real settings [SI]
    integer(ik), intent(in) :: iparam(8)                 !< integer settings [-]
    integer(ik), intent(in) :: n_mesh                    !< meshes [-]
    integer(ik), intent(in) :: mesh_ptr(n_mesh + 1)      !< b pointers [-]
    integer(ik), intent(in) :: n_mesh_nz                 !< b entries [-]
    integer(ik), intent(in) :: mesh_index(n_mesh_nz)     !< b DOFs [-]
    integer(ik), intent(in) :: angle_ptr(n_mesh + 1)     !< angle pointers [-]
    integer(ik), intent(in) :: n_angle_nz                !< angle entries [-]
    integer(ik), intent(in) :: angle_index(n_angle_nz)   !< angle DOFs [-]
    integer(ik), intent(in) :: contact_sign(n_mesh)      !< contact signs [-]
    integer(ik), intent(in) :: load_ptr(3)               !< member pointers [-]
    integer(ik), intent(in) :: n_load_nz                 !< member entries [-]
    integer(ik), intent(in) :: load_index(n_load_nz)     !< member DOFs [-]
    integer(ik), intent(in) :: law_kind(2)               !< law codes [-]
    real(dp), intent(in) :: law_param(4, 2)              !< law parameters [SI]
    integer(ik), intent(in) :: law_start(2), law_size(2) !< law tables [-]
    integer(ik), intent(in) :: n_table                   !< table columns [-]
    real(dp), intent(in) :: law_table(2, n_table)        !< law tables [s, N m]
    integer(ik), intent(out) :: bad                      !< first wrong entry [-]
    integer(ik), intent(out) :: ierr                     !< error code
    integer(ik) :: l, c

    ierr = nm_err_argument
    bad = 0
    if (n < 1 .or. kd < 0 .or. kd > n - 1 .or. n_mesh < 0) return
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
    if (iparam(ip_decimation) < 1) then
      bad = 100 + ip_decimation
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
    if (mesh_ptr(1) /= 0 .or. mesh_ptr(n_mesh + 1) > n_mesh_nz .or. angle_ptr(1) /= 0 .or. &
        angle_ptr(n_mesh + 1) > n_angle_nz .or. load_ptr(1) /= 0 .or. load_ptr(3) > n_load_nz) return
    if (any(mesh_index(1:mesh_ptr(n_mesh + 1)) < 1 .or. mesh_index(1:mesh_ptr(n_mesh + 1)) > n)) return
    if (any(angle_index(1:angle_ptr(n_mesh + 1)) < 1 .or. angle_index(1:angle_ptr(n_mesh + 1)) > n)) return
    if (any(load_index(1:load_ptr(3)) < 1 .or. load_index(1:load_ptr(3)) > n)) return
    if (any(abs(contact_sign) /= 1)) return
    do l = 1, 2
      if (law_kind(l) < law_none .or. law_kind(l) > law_speed_power) return
      if (law_kind(l) == law_ramp .and. .not. (law_param(3, l) > 0.0_dp)) return
      if (law_kind(l) == law_speed_power .and. .not. (law_param(2, l) > 0.0_dp)) return
      if (law_start(l) < 0 .or. law_size(l) < 0 .or. law_start(l) + law_size(l) > n_table) return
      do c = law_start(l) + 2, law_start(l) + law_size(l)
        if (.not. (law_table(1, c) > law_table(1, c - 1))) then
          bad = 1000 + c
          return
        end if
      end do
    end do
    ierr = nm_ok
  end subroutine check_settings

  !> w . x for sparse vector row of a packed set.
  pure real(dp) function sparse_dot(row, ptr, index, value, x)
    integer(ik), intent(in) :: row         !< row (1-based) [-]
    integer(ik), intent(in) :: ptr(:)      !< row pointers [-]
    integer(ik), intent(in) :: index(:)    !< column of each entry [-]
    real(dp), intent(in) :: value(:)       !< entries [-]
    real(dp), intent(in) :: x(:)           !< vector [-]
    integer(ik) :: k
    sparse_dot = 0.0_dp
    do k = ptr(row) + 1, ptr(row + 1)
      sparse_dot = sparse_dot + value(k) * x(index(k))
    end do
  end function sparse_dot

  !> y = y + s w for a sparse vector row of a packed set.
  pure subroutine add_sparse(row, s, ptr, index, value, y)
    integer(ik), intent(in) :: row         !< row (1-based) [-]
    real(dp), intent(in) :: s              !< scale [-]
    integer(ik), intent(in) :: ptr(:)      !< row pointers [-]
    integer(ik), intent(in) :: index(:)    !< column of each entry [-]
    real(dp), intent(in) :: value(:)       !< entries [-]
    real(dp), intent(inout) :: y(:)        !< accumulator [-]
    integer(ik) :: k
    do k = ptr(row) + 1, ptr(row + 1)
      y(index(k)) = y(index(k)) + s * value(k)
    end do
  end subroutine add_sparse

  !> Speed of member 1 (input) or 2 (output) [rad/s].
  pure real(dp) function member_speed(which, ptr, index, value, x)
    integer, intent(in) :: which           !< 1 input, 2 output [-]
    integer(ik), intent(in) :: ptr(3)      !< member pointers [-]
    integer(ik), intent(in) :: index(:)    !< DOFs [-]
    real(dp), intent(in) :: value(:)       !< rotation per DOF [-]
    real(dp), intent(in) :: x(:)           !< velocities [rad/s]
    member_speed = sparse_dot(int(which, ik), ptr, index, value, x)
  end function member_speed

  !> y = y + torque w_member (generalized force of a torque on a member).
  pure subroutine add_member(which, torque, ptr, index, value, y)
    integer, intent(in) :: which           !< 1 input, 2 output [-]
    real(dp), intent(in) :: torque         !< torque [N m]
    integer(ik), intent(in) :: ptr(3)      !< member pointers [-]
    integer(ik), intent(in) :: index(:)    !< DOFs [-]
    real(dp), intent(in) :: value(:)       !< rotation per DOF [-]
    real(dp), intent(inout) :: y(:)        !< generalized forces [N, N m]
    call add_sparse(int(which, ik), torque, ptr, index, value, y)
  end subroutine add_member

  !> The first DOF whose entry of x or y is not finite, else the largest |x|.
  pure integer(ik) function first_bad(x, y)
    real(dp), intent(in) :: x(:), y(:)     !< state vectors [-]
    integer(ik) :: i
    do i = 1, size(x, kind=ik)
      if (.not. (abs(x(i)) <= huge(1.0_dp) .and. abs(y(i)) <= huge(1.0_dp))) then
        first_bad = i
        return
      end if
    end do
    first_bad = int(maxloc(abs(x), 1), ik)
  end function first_bad
end module newmark_support
