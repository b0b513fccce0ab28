!> Building blocks of the Newmark kernel (module newmark): option and error codes,
!> the layouts of the settings and state arrays, symmetric band products, packed
!> sparse vectors (meshes, members, probes) and the drive and load torque laws.
module newmark_support
  use kinds, only: dp, ik
  implicit none
  private

  public :: sparse_rows, torque_laws
  public :: band_multiply, effective_band, torque_law, law_torque, check_laws
  public :: sparse_dot, sparse_products, add_sparse, member_speed, add_member, rows_fit, first_bad
  public :: mode_linear, mode_predictor, mode_iterate, mode_refactor
  public :: law_none, law_constant, law_ramp, law_table, law_speed_power
  public :: probe_displacement, probe_velocity, probe_acceleration, probe_mesh_force, &
            probe_mesh_stiffness, probe_drive_torque, probe_load_torque
  public :: nm_ok, nm_err_argument, nm_err_definite, nm_err_mass, nm_err_not_finite, &
            nm_err_deflection, nm_err_convergence, nm_err_contact, nm_err_size, nm_err_solve, &
            nm_err_handle, nm_err_full, nm_err_unavailable
  public :: rp_dt, rp_beta, rp_gamma, rp_alpha_m, rp_alpha_f, rp_tolerance, rp_refactor, &
            rp_deflection, rp_speed, rp_acceleration
  public :: ip_mode, ip_iterations, ip_varying, ip_separation, ip_refactors, ip_restart, ip_solver
  public :: solver_banded, solver_dense, solver_sparse, solver_refined
  public :: n_rparam, n_iparam, n_rstate, n_istate
  public :: is_step, is_load_on, is_iterations, is_refactors, is_max_iterations, is_window, &
            is_separated, is_contact, is_restarts, is_coast
  public :: rs_t_s, rs_drive, rs_load, pico

  ! equivalent-load modes (iparam(ip_mode))
  integer(ik), parameter :: mode_linear = 0     !< no mesh terms: K0 only
  integer(ik), parameter :: mode_predictor = 1  !< one evaluation at the predictor (the paper)
  integer(ik), parameter :: mode_iterate = 2    !< fixed-point iteration on one factor
  integer(ik), parameter :: mode_refactor = 3   !< iteration with refactoring

  ! linear solvers of Khat a = rhs (iparam(ip_solver))
  integer(ik), parameter :: solver_banded = 0   !< banded Cholesky factor, dpbtrs per solve
  integer(ik), parameter :: solver_dense = 1    !< dense Khat^-1 products, dgemv (module newmark_dense)
  integer(ik), parameter :: solver_sparse = 2   !< CHOLMOD factor of Khat (module newmark_sparse)
  integer(ik), parameter :: solver_refined = 3  !< dense path with one refinement step (module newmark_dense)

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
  integer(ik), parameter :: probe_mesh_force = 4      !< flank force F (spring + damper) of mesh index(1): drive > 0, coast < 0
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
  integer(ik), parameter :: nm_err_handle = 10      !< not the handle of a live problem or contact table
  integer(ik), parameter :: nm_err_full = 11        !< the problem registry is full
  integer(ik), parameter :: nm_err_unavailable = 12 !< the sparse path was built without CHOLMOD

  ! rparam layout
  integer, parameter :: rp_dt = 1, rp_beta = 2, rp_gamma = 3, rp_alpha_m = 4, rp_alpha_f = 5, &
                        rp_tolerance = 6, rp_refactor = 7, rp_deflection = 8, rp_speed = 9, &
                        rp_acceleration = 10
  ! iparam layout (a run's decimation and averaging window are arguments of its advance)
  integer, parameter :: ip_mode = 1, ip_iterations = 2, ip_varying = 3, ip_separation = 4, &
                        ip_refactors = 5, &
                        ip_restart = 6, & ! restart a at mesh-stiffness jumps (0/1)
                        ip_solver = 7     ! solver_banded, solver_dense, solver_sparse or solver_refined
  ! istate layout
  integer, parameter :: is_step = 1, is_load_on = 2, is_iterations = 3, is_refactors = 4, &
                        is_max_iterations = 5, is_window = 6, is_separated = 7, &
                        is_contact = 8, &  ! tooth-contact table evaluations
                        is_restarts = 9, & ! acceleration restarts at stiffness jumps
                        is_coast = 10      ! mesh-steps with the coast flanks in contact
  ! rstate layout
  integer, parameter :: rs_t_s = 1, rs_drive = 2, rs_load = 3
  ! sizes of the four arrays above
  integer(ik), parameter :: n_rparam = 10, n_iparam = 7, n_istate = 10, n_rstate = 3

  real(dp), parameter :: pico = 1.0e-12_dp  !< deflection floor of the convergence scale [m]

  !> Rows of sparse vectors over the DOFs, packed: row r holds value(ptr(r)+1 : ptr(r+1))
  !> at the DOFs index(ptr(r)+1 : ptr(r+1)).
  type :: sparse_rows
    integer(ik), allocatable :: ptr(:)    !< (rows + 1) row pointers, ptr(1) = 0 [-]
    integer(ik), allocatable :: index(:)  !< DOF (1-based) of each entry; a mesh for mesh probes [-]
    real(dp), allocatable :: value(:)     !< entries [row unit per DOF unit]
  end type sparse_rows

  !> The drive law (1) and the load law (2): codes, parameters, (time, torque) tables.
  type :: torque_laws
    integer(ik) :: code(2) = law_none          !< law codes [-]
    real(dp) :: param(4, 2) = 0.0_dp           !< law parameters [N m, s, s or rad/s, -]
    integer(ik) :: table_start(2) = 0          !< offsets of each law's samples in table [-]
    integer(ik) :: table_size(2) = 0           !< samples of each law [-]
    real(dp), allocatable :: table(:, :)       !< (2, columns) time [s], torque [N m]
  end type torque_laws

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
    real(dp), intent(in) :: rparam(n_rparam)            !< settings [SI]
    real(dp), intent(out) :: khat(kd + 1, n)            !< Khat [N/m]
    real(dp) :: dt, beta

    dt = rparam(rp_dt)
    beta = rparam(rp_beta)
    khat = stiffness_band &
           + (1.0_dp - rparam(rp_alpha_m)) / ((1.0_dp - rparam(rp_alpha_f)) * beta * dt * dt) * mass_band &
           + rparam(rp_gamma) / (beta * dt) * damping_band
  end subroutine effective_band

  !> w . x for row row of a packed set of sparse vectors.
  pure real(dp) function sparse_dot(rows, row, x)
    type(sparse_rows), intent(in) :: rows  !< the packed set
    integer(ik), intent(in) :: row         !< row (1-based) [-]
    real(dp), intent(in) :: x(:)           !< vector over the DOFs [DOF units]
    integer(ik) :: k
    sparse_dot = 0.0_dp
    do k = rows%ptr(row) + 1, rows%ptr(row + 1)
      sparse_dot = sparse_dot + rows%value(k) * x(rows%index(k))
    end do
  end function sparse_dot

  !> y(r) = w_r . x for every row r of a packed set of sparse vectors (one call for all
  !> rows: the time loop takes the meshes' deflections and angles this way).
  pure subroutine sparse_products(rows, x, y)
    type(sparse_rows), intent(in) :: rows          !< the packed set
    real(dp), intent(in), contiguous :: x(:)       !< vector over the DOFs [DOF units]
    real(dp), intent(out), contiguous :: y(:)      !< one product per row [row units]
    integer(ik) :: r, k
    real(dp) :: total
    do r = 1, size(y, kind=ik)
      total = 0.0_dp
      do k = rows%ptr(r) + 1, rows%ptr(r + 1)
        total = total + rows%value(k) * x(rows%index(k))
      end do
      y(r) = total
    end do
  end subroutine sparse_products

  !> y = y + s w for row row of a packed set of sparse vectors.
  pure subroutine add_sparse(rows, row, s, y)
    type(sparse_rows), intent(in) :: rows  !< the packed set
    integer(ik), intent(in) :: row         !< row (1-based) [-]
    real(dp), intent(in) :: s              !< scale [units of y per row unit]
    real(dp), intent(inout) :: y(:)        !< accumulator over the DOFs [units of y]
    integer(ik) :: k
    do k = rows%ptr(row) + 1, rows%ptr(row + 1)
      y(rows%index(k)) = y(rows%index(k)) + s * rows%value(k)
    end do
  end subroutine add_sparse

  !> Speed of member 1 (input) or 2 (output) [rad/s].
  pure real(dp) function member_speed(members, which, x)
    type(sparse_rows), intent(in) :: members  !< input and output member rotations per DOF
    integer, intent(in) :: which              !< 1 input, 2 output [-]
    real(dp), intent(in) :: x(:)              !< velocities [m/s, rad/s]
    member_speed = sparse_dot(members, int(which, ik), x)
  end function member_speed

  !> y = y + torque w_member (generalized force of a torque on a member).
  pure subroutine add_member(members, which, torque, y)
    type(sparse_rows), intent(in) :: members  !< input and output member rotations per DOF
    integer, intent(in) :: which              !< 1 input, 2 output [-]
    real(dp), intent(in) :: torque            !< torque [N m]
    real(dp), intent(inout) :: y(:)           !< generalized forces [N, N m]
    call add_sparse(members, int(which, ik), torque, y)
  end subroutine add_member

  !> Whether rows is a packed set of n_rows rows over DOFs 1 .. n (n = 0: any index).
  pure logical function rows_fit(rows, n_rows, n)
    type(sparse_rows), intent(in) :: rows  !< the packed set
    integer(ik), intent(in) :: n_rows      !< rows it must hold [-]
    integer(ik), intent(in) :: n           !< DOFs the indices lie in, 0 for no check [-]
    integer(ik) :: last

    rows_fit = .false.
    if (.not. (allocated(rows%ptr) .and. allocated(rows%index) .and. allocated(rows%value))) return
    if (size(rows%ptr) /= n_rows + 1 .or. size(rows%value) /= size(rows%index)) return
    if (rows%ptr(1) /= 0 .or. rows%ptr(n_rows + 1) > size(rows%index)) return
    last = rows%ptr(n_rows + 1)
    if (n > 0) then
      if (any(rows%index(1:last) < 1 .or. rows%index(1:last) > n)) return
    end if
    rows_fit = .true.
  end function rows_fit

  !> Torque of law which (1 drive, 2 load) of a pair of laws [N m].
  pure real(dp) function law_torque(laws, which, t, speed, load_on)
    type(torque_laws), intent(in) :: laws  !< the drive and load laws
    integer, intent(in) :: which           !< 1 drive, 2 load [-]
    real(dp), intent(in) :: t              !< time [s]
    real(dp), intent(in) :: speed          !< member speed [rad/s]
    logical, intent(in) :: load_on         !< t >= t_s [-]
    law_torque = torque_law(laws%code(which), laws%param(:, which), laws%table_size(which), &
                            laws%table(:, laws%table_start(which) + 1:laws%table_start(which) &
                                                                       + laws%table_size(which)), &
                            t, speed, load_on)
  end function law_torque

  !> Check that the laws are known codes with valid parameters and increasing table
  !> times; bad names a table column + 1000 that is out of order, else 0.
  pure subroutine check_laws(laws, bad, ierr)
    type(torque_laws), intent(in) :: laws  !< the drive and load laws
    integer(ik), intent(out) :: bad        !< first table column out of order + 1000, else 0 [-]
    integer(ik), intent(out) :: ierr       !< error code (0 = ok)
    integer(ik) :: l, c

    ierr = nm_err_argument
    bad = 0
    if (.not. allocated(laws%table)) return
    if (size(laws%table, 1) /= 2) return
    do l = 1, 2
      if (laws%code(l) < law_none .or. laws%code(l) > law_speed_power) return
      if (laws%code(l) == law_ramp .and. .not. (laws%param(3, l) > 0.0_dp)) return
      if (laws%code(l) == law_speed_power .and. .not. (laws%param(2, l) > 0.0_dp)) return
      if (laws%table_start(l) < 0 .or. laws%table_size(l) < 0 .or. &
          laws%table_start(l) + laws%table_size(l) > size(laws%table, 2)) return
      do c = laws%table_start(l) + 2, laws%table_start(l) + laws%table_size(l)
        if (.not. (laws%table(1, c) > laws%table(1, c - 1))) then
          bad = 1000 + c
          return
        end if
      end do
    end do
    ierr = nm_ok
  end subroutine check_laws

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
