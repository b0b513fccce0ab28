!> The flat layer f2py sees for the tooth-contact table (module contact_table):
!> explicit-shape arrays, sizes passed in, error codes out.  Nothing is computed
!> here beyond looping over states; the Newmark loop calls the module directly.

subroutine contact_table_check(n_mesh, teeth, cycle_sign, tooth_offset, mean_stiffness, &
                               contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
                               n_curve, curve, factor_start, n_factor, factor, max_pairs, &
                               bad_mesh, ierr)
  use kinds, only: dp, ik
  use contact_table, only: check_contact_table
  implicit none
  integer(ik), intent(in) :: n_mesh                   !< number of meshes
  integer(ik), intent(in) :: teeth(2, n_mesh)         !< Z1, Z2
  integer(ik), intent(in) :: cycle_sign(n_mesh)       !< +1 or -1
  integer(ik), intent(in) :: tooth_offset(2, n_mesh)  !< i0, j0 (0-based)
  real(dp), intent(in) :: mean_stiffness(n_mesh)      !< k-bar [N/m]
  real(dp), intent(in) :: contact_ratio(n_mesh)       !< epsilon
  real(dp), intent(in) :: end_to_peak(n_mesh)         !< lambda
  real(dp), intent(in) :: phase(n_mesh)               !< gamma [mesh cycles]
  integer(ik), intent(in) :: law(n_mesh)              !< law code (1 parabola, 2 tabulated, 3 helical)
  integer(ik), intent(in) :: curve_start(n_mesh)      !< curve offsets
  integer(ik), intent(in) :: curve_size(n_mesh)       !< curve sample counts
  integer(ik), intent(in) :: n_curve                  !< size of curve
  real(dp), intent(in) :: curve(n_curve)              !< packed unit-mean curves
  integer(ik), intent(in) :: factor_start(2, n_mesh)  !< factor offsets, -1 healthy
  integer(ik), intent(in) :: n_factor                 !< size of factor
  real(dp), intent(in) :: factor(n_factor)            !< packed per-tooth factors
  integer(ik), intent(in) :: max_pairs                !< pairs the output arrays hold
  integer(ik), intent(out) :: bad_mesh                !< first mesh at fault (1-based), 0 if none
  integer(ik), intent(out) :: ierr                    !< error code (0 = ok)
  call check_contact_table(n_mesh, teeth, cycle_sign, tooth_offset, mean_stiffness, &
                           contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
                           n_curve, curve, factor_start, n_factor, factor, max_pairs, bad_mesh, ierr)
end subroutine contact_table_check

subroutine contact_table_evaluate(n_mesh, theta, teeth, cycle_sign, tooth_offset, mean_stiffness, &
                                  contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
                                  n_curve, curve, factor_start, n_factor, factor, max_pairs, &
                                  stiffness, n_pairs, n_loaded, position, tooth, ierr)
  use kinds, only: dp, ik
  use contact_table, only: evaluate_contact
  implicit none
  integer(ik), intent(in) :: n_mesh                   !< number of meshes
  real(dp), intent(in) :: theta(n_mesh)               !< gear 1 rotation relative to the carrier [rad]
  integer(ik), intent(in) :: teeth(2, n_mesh)         !< Z1, Z2
  integer(ik), intent(in) :: cycle_sign(n_mesh)       !< +1 or -1
  integer(ik), intent(in) :: tooth_offset(2, n_mesh)  !< i0, j0 (0-based)
  real(dp), intent(in) :: mean_stiffness(n_mesh)      !< k-bar [N/m]
  real(dp), intent(in) :: contact_ratio(n_mesh)       !< epsilon
  real(dp), intent(in) :: end_to_peak(n_mesh)         !< lambda
  real(dp), intent(in) :: phase(n_mesh)               !< gamma [mesh cycles]
  integer(ik), intent(in) :: law(n_mesh)              !< law code
  integer(ik), intent(in) :: curve_start(n_mesh)      !< curve offsets
  integer(ik), intent(in) :: curve_size(n_mesh)       !< curve sample counts
  integer(ik), intent(in) :: n_curve                  !< size of curve
  real(dp), intent(in) :: curve(n_curve)              !< packed unit-mean curves
  integer(ik), intent(in) :: factor_start(2, n_mesh)  !< factor offsets, -1 healthy
  integer(ik), intent(in) :: n_factor                 !< size of factor
  real(dp), intent(in) :: factor(n_factor)            !< packed per-tooth factors
  integer(ik), intent(in) :: max_pairs                !< pairs the output arrays hold
  real(dp), intent(out) :: stiffness(n_mesh)          !< k_m [N/m]
  integer(ik), intent(out) :: n_pairs(n_mesh)         !< pairs in contact
  integer(ik), intent(out) :: n_loaded(n_mesh)        !< pairs carrying load
  real(dp), intent(out) :: position(max_pairs, n_mesh)     !< p_k [mesh cycles], -1 unused
  integer(ik), intent(out) :: tooth(2, max_pairs, n_mesh)  !< i_k, j_k, -1 unused
  integer(ik), intent(out) :: ierr                    !< error code (0 = ok)
  call evaluate_contact(n_mesh, theta, teeth, cycle_sign, tooth_offset, mean_stiffness, &
                        contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
                        n_curve, curve, factor_start, n_factor, factor, max_pairs, &
                        stiffness, n_pairs, n_loaded, position, tooth, ierr)
end subroutine contact_table_evaluate

subroutine contact_table_series(n_state, n_mesh, theta, teeth, cycle_sign, tooth_offset, &
                                mean_stiffness, contact_ratio, end_to_peak, phase, law, curve_start, &
                                curve_size, n_curve, curve, factor_start, n_factor, factor, max_pairs, &
                                stiffness, n_pairs, n_loaded, position, tooth, bad_state, ierr)
  use kinds, only: dp, ik
  use contact_table, only: evaluate_contact
  implicit none
  integer(ik), intent(in) :: n_state                  !< number of states
  integer(ik), intent(in) :: n_mesh                   !< number of meshes
  real(dp), intent(in) :: theta(n_mesh, n_state)      !< gear 1 rotations relative to the carrier [rad]
  integer(ik), intent(in) :: teeth(2, n_mesh)         !< Z1, Z2
  integer(ik), intent(in) :: cycle_sign(n_mesh)       !< +1 or -1
  integer(ik), intent(in) :: tooth_offset(2, n_mesh)  !< i0, j0 (0-based)
  real(dp), intent(in) :: mean_stiffness(n_mesh)      !< k-bar [N/m]
  real(dp), intent(in) :: contact_ratio(n_mesh)       !< epsilon
  real(dp), intent(in) :: end_to_peak(n_mesh)         !< lambda
  real(dp), intent(in) :: phase(n_mesh)               !< gamma [mesh cycles]
  integer(ik), intent(in) :: law(n_mesh)              !< law code
  integer(ik), intent(in) :: curve_start(n_mesh)      !< curve offsets
  integer(ik), intent(in) :: curve_size(n_mesh)       !< curve sample counts
  integer(ik), intent(in) :: n_curve                  !< size of curve
  real(dp), intent(in) :: curve(n_curve)              !< packed unit-mean curves
  integer(ik), intent(in) :: factor_start(2, n_mesh)  !< factor offsets, -1 healthy
  integer(ik), intent(in) :: n_factor                 !< size of factor
  real(dp), intent(in) :: factor(n_factor)            !< packed per-tooth factors
  integer(ik), intent(in) :: max_pairs                !< pairs the output arrays hold
  real(dp), intent(out) :: stiffness(n_mesh, n_state)          !< k_m [N/m]
  integer(ik), intent(out) :: n_pairs(n_mesh, n_state)         !< pairs in contact
  integer(ik), intent(out) :: n_loaded(n_mesh, n_state)        !< pairs carrying load
  real(dp), intent(out) :: position(max_pairs, n_mesh, n_state)     !< p_k [mesh cycles]
  integer(ik), intent(out) :: tooth(2, max_pairs, n_mesh, n_state)  !< i_k, j_k
  integer(ik), intent(out) :: bad_state               !< first failing state (1-based), 0 if none
  integer(ik), intent(out) :: ierr                    !< error code (0 = ok)
  integer(ik) :: t

  bad_state = 0
  ierr = 0
  stiffness = 0.0_dp
  n_pairs = 0
  n_loaded = 0
  position = -1.0_dp
  tooth = -1
  do t = 1, n_state
    call evaluate_contact(n_mesh, theta(:, t), teeth, cycle_sign, tooth_offset, mean_stiffness, &
                          contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
                          n_curve, curve, factor_start, n_factor, factor, max_pairs, &
                          stiffness(:, t), n_pairs(:, t), n_loaded(:, t), position(:, :, t), &
                          tooth(:, :, :, t), ierr)
    if (ierr /= 0) then
      bad_state = t
      return
    end if
  end do
end subroutine contact_table_series

!> Timing loop for benchmarks: evaluates n_state states n_repeat times inside
!> one call and returns the wall time of the loop alone (system_clock).
subroutine contact_table_benchmark(n_state, n_mesh, theta, teeth, cycle_sign, tooth_offset, &
                                   mean_stiffness, contact_ratio, end_to_peak, phase, law, &
                                   curve_start, curve_size, n_curve, curve, factor_start, n_factor, &
                                   factor, max_pairs, n_repeat, elapsed, checksum, ierr)
  use kinds, only: dp, ik
  use contact_table, only: evaluate_contact
  implicit none
  integer(ik), intent(in) :: n_state                  !< number of states
  integer(ik), intent(in) :: n_mesh                   !< number of meshes
  real(dp), intent(in) :: theta(n_mesh, n_state)      !< gear 1 rotations relative to the carrier [rad]
  integer(ik), intent(in) :: teeth(2, n_mesh)         !< Z1, Z2
  integer(ik), intent(in) :: cycle_sign(n_mesh)       !< +1 or -1
  integer(ik), intent(in) :: tooth_offset(2, n_mesh)  !< i0, j0 (0-based)
  real(dp), intent(in) :: mean_stiffness(n_mesh)      !< k-bar [N/m]
  real(dp), intent(in) :: contact_ratio(n_mesh)       !< epsilon
  real(dp), intent(in) :: end_to_peak(n_mesh)         !< lambda
  real(dp), intent(in) :: phase(n_mesh)               !< gamma [mesh cycles]
  integer(ik), intent(in) :: law(n_mesh)              !< law code
  integer(ik), intent(in) :: curve_start(n_mesh)      !< curve offsets
  integer(ik), intent(in) :: curve_size(n_mesh)       !< curve sample counts
  integer(ik), intent(in) :: n_curve                  !< size of curve
  real(dp), intent(in) :: curve(n_curve)              !< packed unit-mean curves
  integer(ik), intent(in) :: factor_start(2, n_mesh)  !< factor offsets, -1 healthy
  integer(ik), intent(in) :: n_factor                 !< size of factor
  real(dp), intent(in) :: factor(n_factor)            !< packed per-tooth factors
  integer(ik), intent(in) :: max_pairs                !< pairs per mesh the work arrays hold
  integer(ik), intent(in) :: n_repeat                 !< passes over all states
  real(dp), intent(out) :: elapsed                    !< wall time of all passes [s]
  real(dp), intent(out) :: checksum                   !< sum of every k_m, keeps the loop alive [N/m]
  integer(ik), intent(out) :: ierr                    !< error code (0 = ok)
  integer, parameter :: i8 = selected_int_kind(18)
  integer(i8) :: start, finish, rate
  integer(ik) :: r, t
  real(dp) :: stiffness(n_mesh), position(max_pairs, n_mesh)
  integer(ik) :: n_pairs(n_mesh), n_loaded(n_mesh), tooth(2, max_pairs, n_mesh)

  checksum = 0.0_dp
  elapsed = 0.0_dp
  ierr = 0
  call system_clock(start, rate)
  do r = 1, n_repeat
    do t = 1, n_state
      call evaluate_contact(n_mesh, theta(:, t), teeth, cycle_sign, tooth_offset, mean_stiffness, &
                            contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
                            n_curve, curve, factor_start, n_factor, factor, max_pairs, &
                            stiffness, n_pairs, n_loaded, position, tooth, ierr)
      if (ierr /= 0) return
      checksum = checksum + sum(stiffness)
    end do
  end do
  call system_clock(finish)
  elapsed = real(finish - start, dp) / real(rate, dp)
end subroutine contact_table_benchmark
