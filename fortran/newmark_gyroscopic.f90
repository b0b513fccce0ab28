!> Rotor terms of the Newmark kernel (module newmark): the gyroscopic force of spinning
!> shafts and discs, -Omega(t) G v, and unbalance forces at a speed profile.
!>
!> G is skew-symmetric (G^T = -G) per rad/s of a reference speed Omega_ref; every
!> shaft's elements and discs enter it scaled by their shaft's speed ratio, so one
!> reference speed turns them all.  It is kept as its strictly upper entries only,
!> G(i, j) = g and G(j, i) = -g, over the DOFs it couples (the lateral translations
!> and tilts of the spinning nodes): a product costs two multiply-adds per entry, and
!> v^T G v = sum g (v_i v_j - v_j v_i) is zero term by term, so the gyroscopic force
!> does no work on the velocity it is evaluated with.
!>
!> Omega_ref comes from one of two sources:
!> * a prescribed speed profile (time, speed) samples, linear between the samples and
!>   held beyond them; the shaft angle is its exact integral (piecewise quadratic);
!> * the run's own rotation, Omega_ref = w . v with w a sparse row over the DOFs
!>   (a drivetrain's rotor rotation): the force then depends on v through Omega too.
!>
!> Unbalance u at the DOFs (x_u, y_u) of a disc node, m e_u [kg m], angle phi_u [rad]
!> and speed ratio r_u, on a shaft turning by psi = r_u phi_ref(t) + phi_u: the
!> inertial force of the eccentric mass,
!>     F_x = m e (psi'^2 cos psi + psi'' sin psi),  F_y = m e (psi'^2 sin psi - psi'' cos psi),
!> with psi' = r_u Omega_ref and psi'' = r_u dOmega_ref/dt (prescribed profile only).
!>
!> Time integration (module newmark): both forces are loads of the step equation at
!> t_n+1 (with the alpha_f share at t_n), and the gyroscopic one is evaluated at the
!> iterate's velocity v_n+1 = vt + gamma dt a within the equivalent-load iteration, on
!> the same factor of Khat: the iteration contracts by about gamma dt |Omega| times the
!> largest eigenvalue of M^-1 G restricted to the spinning DOFs (2 for a thin disc),
!> i.e. h Omega << 1.  With average acceleration at a constant speed the converged step
!> is energy-neutral: the trapezoidal work of -Omega G v over the step is
!> -(dt / 4) (Omega_n+1 - Omega_n) v_n^T G v_n+1, zero when the speed holds.
module newmark_gyroscopic
  use kinds, only: dp, ik
  use band_lapack, only: band_cholesky_factor
  implicit none
  private

  public :: rotor_terms, attach_rotor_terms, rotor_speed, add_rotor_load, add_gyroscopic_force
  public :: speed_profile, speed_rotation
  public :: rt_ok, rt_err_argument, rt_err_mass

  integer(ik), parameter :: speed_profile = 1   !< Omega_ref from (time, speed) samples
  integer(ik), parameter :: speed_rotation = 2  !< Omega_ref = w . v (the run's rotation)

  integer(ik), parameter :: rt_ok = 0            !< success
  integer(ik), parameter :: rt_err_argument = 1  !< a size, index or value is out of range
  integer(ik), parameter :: rt_err_mass = 2      !< M not positive definite (dense path factor)

  !> The rotor terms of one transient problem; active = .false. costs nothing.
  type :: rotor_terms
    logical :: active = .false.                     !< any gyroscopic entry or unbalance [-]
    integer(ik) :: source = speed_profile           !< speed_profile or speed_rotation [-]
    integer(ik), allocatable :: row(:)              !< DOF i of each entry G(i, j) (1-based) [-]
    integer(ik), allocatable :: column(:)           !< DOF j of each entry [-]
    real(dp), allocatable :: value(:)               !< G(i, j) = -G(j, i) per unit Omega_ref [kg m^2, kg m]
    real(dp), allocatable :: profile(:, :)          !< (3, samples) time [s], speed [rad/s], angle [rad]
    integer(ik), allocatable :: speed_index(:)      !< DOFs of w (speed_rotation) [-]
    real(dp), allocatable :: speed_value(:)         !< w entries [rad/rad per DOF unit]
    integer(ik), allocatable :: unbalance_dof(:, :) !< (2, unbalances) DOFs x, y [-]
    real(dp), allocatable :: unbalance(:, :)        !< (3, unbalances) m e [kg m], phi [rad], ratio [-]
    real(dp), allocatable :: mass_factor(:, :)      !< (kd + 1, n) Cholesky factor of M (dense path) [kg]
  end type rotor_terms

contains

  !> Check the rotor terms of a problem of n DOFs and complete them: the angle of each
  !> profile sample, and, with dense = .true., the band Cholesky factor of M the dense
  !> path applies Khat^-1 with.  bad: the first wrong entry (1 entries, 2 profile,
  !> 3 speed row, 4 unbalances, 5 M's pivot DOF offset by 10).
  subroutine attach_rotor_terms(terms, n, kd, mass_band, dense, bad, ierr)
    type(rotor_terms), intent(inout) :: terms   !< the terms to check and complete
    integer(ik), intent(in) :: n                !< DOFs [-]
    integer(ik), intent(in) :: kd               !< band subdiagonals of mass_band [-]
    real(dp), intent(in) :: mass_band(:, :)     !< (kd + 1, n) M, used on the dense path only [kg, kg m^2]
    logical, intent(in) :: dense                !< the problem is on the dense path [-]
    integer(ik), intent(out) :: bad             !< first wrong entry [-]
    integer(ik), intent(out) :: ierr            !< error code (rt_ok = 0)
    integer(ik) :: k, samples, info

    ierr = rt_err_argument
    bad = 1
    if (.not. (allocated(terms%row) .and. allocated(terms%column) .and. allocated(terms%value))) return
    if (size(terms%column) /= size(terms%row) .or. size(terms%value) /= size(terms%row)) return
    if (any(terms%row < 1 .or. terms%row > n .or. terms%column < 1 .or. terms%column > n)) return
    if (any(terms%row == terms%column)) return
    if (.not. all(abs(terms%value) <= huge(1.0_dp))) return
    bad = 2
    if (terms%source /= speed_profile .and. terms%source /= speed_rotation) return
    if (.not. allocated(terms%profile)) return
    samples = int(size(terms%profile, 2), ik)
    if (size(terms%profile, 1) /= 3 .or. samples < 1) return
    if (.not. all(abs(terms%profile(1:2, :)) <= huge(1.0_dp))) return
    do k = 2, samples
      if (.not. (terms%profile(1, k) > terms%profile(1, k - 1))) return
    end do
    terms%profile(3, 1) = 0.0_dp  ! the angle from the first sample on, exact for linear speed
    do k = 2, samples
      terms%profile(3, k) = terms%profile(3, k - 1) + 0.5_dp * (terms%profile(1, k) - &
                            terms%profile(1, k - 1)) * (terms%profile(2, k) + terms%profile(2, k - 1))
    end do
    bad = 3
    if (.not. (allocated(terms%speed_index) .and. allocated(terms%speed_value))) return
    if (size(terms%speed_value) /= size(terms%speed_index)) return
    if (any(terms%speed_index < 1 .or. terms%speed_index > n)) return
    if (.not. all(abs(terms%speed_value) <= huge(1.0_dp))) return
    bad = 4
    if (.not. (allocated(terms%unbalance_dof) .and. allocated(terms%unbalance))) return
    if (size(terms%unbalance_dof, 1) /= 2 .or. size(terms%unbalance, 1) /= 3) return
    if (size(terms%unbalance_dof, 2) /= size(terms%unbalance, 2)) return
    if (any(terms%unbalance_dof < 1 .or. terms%unbalance_dof > n)) return
    if (.not. all(abs(terms%unbalance) <= huge(1.0_dp))) return
    ! an unbalance needs the angle and the acceleration of its shaft: a prescribed profile
    if (size(terms%unbalance, 2) > 0 .and. terms%source /= speed_profile) return
    terms%active = size(terms%value) > 0 .or. size(terms%unbalance, 2) > 0
    bad = 0
    ierr = rt_ok
    if (.not. (dense .and. terms%active)) return
    if (size(mass_band, 1) /= kd + 1 .or. size(mass_band, 2) /= n) then
      ierr = rt_err_argument
      bad = 5
      return
    end if
    allocate (terms%mass_factor(kd + 1, n))
    terms%mass_factor = mass_band
    call band_cholesky_factor(n, kd, terms%mass_factor, info)
    if (info /= 0) then
      ierr = rt_err_mass
      bad = 10 + max(info, 0_ik)
    end if
  end subroutine attach_rotor_terms

  !> The reference speed at time t and velocities v, its rate and the angle turned.
  pure subroutine rotor_speed(terms, t, v, speed, rate, angle)
    type(rotor_terms), intent(in) :: terms  !< checked terms
    real(dp), intent(in) :: t               !< time [s]
    real(dp), intent(in) :: v(:)            !< velocities [m/s, rad/s]
    real(dp), intent(out) :: speed          !< Omega_ref [rad/s]
    real(dp), intent(out) :: rate           !< dOmega_ref/dt [rad/s^2] (profile; 0 beyond its ends)
    real(dp), intent(out) :: angle          !< integral of Omega_ref from the first sample [rad]
    integer(ik) :: k, samples, low, high
    real(dp) :: tau

    rate = 0.0_dp
    angle = 0.0_dp
    if (terms%source == speed_rotation) then
      speed = sum(terms%speed_value * v(terms%speed_index))
      return
    end if
    samples = int(size(terms%profile, 2), ik)
    if (t <= terms%profile(1, 1)) then
      speed = terms%profile(2, 1)
      angle = speed * (t - terms%profile(1, 1))
      return
    end if
    if (t >= terms%profile(1, samples)) then
      speed = terms%profile(2, samples)
      angle = terms%profile(3, samples) + speed * (t - terms%profile(1, samples))
      return
    end if
    low = 1  ! bisection: the interval [t_k, t_k+1) holding t
    high = samples
    do while (high - low > 1)
      k = (low + high) / 2
      if (terms%profile(1, k) <= t) then
        low = k
      else
        high = k
      end if
    end do
    tau = t - terms%profile(1, low)
    rate = (terms%profile(2, high) - terms%profile(2, low)) / &
           (terms%profile(1, high) - terms%profile(1, low))
    speed = terms%profile(2, low) + rate * tau
    angle = terms%profile(3, low) + tau * (terms%profile(2, low) + 0.5_dp * rate * tau)
  end subroutine rotor_speed

  !> f = f - scale speed G v (the gyroscopic force at the reference speed).
  pure subroutine add_gyroscopic_force(terms, speed, v, scale, f)
    type(rotor_terms), intent(in) :: terms  !< checked terms
    real(dp), intent(in) :: speed           !< Omega_ref [rad/s]
    real(dp), intent(in) :: v(:)            !< velocities [m/s, rad/s]
    real(dp), intent(in) :: scale           !< factor on the force [-]
    real(dp), intent(inout) :: f(:)         !< accumulator [N, N m]
    integer(ik) :: e, i, j
    real(dp) :: s

    s = scale * speed
    if (s == 0.0_dp) return
    do e = 1, int(size(terms%value), ik)
      i = terms%row(e)
      j = terms%column(e)
      f(i) = f(i) - s * terms%value(e) * v(j)
      f(j) = f(j) + s * terms%value(e) * v(i)
    end do
  end subroutine add_gyroscopic_force

  !> f = f + scale (-Omega_ref G v + unbalance forces) at time t and velocities v, or
  !> the unbalance forces alone (gyroscopic = .false.).
  pure subroutine add_rotor_load(terms, t, v, scale, gyroscopic, f)
    type(rotor_terms), intent(in) :: terms  !< checked terms
    real(dp), intent(in) :: t               !< time [s]
    real(dp), intent(in) :: v(:)            !< velocities [m/s, rad/s]
    real(dp), intent(in) :: scale           !< factor on the load [-]
    logical, intent(in) :: gyroscopic       !< include the gyroscopic force [-]
    real(dp), intent(inout) :: f(:)         !< accumulator [N, N m]
    real(dp) :: speed, rate, angle, psi, psi_dot, psi_ddot, me
    integer(ik) :: u

    call rotor_speed(terms, t, v, speed, rate, angle)
    if (gyroscopic) call add_gyroscopic_force(terms, speed, v, scale, f)
    do u = 1, int(size(terms%unbalance, 2), ik)
      me = scale * terms%unbalance(1, u)
      psi = terms%unbalance(3, u) * angle + terms%unbalance(2, u)
      psi_dot = terms%unbalance(3, u) * speed
      psi_ddot = terms%unbalance(3, u) * rate
      f(terms%unbalance_dof(1, u)) = f(terms%unbalance_dof(1, u)) + &
                                     me * (psi_dot**2 * cos(psi) + psi_ddot * sin(psi))
      f(terms%unbalance_dof(2, u)) = f(terms%unbalance_dof(2, u)) + &
                                     me * (psi_dot**2 * sin(psi) - psi_ddot * cos(psi))
    end do
  end subroutine add_rotor_load
end module newmark_gyroscopic
