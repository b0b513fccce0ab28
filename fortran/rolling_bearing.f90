!> Rolling bearings as nonlinear elements of the Newmark kernel (docs/bearings.md).
!>
!> A bearing joins an inner and an outer ring.  Four sparse rows over the DOFs give, at
!> a state q, the inner ring's displacement relative to the outer one in the bearing's
!> plane (x, y) and the two rings' rotation angles (theta_i, theta_o), all in the frame
!> the bearing's springs are written in (the housing, or a carrier for planet
!> bearings).  The cage rolls without slip: its angle is the fixed combination
!> theta_c = ((1 - gamma) theta_i + (1 + gamma) theta_o) / 2 (gamma = d cos(alpha) / D),
!> and element j (0-based) of Z sits at psi_j = theta_c + 2 pi j / Z.  It deflects by
!>
!>     delta_j = (x cos psi_j + y sin psi_j - P_d / 2) cos(alpha) - h_j
!>
!> and carries Q_j = K_n <delta_j>_+^n + c_c d(delta_j)/dt (Hertz, n = 3/2 for balls,
!> 10/9 for rollers; c_c the lubricated contact's viscous damping, acting only while
!> delta_j > 0, with the approach rate d(delta_j)/dt = (xdot cos psi_j + ydot sin psi_j)
!> cos(alpha) of the rings' relative velocity: the rolling past and the defects' edges
!> move the contact, they do not squeeze the film, and are left out of the rate).
!> h_j is what defects take off the contact: a spall of angular width w and depth h on
!> a ring at angle phi (it turns with its ring, at phi + theta_ring) takes h off every
!> element within w / 2 of it; waviness of order N and amplitude A on a ring adds
!> A cos(N (psi_j - theta_ring - phi)) to delta_j.  The elements push the inner ring
!> with -F, F = sum_j Q_j cos(alpha) (cos psi_j, sin psi_j), and the outer ring with +F.
!>
!> The kernel keeps a linear spring k_r (the bearing's radial stiffness, in K0) on the
!> same two rows, so the bearing enters the equation of motion as the equivalent load
!> N = w_x (F_x - k_r x) + w_y (F_y - k_r y): the Hertz law replaces the spring, and the
!> fixed-point iteration of the kernel (module newmark) converges it with the meshes'
!> loads.  Everything here is a function of the state: no history, nothing to rebase
!> but the ring angles (the caller keeps them out of any rigid-rotation rebasing).
!> Element inertia and slip are not modelled.
module rolling_bearing
  use kinds, only: dp, ik
  use newmark_support, only: sparse_rows, sparse_products, add_sparse, rows_fit
  implicit none
  private

  public :: bearing_set, bearing_rows, bearing_loads, add_bearing_loads, add_state_bearing_loads, &
            check_bearing_set
  public :: bp_constant, bp_exponent, bp_clearance, bp_cos_alpha, bp_cage_inner, &
            bp_cage_outer, bp_spring, bp_damping, n_bearing_param, defect_spall, defect_waviness, &
            ring_outer, ring_inner, bearing_rows_per

  integer(ik), parameter :: bp_constant = 1      !< K_n [N/m^n]
  integer(ik), parameter :: bp_exponent = 2      !< n [-]
  integer(ik), parameter :: bp_clearance = 3     !< P_d, diametral clearance (< 0 preload) [m]
  integer(ik), parameter :: bp_cos_alpha = 4     !< cos(alpha) [-]
  integer(ik), parameter :: bp_cage_inner = 5    !< (1 - gamma) / 2, cage angle per inner-ring angle [-]
  integer(ik), parameter :: bp_cage_outer = 6    !< (1 + gamma) / 2, per outer-ring angle [-]
  integer(ik), parameter :: bp_spring = 7        !< k_r, the radial spring inside K0 [N/m]
  integer(ik), parameter :: bp_damping = 8       !< c_c, viscous damping per loaded contact [N s/m]
  integer(ik), parameter :: n_bearing_param = 8  !< reals per bearing [-]
  integer(ik), parameter :: bearing_rows_per = 4 !< rows per bearing: x, y, theta_i, theta_o [-]
  integer(ik), parameter :: defect_spall = 1     !< a localized defect (rectangular depth profile)
  integer(ik), parameter :: defect_waviness = 2  !< race waviness
  integer(ik), parameter :: ring_outer = 1       !< a defect on the outer ring
  integer(ik), parameter :: ring_inner = 2       !< a defect on the inner ring

  real(dp), parameter :: two_pi = 8.0_dp * atan(1.0_dp)

  !> The rolling bearings of a transient problem.
  type :: bearing_set
    integer(ik) :: n_bearing = 0                     !< bearings [-]
    integer(ik), allocatable :: elements(:)          !< Z per bearing [-]
    real(dp), allocatable :: param(:, :)             !< (n_bearing_param, n_bearing) [SI, see bp_*]
    type(sparse_rows) :: rows                        !< 4 rows per bearing: x, y [m/m], theta_i, theta_o [rad/rad]
    integer(ik) :: n_defect = 0                      !< defects [-]
    integer(ik), allocatable :: defect(:, :)         !< (3, n_defect): bearing, ring, kind [-]
    real(dp), allocatable :: defect_value(:, :)      !< (3, n_defect): phi [rad], w [rad] or N [-], h or A [m]
  end type bearing_set

contains

  !> Check a set against n DOFs: 0 when good, else the index of the first wrong entry
  !> (bearing b: b; defect d: 1000 + d; the rows: -1).
  pure integer(ik) function check_bearing_set(set, n) result(bad)
    type(bearing_set), intent(in) :: set  !< the bearings
    integer(ik), intent(in) :: n          !< DOFs [-]
    integer(ik) :: b, d

    bad = 0
    if (.not. rows_fit(set%rows, bearing_rows_per * set%n_bearing, n)) then
      bad = -1
      return
    end if
    do b = 1, set%n_bearing
      if (set%elements(b) < 3 .or. .not. (set%param(bp_constant, b) > 0.0_dp) .or. &
          .not. (set%param(bp_exponent, b) >= 1.0_dp) .or. &
          .not. (abs(set%param(bp_clearance, b)) < 1.0_dp) .or. &
          .not. (set%param(bp_cos_alpha, b) > 0.0_dp .and. set%param(bp_cos_alpha, b) <= 1.0_dp) .or. &
          .not. (set%param(bp_spring, b) >= 0.0_dp) .or. &
          .not. (set%param(bp_damping, b) >= 0.0_dp .and. set%param(bp_damping, b) <= huge(1.0_dp))) then
        bad = b
        return
      end if
    end do
    do d = 1, set%n_defect
      if (set%defect(1, d) < 1 .or. set%defect(1, d) > set%n_bearing .or. &
          (set%defect(2, d) /= ring_outer .and. set%defect(2, d) /= ring_inner) .or. &
          (set%defect(3, d) /= defect_spall .and. set%defect(3, d) /= defect_waviness) .or. &
          .not. all(abs(set%defect_value(:, d)) <= huge(1.0_dp))) then
        bad = 1000 + d
        return
      end if
    end do
  end function check_bearing_set

  !> p = the bearings' rows times x (4 per bearing: x, y, theta_i, theta_o).
  pure subroutine bearing_rows(set, x, p)
    type(bearing_set), intent(in) :: set             !< the bearings
    real(dp), intent(in), contiguous :: x(:)         !< a vector over the DOFs [m, rad]
    real(dp), intent(out), contiguous :: p(:)        !< (4 n_bearing) products [m, rad]
    call sparse_products(set%rows, x, p)
  end subroutine bearing_rows

  !> Equivalent loads g(1:2, b) = F_b - k_r (x, y) of every bearing at the ring state p
  !> and rates pv, the elements' force F_b and the number of loaded elements.
  !>
  !> Contact dampers within a step's iteration (contact, flips given): an element
  !> touching at the start of an impact carries c_c ddelta at once, which can throw it
  !> back out of contact, where it carries nothing: the iterates could alternate.  As
  !> the mesh dampers (module newmark), an element's damper that switched twice within
  !> the step (flips, counted when count is set) stays off for that step, so it engages
  !> one step late and never acts across an open gap.
  pure subroutine bearing_loads(set, p, pv, g, force, loaded, contact, flips, count)
    type(bearing_set), intent(in) :: set                 !< the bearings
    real(dp), intent(in) :: p(:)                         !< (4 n_bearing) x, y [m], theta_i, theta_o [rad]
    real(dp), intent(in) :: pv(:)                        !< (4 n_bearing) their rates [m/s, rad/s]
    real(dp), intent(out) :: g(:, :)                     !< (2, n_bearing) equivalent loads [N]
    real(dp), intent(out) :: force(:, :)                 !< (2, n_bearing) F = sum Q_j cos(alpha) e_j [N]
    integer(ik), intent(out) :: loaded(:)                !< (n_bearing) elements in contact [-]
    logical, intent(inout), optional :: contact(:, :)    !< (max Z, n_bearing) element in contact at the last call [-]
    integer(ik), intent(inout), optional :: flips(:, :)  !< (max Z, n_bearing) its contact switches this step [-]
    logical, intent(in), optional :: count               !< count switches against contact [-]
    integer(ik) :: b, j, d, z, base, first, last
    real(dp) :: x, y, theta_i, theta_o, cage, psi, c, s, delta, q, k_n, exponent, half_gap, &
                cos_alpha, ring, gap, c_step, s_step, c_next, radial, half_zone, direction, &
                damping, x_rate, y_rate
    logical :: defects, wavy, tracked, counting, was(maxval(set%elements))
    integer(ik) :: k

    do b = 1, set%n_bearing
      base = bearing_rows_per * (b - 1)
      x = p(base + 1)
      y = p(base + 2)
      theta_i = p(base + 3)
      theta_o = p(base + 4)
      x_rate = pv(base + 1)
      y_rate = pv(base + 2)
      damping = set%param(bp_damping, b)
      z = set%elements(b)
      k_n = set%param(bp_constant, b)
      exponent = set%param(bp_exponent, b)
      half_gap = 0.5_dp * set%param(bp_clearance, b)
      cos_alpha = set%param(bp_cos_alpha, b)
      cage = set%param(bp_cage_inner, b) * theta_i + set%param(bp_cage_outer, b) * theta_o
      force(:, b) = 0.0_dp
      loaded(b) = 0
      tracked = damping > 0.0_dp .and. present(contact) .and. present(flips) .and. present(count)
      counting = .false.
      if (tracked) then
        counting = count
        was(1:z) = contact(1:z, b)
        contact(1:z, b) = .false.
      end if
      defects = any(set%defect(1, 1:set%n_defect) == b)
      wavy = any(set%defect(1, 1:set%n_defect) == b .and. set%defect(3, 1:set%n_defect) == &
                 defect_waviness)
      ! with clearance and no waviness (spalls only take contact away) only the elements
      ! within the load zone, |psi - direction| < acos(P_d / (2 e)), can touch
      first = 0
      last = z - 1
      radial = hypot(x, y)
      if (half_gap >= 0.0_dp .and. .not. wavy) then
        if (radial <= half_gap) then  ! inside the clearance: no element touches
          last = -1
        else
          half_zone = acos(half_gap / radial)
          direction = atan2(y, x)
          first = ceiling((direction - half_zone - cage) * real(z, dp) / two_pi, ik)
          last = min(floor((direction + half_zone - cage) * real(z, dp) / two_pi, ik), first + z - 1)
        end if
      end if
      ! the elements' directions by rotation from the first's (two cosines per bearing;
      ! the recurrence's rounding grows by about eps per element, 1e-14 at Z = 100)
      c = cos(cage + two_pi * real(first, dp) / real(z, dp))
      s = sin(cage + two_pi * real(first, dp) / real(z, dp))
      c_step = cos(two_pi / real(z, dp))
      s_step = sin(two_pi / real(z, dp))
      psi = cage  ! read only with defects, set per element then
      do j = first, last
        if (j > first) then
          c_next = c * c_step - s * s_step
          s = s * c_step + c * s_step
          c = c_next
        end if
        delta = (x * c + y * s - half_gap) * cos_alpha
        if (defects) psi = cage + two_pi * real(j, dp) / real(z, dp)
        do d = 1, set%n_defect  ! what the defects of this bearing take off the contact
          if (set%defect(1, d) /= b) cycle
          ring = merge(theta_o, theta_i, set%defect(2, d) == ring_outer)
          if (set%defect(3, d) == defect_spall) then
            gap = modulo(psi - ring - set%defect_value(1, d) + 0.5_dp * two_pi, two_pi) - 0.5_dp * two_pi
            if (abs(gap) < 0.5_dp * set%defect_value(2, d)) delta = delta - set%defect_value(3, d)
          else
            delta = delta + set%defect_value(3, d) * &
                    cos(set%defect_value(2, d) * (psi - ring - set%defect_value(1, d)))
          end if
        end do
        if (delta > 0.0_dp) then
          q = k_n * delta * sqrt(delta)  ! n = 3/2
          if (exponent /= 1.5_dp) q = k_n * delta**exponent
          if (tracked) then  ! the damper unless it switched twice this step
            k = int(modulo(j, z), ik) + 1
            contact(k, b) = .true.
            if (counting .and. .not. was(k)) flips(k, b) = flips(k, b) + 1
            if (flips(k, b) < 2) q = q + damping * (x_rate * c + y_rate * s) * cos_alpha
          else if (damping > 0.0_dp) then
            q = q + damping * (x_rate * c + y_rate * s) * cos_alpha
          end if
          force(1, b) = force(1, b) + q * cos_alpha * c
          force(2, b) = force(2, b) + q * cos_alpha * s
          loaded(b) = loaded(b) + 1
        end if
      end do
      if (counting) where (was(1:z) .and. .not. contact(1:z, b)) flips(1:z, b) = flips(1:z, b) + 1
      g(1, b) = force(1, b) - set%param(bp_spring, b) * x
      g(2, b) = force(2, b) - set%param(bp_spring, b) * y
    end do
  end subroutine bearing_loads

  !> y = y + s sum_b (w_x g_x + w_y g_y): the bearings' equivalent loads over the DOFs.
  pure subroutine add_bearing_loads(set, g, s, y)
    type(bearing_set), intent(in) :: set    !< the bearings
    real(dp), intent(in) :: g(:, :)         !< (2, n_bearing) equivalent loads [N]
    real(dp), intent(in) :: s               !< scale [-]
    real(dp), intent(inout) :: y(:)         !< accumulator over the DOFs [N, N m]
    integer(ik) :: b, base
    do b = 1, set%n_bearing
      base = bearing_rows_per * (b - 1)
      call add_sparse(set%rows, base + 1, s * g(1, b), y)
      call add_sparse(set%rows, base + 2, s * g(2, b), y)
    end do
  end subroutine add_bearing_loads

  !> y = y + s N(q, v): the bearings' equivalent loads at the state (q, v) over the DOFs.
  pure subroutine add_state_bearing_loads(set, q, v, s, y)
    type(bearing_set), intent(in) :: set    !< the bearings
    real(dp), intent(in), contiguous :: q(:) !< displacements [m, rad]
    real(dp), intent(in), contiguous :: v(:) !< velocities [m/s, rad/s]
    real(dp), intent(in) :: s               !< scale [-]
    real(dp), intent(inout) :: y(:)         !< accumulator over the DOFs [N, N m]
    real(dp) :: p(bearing_rows_per * set%n_bearing), pv(bearing_rows_per * set%n_bearing), &
                g(2, set%n_bearing), force(2, set%n_bearing)
    integer(ik) :: loaded(set%n_bearing)
    call bearing_rows(set, q, p)
    pv = 0.0_dp
    if (any(set%param(bp_damping, :) > 0.0_dp)) call bearing_rows(set, v, pv)
    call bearing_loads(set, p, pv, g, force, loaded)
    call add_bearing_loads(set, g, s, y)
  end subroutine add_state_bearing_loads

end module rolling_bearing
