!> Tooth-contact table (docs/model.md section 5.1): the stiffness of every mesh at a state.
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
!> A table is one tooth_contact_table (one entry or column per mesh); the Newmark
!> loop calls evaluate_contact on it directly, and evaluate_contact does not
!> allocate.  Per-tooth factors of all gears are packed into one array: the
!> factors of gear g of mesh m are factor(factor_start(g, m) + 1 : ... + Z_g),
!> and factor_start = -1 marks a healthy gear (no look-up).  Several meshes may
!> share one block (a planet's sun and ring meshes share the planet's).
!> Tabulated single-pair curves are packed the same way into curve.
!>
!> A damaged tooth may carry its own pair curve (from the potential-energy method,
!> pygear.assembly.tooth_stiffness): while it is in mesh its pair follows that curve
!> instead of the mesh's law, k_pair = (k-bar / eps) c_tooth(p) on the scale of the
!> tabulated law (the healthy curve's unit mean sets the scale; c_tooth is not unit
!> mean).  tooth_curve_block(g, m) is the offset of gear g's per-tooth entries in
!> tooth_curve_start / tooth_curve_size for mesh m (-1: every tooth follows the law);
!> an entry gives the offset of the tooth's samples in curve and their number (0: the
!> tooth follows the law).  The blocks are per mesh: a planet tooth meets the sun and
!> the ring with different pair curves.  When both teeth of a pair carry a curve their
!> extra compliances add: 1/k = 1/k_1 + 1/k_2 - 1/k_law (teeth, foundation and Hertz
!> contact in series; the faults change only their own tooth's terms), and the pair is
!> never stiffer than either alone.  Per-tooth factors multiply the result as for any
!> pair.
!>
!> A mesh may carry a displacement excitation e(s) (docs/contact.md, the loaded contact
!> as a mesh law): its unloaded transmission error along the drive flank's compression,
!> one period over a mesh cycle, n samples at s = q / (n - 1), q = 0 .. n - 1 (first and
!> last the same), interpolated linearly at frac(s).  The mesh force is then
!> k_m (c - e(s)), c the drive flank's compression (module newmark).  Samples are packed
!> in excitation; excitation_size(m) = 0 marks a mesh without one, and a table without
!> any excitation is never looked at in the time loop.
!>
!> Tables that Python uses are checked once and kept here, addressed by a handle
!> (module handles): create_contact_table, contact_table_at, free_contact_table.
module contact_table
  use kinds, only: dp, ik
  use handles, only: handle_registry, keep_item, find_item, release_item, hd_ok, hd_err_full
  implicit none
  private

  public :: tooth_contact_table
  public :: evaluate_contact, evaluate_contact_series, evaluate_excitation, has_excitation, check_contact_table, pair_stiffness
  public :: create_contact_table, free_contact_table, contact_table_at
  public :: law_parabola, law_tabulated, law_helical
  public :: ct_ok, ct_err_argument, ct_err_option, ct_err_size, ct_err_state, ct_err_handle, &
            ct_err_full

  integer(ik), parameter :: law_parabola = 1   !< mean-preserving parabola (docs/model.md section 5.2)
  integer(ik), parameter :: law_tabulated = 2  !< tabulated curve, linear interpolation
  integer(ik), parameter :: law_helical = 3    !< helical contact-line length (trapezoid)

  integer(ik), parameter :: ct_ok = 0            !< success
  integer(ik), parameter :: ct_err_argument = 1  !< a table entry is out of range
  integer(ik), parameter :: ct_err_option = 2    !< an unknown law code
  integer(ik), parameter :: ct_err_size = 3      !< an output array or packed array is too small
  integer(ik), parameter :: ct_err_state = 4     !< a state is not finite or too large
  integer(ik), parameter :: ct_err_handle = 5    !< not the handle of a live table
  integer(ik), parameter :: ct_err_full = 6      !< the table registry is full

  integer, parameter :: i8 = selected_int_kind(18)         !< unwrapped cycle counts
  real(dp), parameter :: two_pi = 6.283185307179586476925286766559_dp
  real(dp), parameter :: max_cycles = 2.0_dp**50            !< beyond, frac(s) loses its digits
  real(dp), parameter :: mean_tolerance = 1.0e-9_dp         !< unit-mean check of a curve

  !> The tooth-contact table of n_mesh meshes.
  type :: tooth_contact_table
    integer(ik) :: n_mesh = 0                        !< number of meshes [-]
    integer(ik) :: max_pairs = 0                     !< pairs per mesh the outputs hold [-]
    integer(ik), allocatable :: teeth(:, :)          !< (2, n_mesh) tooth numbers Z1, Z2 [-]
    integer(ik), allocatable :: cycle_sign(:)        !< +1 or -1: sign of theta in s [-]
    integer(ik), allocatable :: tooth_offset(:, :)   !< (2, n_mesh) i0, j0: pair entering at s = 0 [-]
    real(dp), allocatable :: mean_stiffness(:)       !< k-bar, mean over a mesh cycle [N/m]
    real(dp), allocatable :: contact_ratio(:)        !< epsilon [-]
    real(dp), allocatable :: end_to_peak(:)          !< lambda (parabola), overlap ratio (helical) [-]
    real(dp), allocatable :: phase(:)                !< gamma [mesh cycles]
    integer(ik), allocatable :: law(:)               !< single-pair law code [-]
    integer(ik), allocatable :: curve_start(:)       !< offset of the mesh's curve in curve [-]
    integer(ik), allocatable :: curve_size(:)        !< samples of the mesh's curve (tabulated) [-]
    real(dp), allocatable :: curve(:)                !< packed curves, unit mean over [0, eps] [-]
    integer(ik), allocatable :: factor_start(:, :)   !< (2, n_mesh) factor offsets; -1 healthy [-]
    real(dp), allocatable :: factor(:)               !< packed per-tooth factors in [0, 1] [-]
    integer(ik), allocatable :: tooth_curve_block(:, :) !< (2, n_mesh) per-tooth curve offsets; -1 none [-]
    integer(ik), allocatable :: tooth_curve_start(:) !< offset of a tooth's pair curve in curve [-]
    integer(ik), allocatable :: tooth_curve_size(:)  !< samples of a tooth's pair curve, 0 law [-]
    integer(ik), allocatable :: excitation_start(:)  !< offset of the mesh's e(s) in excitation [-]
    integer(ik), allocatable :: excitation_size(:)   !< samples of e(s) over a cycle, 0 none [-]
    real(dp), allocatable :: excitation(:)           !< packed e(s) samples along the compression [m]
  end type tooth_contact_table

  type(handle_registry), target :: registry  !< the tables Python holds handles of

contains

  !> Mesh stiffness, pairs in contact, their positions and teeth for every mesh
  !> at one state.  No allocation; callable from the time loop.
  subroutine evaluate_contact(table, theta, stiffness, n_pairs, n_loaded, position, tooth, ierr)
    type(tooth_contact_table), intent(in) :: table                  !< a checked table
    real(dp), intent(in) :: theta(table%n_mesh)                     !< gear 1 rotation relative to the carrier [rad]
    real(dp), intent(out) :: stiffness(table%n_mesh)                !< mesh stiffness k_m [N/m]
    integer(ik), intent(out) :: n_pairs(table%n_mesh)               !< tooth pairs in contact [-]
    integer(ik), intent(out) :: n_loaded(table%n_mesh)              !< pairs with both factors > 0 [-]
    real(dp), intent(out) :: position(table%max_pairs, table%n_mesh) !< p_k, 0 <= p_k < eps [mesh cycles]
    integer(ik), intent(out) :: tooth(2, table%max_pairs, table%n_mesh) !< i_k, j_k (0-based); -1 unused [-]
    integer(ik), intent(out) :: ierr                                !< error code (0 = ok)
    integer(ik) :: m, k, z1, z2, i, j, c0, c1, f1, f2, t1, t2
    integer(i8) :: count
    real(dp) :: s, whole, p, eps, k_pair, d, total

    ierr = ct_ok
    stiffness = 0.0_dp
    n_pairs = 0
    n_loaded = 0
    position = -1.0_dp
    tooth = -1
    do m = 1, table%n_mesh
      z1 = table%teeth(1, m)
      z2 = table%teeth(2, m)
      eps = table%contact_ratio(m)
      s = real(table%cycle_sign(m), dp) * real(z1, dp) * theta(m) / two_pi + table%phase(m)
      if (.not. (abs(s) < max_cycles)) then
        ierr = ct_err_state
        return
      end if
      whole = floor(s)
      count = int(whole, i8)
      ! teeth of the newest pair (k = 0); older pairs step back one tooth each
      i = int(modulo(int(table%tooth_offset(1, m), i8) + count, int(z1, i8)), ik)
      j = int(modulo(int(table%tooth_offset(2, m), i8) + count, int(z2, i8)), ik)
      c0 = table%curve_start(m) + 1
      c1 = table%curve_start(m) + table%curve_size(m)
      f1 = table%factor_start(1, m)
      f2 = table%factor_start(2, m)
      t1 = table%tooth_curve_block(1, m)
      t2 = table%tooth_curve_block(2, m)
      total = 0.0_dp
      p = s - whole
      k = 0
      do while (p < eps)
        k = k + 1
        if (k > table%max_pairs) then
          ierr = ct_err_size
          return
        end if
        call pair_stiffness(table%law(m), p, table%mean_stiffness(m), eps, table%end_to_peak(m), &
                            table%curve(c0:c1), k_pair, ierr)
        if (ierr /= ct_ok) return
        if (t1 >= 0 .or. t2 >= 0) then
          call damaged_pair(table, m, t1, t2, i, j, p, k_pair, ierr)
          if (ierr /= ct_ok) return
        end if
        d = 1.0_dp
        if (f1 >= 0) d = table%factor(f1 + i + 1)
        if (f2 >= 0) d = d * table%factor(f2 + j + 1)
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

  !> True when a mesh of the table carries a displacement excitation.
  pure logical function has_excitation(table)
    type(tooth_contact_table), intent(in) :: table  !< a checked table

    has_excitation = .false.
    if (allocated(table%excitation_size)) has_excitation = any(table%excitation_size > 0)
  end function has_excitation

  !> The displacement excitation e_m(s) of every mesh at one state (0 for a mesh
  !> without one), along the drive flank's compression.  No allocation.
  pure subroutine evaluate_excitation(table, theta, excitation, ierr)
    type(tooth_contact_table), intent(in) :: table        !< a checked table
    real(dp), intent(in) :: theta(table%n_mesh)           !< gear 1 rotation relative to the carrier [rad]
    real(dp), intent(out) :: excitation(table%n_mesh)     !< e_m at the state [m]
    integer(ik), intent(out) :: ierr                      !< error code (0 = ok)
    integer(ik) :: m, n, q, c0
    real(dp) :: s, u, w

    ierr = ct_ok
    excitation = 0.0_dp
    do m = 1, table%n_mesh
      n = table%excitation_size(m)
      if (n == 0) cycle
      s = real(table%cycle_sign(m), dp) * real(table%teeth(1, m), dp) * theta(m) / two_pi &
          + table%phase(m)
      if (.not. (abs(s) < max_cycles)) then
        ierr = ct_err_state
        return
      end if
      u = (s - floor(s)) * real(n - 1, dp)
      q = min(max(int(u), 0), n - 2)
      w = u - real(q, dp)
      c0 = table%excitation_start(m) + q + 1
      excitation(m) = (1.0_dp - w) * table%excitation(c0) + w * table%excitation(c0 + 1)
    end do
  end subroutine evaluate_excitation

  !> The pair of teeth i (gear 1) and j (gear 2) at position p when either carries its
  !> own pair curve; k_pair holds the law's value on entry.
  pure subroutine damaged_pair(table, m, block_1, block_2, i, j, p, k_pair, ierr)
    type(tooth_contact_table), intent(in) :: table  !< a checked table
    integer(ik), intent(in) :: m                    !< mesh [-]
    integer(ik), intent(in) :: block_1, block_2     !< tooth_curve_block of gears 1, 2; -1 none [-]
    integer(ik), intent(in) :: i, j                 !< teeth of the pair (0-based) [-]
    real(dp), intent(in) :: p                       !< relative contact position [mesh cycles]
    real(dp), intent(inout) :: k_pair               !< law's pair stiffness in, the pair's out [N/m]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)
    real(dp) :: k_tooth(2)
    logical :: own(2)
    integer(ik) :: g, slot, c0, c1

    ierr = ct_ok
    own = .false.
    k_tooth = k_pair
    do g = 1, 2
      slot = merge(block_1 + i, block_2 + j, g == 1) + 1
      if (merge(block_1, block_2, g == 1) < 0) cycle
      if (table%tooth_curve_size(slot) == 0) cycle
      own(g) = .true.
      c0 = table%tooth_curve_start(slot) + 1
      c1 = table%tooth_curve_start(slot) + table%tooth_curve_size(slot)
      call pair_stiffness(law_tabulated, p, table%mean_stiffness(m), table%contact_ratio(m), &
                          0.0_dp, table%curve(c0:c1), k_tooth(g), ierr)
      if (ierr /= ct_ok) return
    end do
    if (own(1) .and. own(2)) then  ! extra compliances in series
      if (k_tooth(1) > 0.0_dp .and. k_tooth(2) > 0.0_dp .and. k_pair > 0.0_dp) then
        ! never stiffer than either damaged tooth alone (a law stiffer than the curves)
        k_pair = 1.0_dp / max(1.0_dp / k_tooth(1) + 1.0_dp / k_tooth(2) - 1.0_dp / k_pair, &
                              1.0_dp / k_tooth(1), 1.0_dp / k_tooth(2))
      else
        k_pair = 0.0_dp
      end if
    else if (own(1)) then
      k_pair = k_tooth(1)
    else if (own(2)) then
      k_pair = k_tooth(2)
    end if
  end subroutine damaged_pair

  !> evaluate_contact at every state (column) of theta; bad_state names the first state
  !> that failed, and the columns of the states after it are left as they were.
  subroutine evaluate_contact_series(table, theta, stiffness, n_pairs, n_loaded, position, tooth, &
                                     bad_state, ierr)
    type(tooth_contact_table), intent(in) :: table         !< a checked table
    real(dp), intent(in), contiguous :: theta(:, :)        !< (n_mesh, states) gear 1 rotations [rad]
    real(dp), intent(out), contiguous :: stiffness(:, :)   !< (n_mesh, states) k_m [N/m]
    integer(ik), intent(out), contiguous :: n_pairs(:, :)  !< (n_mesh, states) pairs in contact [-]
    integer(ik), intent(out), contiguous :: n_loaded(:, :) !< (n_mesh, states) pairs carrying load [-]
    real(dp), intent(out), contiguous :: position(:, :, :) !< (max_pairs, n_mesh, states) p_k [mesh cycles]
    integer(ik), intent(out), contiguous :: tooth(:, :, :, :) !< (2, max_pairs, n_mesh, states) i_k, j_k [-]
    integer(ik), intent(out) :: bad_state                  !< first failing state (1-based), 0 if none [-]
    integer(ik), intent(out) :: ierr                       !< error code (0 = ok)
    integer(ik) :: t

    bad_state = 0
    ierr = ct_ok
    do t = 1, int(size(theta, 2), ik)
      call evaluate_contact(table, theta(:, t), stiffness(:, t), n_pairs(:, t), n_loaded(:, t), &
                            position(:, :, t), tooth(:, :, :, t), ierr)
      if (ierr /= ct_ok) then
        bad_state = t
        return
      end if
    end do
  end subroutine evaluate_contact_series

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
  pure subroutine check_contact_table(table, bad_mesh, ierr)
    type(tooth_contact_table), intent(in) :: table   !< the table to check
    integer(ik), intent(out) :: bad_mesh             !< first mesh at fault, 0 if none [-]
    integer(ik), intent(out) :: ierr                 !< error code (0 = ok)
    integer(ik) :: m, g, c0, c1, f0, f1, n_curve, n_factor
    real(dp) :: trapezoid

    ierr = ct_ok
    bad_mesh = 0
    if (.not. consistent_sizes(table)) then
      ierr = ct_err_size
      return
    end if
    n_curve = int(size(table%curve), ik)
    n_factor = int(size(table%factor), ik)
    do m = 1, table%n_mesh
      bad_mesh = m
      if (any(table%teeth(:, m) < 1) .or. abs(table%cycle_sign(m)) /= 1) ierr = ct_err_argument
      if (any(table%tooth_offset(:, m) < 0) .or. any(table%tooth_offset(:, m) >= table%teeth(:, m))) &
        ierr = ct_err_argument
      if (.not. (table%mean_stiffness(m) > 0.0_dp .and. table%mean_stiffness(m) <= huge(1.0_dp))) &
        ierr = ct_err_argument
      if (.not. (table%contact_ratio(m) > 0.0_dp .and. table%contact_ratio(m) < 1.0e6_dp)) &
        ierr = ct_err_argument
      if (.not. (abs(table%phase(m)) < max_cycles)) ierr = ct_err_argument
      if (ierr /= ct_ok) return
      if (real(table%max_pairs, dp) < table%contact_ratio(m)) then
        ierr = ct_err_size
        return
      end if
      select case (table%law(m))
      case (law_parabola)
        if (.not. (table%end_to_peak(m) > 0.0_dp .and. table%end_to_peak(m) <= 1.0_dp)) &
          ierr = ct_err_argument
      case (law_helical)
        ! eps_b in (0, eps): the transverse ratio eps - eps_b stays positive
        if (.not. (table%end_to_peak(m) > 0.0_dp .and. table%end_to_peak(m) < table%contact_ratio(m))) &
          ierr = ct_err_argument
      case (law_tabulated)
        c0 = table%curve_start(m) + 1
        c1 = table%curve_start(m) + table%curve_size(m)
        if (table%curve_size(m) < 2 .or. table%curve_start(m) < 0 .or. c1 > n_curve) then
          ierr = ct_err_size
          return
        end if
        if (.not. all(table%curve(c0:c1) >= 0.0_dp .and. table%curve(c0:c1) <= huge(1.0_dp))) then
          ierr = ct_err_argument
          return
        end if
        trapezoid = (sum(table%curve(c0:c1)) - 0.5_dp * (table%curve(c0) + table%curve(c1))) &
                    / real(table%curve_size(m) - 1, dp)
        if (abs(trapezoid - 1.0_dp) > mean_tolerance) ierr = ct_err_argument
      case default
        ierr = ct_err_option
      end select
      if (ierr /= ct_ok) return
      call check_tooth_curves(table, m, n_curve, ierr)
      if (ierr /= ct_ok) return
      call check_excitation(table, m, ierr)
      if (ierr /= ct_ok) return
      do g = 1, 2
        f0 = table%factor_start(g, m)
        if (f0 < -1) ierr = ct_err_argument
        if (f0 >= 0) then
          f1 = f0 + table%teeth(g, m)
          if (f1 > n_factor) then
            ierr = ct_err_size
            return
          end if
          if (.not. all(table%factor(f0 + 1:f1) >= 0.0_dp .and. table%factor(f0 + 1:f1) <= 1.0_dp)) &
            ierr = ct_err_argument
        end if
      end do
      if (ierr /= ct_ok) return
    end do
    bad_mesh = 0
  end subroutine check_contact_table

  !> The per-tooth pair curves of mesh m: blocks inside the arrays, each curve inside
  !> curve with at least two finite samples >= 0.
  pure subroutine check_tooth_curves(table, m, n_curve, ierr)
    type(tooth_contact_table), intent(in) :: table  !< the table to check
    integer(ik), intent(in) :: m                    !< mesh [-]
    integer(ik), intent(in) :: n_curve              !< size of curve [-]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)
    integer(ik) :: g, block, slot, c0, c1

    ierr = ct_ok
    do g = 1, 2
      block = table%tooth_curve_block(g, m)
      if (block < -1) ierr = ct_err_argument
      if (block < 0) cycle
      if (block + table%teeth(g, m) > size(table%tooth_curve_size)) then
        ierr = ct_err_size
        return
      end if
      do slot = block + 1, block + table%teeth(g, m)
        if (table%tooth_curve_size(slot) == 0) cycle
        c0 = table%tooth_curve_start(slot) + 1
        c1 = table%tooth_curve_start(slot) + table%tooth_curve_size(slot)
        if (table%tooth_curve_size(slot) < 2 .or. c0 < 1 .or. c1 > n_curve) then
          ierr = ct_err_size
          return
        end if
        if (.not. all(table%curve(c0:c1) >= 0.0_dp .and. table%curve(c0:c1) <= huge(1.0_dp))) &
          ierr = ct_err_argument
      end do
    end do
  end subroutine check_tooth_curves

  !> The excitation of mesh m: none, or at least two finite samples inside the array
  !> whose first and last agree (one period).
  pure subroutine check_excitation(table, m, ierr)
    type(tooth_contact_table), intent(in) :: table  !< the table to check
    integer(ik), intent(in) :: m                    !< mesh [-]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)
    integer(ik) :: c0, c1

    ierr = ct_ok
    if (table%excitation_size(m) == 0) return
    c0 = table%excitation_start(m) + 1
    c1 = table%excitation_start(m) + table%excitation_size(m)
    if (table%excitation_size(m) < 2 .or. c0 < 1 .or. c1 > size(table%excitation)) then
      ierr = ct_err_size
      return
    end if
    if (.not. all(abs(table%excitation(c0:c1)) <= huge(1.0_dp))) ierr = ct_err_argument
    if (table%excitation(c0) /= table%excitation(c1)) ierr = ct_err_argument
  end subroutine check_excitation

  !> Every array of the table is allocated with the size its n_mesh gives.
  pure logical function consistent_sizes(table)
    type(tooth_contact_table), intent(in) :: table  !< the table to inspect
    integer(ik) :: n

    n = table%n_mesh
    consistent_sizes = .false.
    if (n < 0) return
    if (.not. (allocated(table%teeth) .and. allocated(table%cycle_sign) .and. &
               allocated(table%tooth_offset) .and. allocated(table%mean_stiffness) .and. &
               allocated(table%contact_ratio) .and. allocated(table%end_to_peak) .and. &
               allocated(table%phase) .and. allocated(table%law) .and. &
               allocated(table%curve_start) .and. allocated(table%curve_size) .and. &
               allocated(table%curve) .and. allocated(table%factor_start) .and. &
               allocated(table%factor) .and. allocated(table%tooth_curve_block) .and. &
               allocated(table%tooth_curve_start) .and. allocated(table%tooth_curve_size) .and. &
               allocated(table%excitation_start) .and. allocated(table%excitation_size) .and. &
               allocated(table%excitation))) return
    if (any(shape(table%teeth) /= [2, n]) .or. any(shape(table%tooth_offset) /= [2, n]) .or. &
        any(shape(table%factor_start) /= [2, n]) .or. &
        any(shape(table%tooth_curve_block) /= [2, n])) return
    if (size(table%tooth_curve_start) /= size(table%tooth_curve_size)) return
    if (size(table%cycle_sign) /= n .or. size(table%mean_stiffness) /= n .or. &
        size(table%contact_ratio) /= n .or. size(table%end_to_peak) /= n .or. &
        size(table%phase) /= n .or. size(table%law) /= n .or. size(table%curve_start) /= n .or. &
        size(table%curve_size) /= n .or. size(table%excitation_start) /= n .or. &
        size(table%excitation_size) /= n) return
    if (any(table%excitation_size < 0)) return
    consistent_sizes = .true.
  end function consistent_sizes

  !> Check a table and keep a copy of it under a new handle.
  subroutine create_contact_table(table, handle, bad_mesh, ierr)
    type(tooth_contact_table), intent(in) :: table  !< the table to keep
    integer(ik), intent(out) :: handle              !< its handle, 0 on error [-]
    integer(ik), intent(out) :: bad_mesh            !< first mesh at fault, 0 if none [-]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)

    handle = 0
    call check_contact_table(table, bad_mesh, ierr)
    if (ierr /= ct_ok) return
    call keep_item(registry, table, handle, ierr)
    if (ierr /= hd_ok) ierr = merge(ct_err_full, ct_err_handle, ierr == hd_err_full)
  end subroutine create_contact_table

  !> Release a table; its handle is no longer valid.
  subroutine free_contact_table(handle, ierr)
    integer(ik), intent(in) :: handle   !< handle from create_contact_table [-]
    integer(ik), intent(out) :: ierr    !< error code (0 = ok)

    call release_item(registry, handle, ierr)
    if (ierr /= hd_ok) ierr = ct_err_handle
  end subroutine free_contact_table

  !> The table a handle names, for as long as no table is created or freed; n_mesh
  !> (and max_pairs, when given) must be the sizes the caller's arrays have.
  subroutine contact_table_at(handle, n_mesh, table, ierr, max_pairs)
    integer(ik), intent(in) :: handle                          !< handle from create_contact_table [-]
    integer(ik), intent(in) :: n_mesh                          !< meshes the caller expects [-]
    type(tooth_contact_table), pointer, intent(out) :: table   !< the table, null on error
    integer(ik), intent(out) :: ierr                           !< error code (0 = ok)
    integer(ik), intent(in), optional :: max_pairs             !< pairs per mesh the caller holds [-]
    class(*), pointer :: item

    nullify (table)
    call find_item(registry, handle, item, ierr)
    ierr = ct_err_handle
    if (.not. associated(item)) return
    select type (item)
    type is (tooth_contact_table)
      ierr = ct_err_size
      if (item%n_mesh /= n_mesh) return
      if (present(max_pairs)) then
        if (item%max_pairs /= max_pairs) return
      end if
      table => item
      ierr = ct_ok
    end select
  end subroutine contact_table_at
end module contact_table
