!> Tooth-contact table (PHYSICS.md 5): the stiffness of every mesh at a state.
!>
!> For mesh m the mesh cycle is s = sign_m Z1 theta_m / (2 pi) + gamma_m, with
!> theta_m the rotation of gear 1 relative to the carrier and sign_m = +1 or -1
!> chosen so that s grows in the running direction.  The tooth pairs in contact
!> sit at relative positions p_k = frac(s) + k (k = 0, 1, ... while p_k < eps), in
!> mesh cycles (base pitches) from the start of contact.  With n_k = floor(s) - k
!> (the unwrapped count of the pair's entry into mesh) pair k is tooth
!>   i_k = modulo(i0 + n_k, Z1)   on gear 1,    j_k = modulo(j0 + n_k, Z2)   on gear 2,
!> (0-based; teeth numbered in the order in which they come into mesh).  The
!> count must be the unwrapped one: i - i0 taken modulo Z1 would restart gear
!> 2's count every Z1 cycles.  Total: k_m = sum_k k_pair(p_k) d1(i_k) d2(j_k).
!>
!> Everything is passed as plain arrays (one entry or column per mesh) so that
!> the Newmark loop can call evaluate_contact directly; evaluate_contact does
!> not allocate.  Per-tooth factors of all gears are packed into one array: the
!> factors of gear g of mesh m are factor(factor_start(g, m) + 1 : ... + Z_g),
!> and factor_start = -1 marks a healthy gear (no look-up).  Several meshes may
!> share one block (a planet's sun and ring meshes share the planet's).
!> Tabulated single-pair curves are packed the same way into curve.
module contact_table
  use kinds, only: dp, ik
  implicit none
  private

  public :: evaluate_contact, check_contact_table, pair_stiffness
  public :: law_parabola, law_tabulated, law_helical
  public :: ct_ok, ct_err_argument, ct_err_option, ct_err_size, ct_err_state

  integer(ik), parameter :: law_parabola = 1   !< mean-preserving parabola (PHYSICS.md 5)
  integer(ik), parameter :: law_tabulated = 2  !< tabulated curve, linear interpolation
  integer(ik), parameter :: law_helical = 3    !< helical contact-line length (trapezoid)

  integer(ik), parameter :: ct_ok = 0            !< success
  integer(ik), parameter :: ct_err_argument = 1  !< a table entry is out of range
  integer(ik), parameter :: ct_err_option = 2    !< an unknown law code
  integer(ik), parameter :: ct_err_size = 3      !< an output array or packed array is too small
  integer(ik), parameter :: ct_err_state = 4     !< a state is not finite or too large

  integer, parameter :: i8 = selected_int_kind(18)         !< unwrapped cycle counts
  real(dp), parameter :: two_pi = 6.283185307179586476925286766559_dp
  real(dp), parameter :: max_cycles = 2.0_dp**50            !< beyond, frac(s) loses its digits
  real(dp), parameter :: mean_tolerance = 1.0e-9_dp         !< unit-mean check of a curve

contains

  !> Mesh stiffness, pairs in contact, their positions and teeth for every mesh
  !> at one state.  No allocation; callable from the time loop.
  subroutine evaluate_contact(n_mesh, theta, teeth, cycle_sign, tooth_offset, mean_stiffness, &
                              contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
                              n_curve, curve, factor_start, n_factor, factor, max_pairs, &
                              stiffness, n_pairs, n_loaded, position, tooth, ierr)
    integer(ik), intent(in) :: n_mesh                    !< number of meshes
    real(dp), intent(in) :: theta(n_mesh)                !< gear 1 rotation relative to the carrier [rad]
    integer(ik), intent(in) :: teeth(2, n_mesh)          !< tooth numbers Z1, Z2 [-]
    integer(ik), intent(in) :: cycle_sign(n_mesh)        !< +1 or -1: sign of theta in s [-]
    integer(ik), intent(in) :: tooth_offset(2, n_mesh)   !< i0, j0: teeth of the pair entering at s = 0 [-]
    real(dp), intent(in) :: mean_stiffness(n_mesh)       !< k-bar, mean over a mesh cycle [N/m]
    real(dp), intent(in) :: contact_ratio(n_mesh)        !< epsilon [-]
    real(dp), intent(in) :: end_to_peak(n_mesh)          !< lambda (parabola), overlap ratio (helical) [-]
    real(dp), intent(in) :: phase(n_mesh)                !< gamma [mesh cycles]
    integer(ik), intent(in) :: law(n_mesh)               !< single-pair law code [-]
    integer(ik), intent(in) :: curve_start(n_mesh)       !< offset of the mesh's curve in curve [-]
    integer(ik), intent(in) :: curve_size(n_mesh)        !< samples of the mesh's curve (tabulated) [-]
    integer(ik), intent(in) :: n_curve                   !< size of curve [-]
    real(dp), intent(in) :: curve(n_curve)               !< packed curves, unit mean over [0, eps] [-]
    integer(ik), intent(in) :: factor_start(2, n_mesh)   !< offsets of gear 1 and 2 factors; -1 healthy [-]
    integer(ik), intent(in) :: n_factor                  !< size of factor [-]
    real(dp), intent(in) :: factor(n_factor)             !< packed per-tooth factors in [0, 1] [-]
    integer(ik), intent(in) :: max_pairs                 !< leading size of position and tooth [-]
    real(dp), intent(out) :: stiffness(n_mesh)           !< mesh stiffness k_m [N/m]
    integer(ik), intent(out) :: n_pairs(n_mesh)          !< tooth pairs in contact [-]
    integer(ik), intent(out) :: n_loaded(n_mesh)         !< pairs with both factors > 0 [-]
    real(dp), intent(out) :: position(max_pairs, n_mesh) !< p_k, 0 <= p_k < eps [mesh cycles]
    integer(ik), intent(out) :: tooth(2, max_pairs, n_mesh) !< i_k, j_k (0-based); -1 unused [-]
    integer(ik), intent(out) :: ierr                     !< error code (0 = ok)
    integer(ik) :: m, k, z1, z2, i, j, c0, c1, f1, f2
    integer(i8) :: count
    real(dp) :: s, whole, p, eps, k_pair, d, total

    ierr = ct_ok
    stiffness = 0.0_dp
    n_pairs = 0
    n_loaded = 0
    position = -1.0_dp
    tooth = -1
    do m = 1, n_mesh
      z1 = teeth(1, m)
      z2 = teeth(2, m)
      eps = contact_ratio(m)
      s = real(cycle_sign(m), dp) * real(z1, dp) * theta(m) / two_pi + phase(m)
      if (.not. (abs(s) < max_cycles)) then
        ierr = ct_err_state
        return
      end if
      whole = floor(s)
      count = int(whole, i8)
      ! teeth of the newest pair (k = 0); older pairs step back one tooth each
      i = int(modulo(int(tooth_offset(1, m), i8) + count, int(z1, i8)), ik)
      j = int(modulo(int(tooth_offset(2, m), i8) + count, int(z2, i8)), ik)
      c0 = curve_start(m) + 1
      c1 = curve_start(m) + curve_size(m)
      f1 = factor_start(1, m)
      f2 = factor_start(2, m)
      total = 0.0_dp
      p = s - whole
      k = 0
      do while (p < eps)
        k = k + 1
        if (k > max_pairs) then
          ierr = ct_err_size
          return
        end if
        call pair_stiffness(law(m), p, mean_stiffness(m), eps, end_to_peak(m), &
                            curve(c0:c1), k_pair, ierr)
        if (ierr /= ct_ok) return
        d = 1.0_dp
        if (f1 >= 0) d = factor(f1 + i + 1)
        if (f2 >= 0) d = d * factor(f2 + j + 1)
        total = total + k_pair * d
        if (d > 0.0_dp) n_loaded(m) = n_loaded(m) + 1
        position(k, m) = p
        tooth(1, k, m) = i
        tooth(2, k, m) = j
        i = i - 1
        if (i < 0) i = z1 - 1
        j = j - 1
        if (j < 0) j = z2 - 1
        p = p + 1.0_dp
      end do
      stiffness(m) = total
      n_pairs(m) = k
    end do
  end subroutine evaluate_contact

  !> Stiffness of one tooth pair at relative contact position p, by law code.
  !>
  !> law_parabola: k = k_pk [1 - (1 - lambda)(2p/eps - 1)^2] with
  !>   k_pk = 3 k-bar / (eps (2 + lambda)), so that the integral over [0, eps]
  !>   (the mean of k_m over one mesh cycle) is k-bar.
  !> law_tabulated: k = (k-bar / eps) c(p), with c the linear interpolant of
  !>   samples at p = eps q / (n - 1), q = 0 .. n - 1, normalised by the caller to
  !>   unit mean over [0, eps] (trapezoid rule, exact for the interpolant), so that
  !>   the mean over a mesh cycle is again k-bar.
  !> law_helical: eps is the total contact ratio eps_a + eps_b and end_to_peak the
  !>   overlap ratio eps_b.  A helical pair's contact line grows while it enters the
  !>   face width, stays, and shrinks while it leaves: its length is proportional to
  !>   min(p, eps - p, eps_a, eps_b), whose integral over [0, eps] is eps_a eps_b, so
  !>   k = k-bar min(p, eps - p, eps_a, eps_b) / (eps_a eps_b) keeps the mean k-bar.
  pure subroutine pair_stiffness(law, p, mean_stiffness, contact_ratio, end_to_peak, curve, &
                                 k_pair, ierr)
    integer(ik), intent(in) :: law              !< single-pair law code [-]
    real(dp), intent(in) :: p                   !< relative contact position, 0 <= p < eps [mesh cycles]
    real(dp), intent(in) :: mean_stiffness      !< k-bar [N/m]
    real(dp), intent(in) :: contact_ratio       !< epsilon [-]
    real(dp), intent(in) :: end_to_peak         !< lambda (parabola), eps_b (helical) [-]
    real(dp), intent(in) :: curve(:)            !< the mesh's curve samples, unit mean (tabulated) [-]
    real(dp), intent(out) :: k_pair             !< pair stiffness [N/m]
    integer(ik), intent(out) :: ierr            !< error code (0 = ok)
    real(dp) :: x, u, w
    integer :: q, n

    ierr = ct_ok
    select case (law)
    case (law_parabola)
      x = 2.0_dp * p / contact_ratio - 1.0_dp
      k_pair = 3.0_dp * mean_stiffness / (contact_ratio * (2.0_dp + end_to_peak)) &
               * (1.0_dp - (1.0_dp - end_to_peak) * x * x)
    case (law_tabulated)
      n = size(curve)
      if (n < 2) then
        k_pair = 0.0_dp
        ierr = ct_err_size
        return
      end if
      u = p / contact_ratio * real(n - 1, dp)
      q = min(max(int(u), 0), n - 2)
      w = u - real(q, dp)
      k_pair = mean_stiffness / contact_ratio * ((1.0_dp - w) * curve(q + 1) + w * curve(q + 2))
    case (law_helical)
      w = contact_ratio - end_to_peak
      k_pair = mean_stiffness * max(min(p, contact_ratio - p, w, end_to_peak), 0.0_dp) &
               / (w * end_to_peak)
    case default
      k_pair = 0.0_dp
      ierr = ct_err_option
    end select
  end subroutine pair_stiffness

  !> Check a contact table once, before it is used in a loop.  bad_mesh names
  !> the first mesh at fault (0 when the error is not tied to one mesh).
  subroutine check_contact_table(n_mesh, teeth, cycle_sign, tooth_offset, mean_stiffness, &
                                 contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
                                 n_curve, curve, factor_start, n_factor, factor, max_pairs, &
                                 bad_mesh, ierr)
    integer(ik), intent(in) :: n_mesh                    !< number of meshes
    integer(ik), intent(in) :: teeth(2, n_mesh)          !< tooth numbers Z1, Z2 [-]
    integer(ik), intent(in) :: cycle_sign(n_mesh)        !< +1 or -1 [-]
    integer(ik), intent(in) :: tooth_offset(2, n_mesh)   !< i0, j0 [-]
    real(dp), intent(in) :: mean_stiffness(n_mesh)       !< k-bar [N/m]
    real(dp), intent(in) :: contact_ratio(n_mesh)        !< epsilon [-]
    real(dp), intent(in) :: end_to_peak(n_mesh)          !< lambda, or eps_b (helical) [-]
    real(dp), intent(in) :: phase(n_mesh)                !< gamma [mesh cycles]
    integer(ik), intent(in) :: law(n_mesh)               !< single-pair law code [-]
    integer(ik), intent(in) :: curve_start(n_mesh)       !< curve offsets [-]
    integer(ik), intent(in) :: curve_size(n_mesh)        !< curve sample counts [-]
    integer(ik), intent(in) :: n_curve                   !< size of curve [-]
    real(dp), intent(in) :: curve(n_curve)               !< packed curves [-]
    integer(ik), intent(in) :: factor_start(2, n_mesh)   !< factor offsets, -1 healthy [-]
    integer(ik), intent(in) :: n_factor                  !< size of factor [-]
    real(dp), intent(in) :: factor(n_factor)             !< packed per-tooth factors [-]
    integer(ik), intent(in) :: max_pairs                 !< pairs the output arrays hold [-]
    integer(ik), intent(out) :: bad_mesh                 !< first mesh at fault, 0 if none [-]
    integer(ik), intent(out) :: ierr                     !< error code (0 = ok)
    integer(ik) :: m, g, c0, c1
    real(dp) :: trapezoid

    ierr = ct_ok
    bad_mesh = 0
    if (n_mesh < 0 .or. n_curve < 0 .or. n_factor < 0) then
      ierr = ct_err_size
      return
    end if
    do m = 1, n_mesh
      bad_mesh = m
      if (any(teeth(:, m) < 1) .or. abs(cycle_sign(m)) /= 1) ierr = ct_err_argument
      if (any(tooth_offset(:, m) < 0) .or. any(tooth_offset(:, m) >= teeth(:, m))) ierr = ct_err_argument
      if (.not. (mean_stiffness(m) > 0.0_dp .and. mean_stiffness(m) <= huge(1.0_dp))) ierr = ct_err_argument
      if (.not. (contact_ratio(m) > 0.0_dp .and. contact_ratio(m) < 1.0e6_dp)) ierr = ct_err_argument
      if (.not. (abs(phase(m)) < max_cycles)) ierr = ct_err_argument
      if (ierr /= ct_ok) return
      if (real(max_pairs, dp) < contact_ratio(m)) then
        ierr = ct_err_size
        return
      end if
      select case (law(m))
      case (law_parabola)
        if (.not. (end_to_peak(m) > 0.0_dp .and. end_to_peak(m) <= 1.0_dp)) ierr = ct_err_argument
      case (law_helical)
        ! eps_b in (0, eps): the transverse ratio eps - eps_b stays positive
        if (.not. (end_to_peak(m) > 0.0_dp .and. end_to_peak(m) < contact_ratio(m))) &
          ierr = ct_err_argument
      case (law_tabulated)
        c0 = curve_start(m) + 1
        c1 = curve_start(m) + curve_size(m)
        if (curve_size(m) < 2 .or. curve_start(m) < 0 .or. c1 > n_curve) then
          ierr = ct_err_size
          return
        end if
        if (.not. all(curve(c0:c1) >= 0.0_dp .and. curve(c0:c1) <= huge(1.0_dp))) then
          ierr = ct_err_argument
          return
        end if
        trapezoid = (sum(curve(c0:c1)) - 0.5_dp * (curve(c0) + curve(c1))) / real(curve_size(m) - 1, dp)
        if (abs(trapezoid - 1.0_dp) > mean_tolerance) ierr = ct_err_argument
      case default
        ierr = ct_err_option
      end select
      if (ierr /= ct_ok) return
      do g = 1, 2
        if (factor_start(g, m) < -1) ierr = ct_err_argument
        if (factor_start(g, m) >= 0) then
          if (factor_start(g, m) + teeth(g, m) > n_factor) then
            ierr = ct_err_size
            return
          end if
          if (.not. all(factor(factor_start(g, m) + 1:factor_start(g, m) + teeth(g, m)) >= 0.0_dp &
                        .and. factor(factor_start(g, m) + 1:factor_start(g, m) + teeth(g, m)) <= 1.0_dp)) &
            ierr = ct_err_argument
        end if
      end do
      if (ierr /= ct_ok) return
    end do
    bad_mesh = 0
  end subroutine check_contact_table
end module contact_table
