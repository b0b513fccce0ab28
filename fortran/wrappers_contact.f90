!> The flat layer f2py sees for the tooth-contact table (module contact_table):
!> explicit-shape arrays, sizes passed in, error codes out.  A table's arrays cross
!> once, into contact_table_create, which checks the table and returns a handle;
!> the other routines take the handle.  Nothing is computed here beyond looping over
!> states; the Newmark loop calls the module directly.

!> Check a table and keep it under a handle.  Damaged teeth may carry their own pair
!> curves (packed in curve; see module contact_table); a table without them passes
!> tooth_curve_block = -1 and one-element tooth_curve_start/size.
subroutine contact_table_create(n_mesh, teeth, cycle_sign, tooth_offset, mean_stiffness, &
                                contact_ratio, end_to_peak, phase, law, curve_start, &
                                curve_size, n_curve, curve, factor_start, n_factor, &
                                factor, tooth_curve_block, n_tooth, tooth_curve_start, &
                                tooth_curve_size, excitation_start, excitation_size, &
                                n_excitation, excitation, max_pairs, handle, bad_mesh, ierr)
  use kinds, only: dp, ik
  use contact_table, only: tooth_contact_table, create_contact_table
  implicit none
  integer(ik), intent(in) :: n_mesh                        !< number of meshes [-]
  integer(ik), intent(in) :: teeth(2, n_mesh)              !< Z1, Z2 [-]
  integer(ik), intent(in) :: cycle_sign(n_mesh)            !< +1 or -1 [-]
  integer(ik), intent(in) :: tooth_offset(2, n_mesh)       !< i0, j0 (0-based) [-]
  real(dp), intent(in) :: mean_stiffness(n_mesh)           !< k-bar [N/m]
  real(dp), intent(in) :: contact_ratio(n_mesh)            !< epsilon [-]
  real(dp), intent(in) :: end_to_peak(n_mesh)              !< lambda, or eps_b (helical) [-]
  real(dp), intent(in) :: phase(n_mesh)                    !< gamma [mesh cycles]
  integer(ik), intent(in) :: law(n_mesh)                   !< law code [-]
  integer(ik), intent(in) :: curve_start(n_mesh)           !< curve offsets [-]
  integer(ik), intent(in) :: curve_size(n_mesh)            !< curve sample counts [-]
  integer(ik), intent(in) :: n_curve                       !< size of curve [-]
  real(dp), intent(in) :: curve(n_curve)                   !< packed curves, the laws' and the teeth's [-]
  integer(ik), intent(in) :: factor_start(2, n_mesh)       !< factor offsets, -1 healthy [-]
  integer(ik), intent(in) :: n_factor                      !< size of factor [-]
  real(dp), intent(in) :: factor(n_factor)                 !< packed per-tooth factors [-]
  integer(ik), intent(in) :: tooth_curve_block(2, n_mesh)  !< per-tooth curve offsets, -1 none [-]
  integer(ik), intent(in) :: n_tooth                       !< size of the per-tooth curve arrays [-]
  integer(ik), intent(in) :: tooth_curve_start(n_tooth)    !< a tooth's curve offset in curve [-]
  integer(ik), intent(in) :: tooth_curve_size(n_tooth)     !< its samples, 0 the law [-]
  integer(ik), intent(in) :: excitation_start(n_mesh)     !< offsets of e(s) in excitation [-]
  integer(ik), intent(in) :: excitation_size(n_mesh)      !< samples of e(s), 0 none [-]
  integer(ik), intent(in) :: n_excitation                  !< size of excitation [-]
  real(dp), intent(in) :: excitation(n_excitation)         !< packed e(s) samples [m]
  integer(ik), intent(in) :: max_pairs                     !< pairs per mesh the outputs hold [-]
  integer(ik), intent(out) :: handle                       !< the table's handle, 0 on error [-]
  integer(ik), intent(out) :: bad_mesh                     !< first mesh at fault (1-based), 0 if none [-]
  integer(ik), intent(out) :: ierr                         !< error code (0 = ok)
  call create_contact_table(tooth_contact_table(n_mesh=n_mesh, max_pairs=max_pairs, teeth=teeth, &
                                                cycle_sign=cycle_sign, tooth_offset=tooth_offset, &
                                                mean_stiffness=mean_stiffness, &
                                                contact_ratio=contact_ratio, &
                                                end_to_peak=end_to_peak, phase=phase, law=law, &
                                                curve_start=curve_start, curve_size=curve_size, &
                                                curve=curve, factor_start=factor_start, &
                                                factor=factor, tooth_curve_block=tooth_curve_block, &
                                                tooth_curve_start=tooth_curve_start, &
                                                tooth_curve_size=tooth_curve_size, &
                                                excitation_start=excitation_start, &
                                                excitation_size=excitation_size, &
                                                excitation=excitation), &
                            handle, bad_mesh, ierr)
end subroutine contact_table_create

subroutine contact_table_free(handle, ierr)
  use kinds, only: ik
  use contact_table, only: free_contact_table
  implicit none
  integer(ik), intent(in) :: handle   !< handle from contact_table_create [-]
  integer(ik), intent(out) :: ierr    !< error code (0 = ok)
  call free_contact_table(handle, ierr)
end subroutine contact_table_free

subroutine contact_table_evaluate(handle, n_mesh, max_pairs, theta, stiffness, n_pairs, &
                                  n_loaded, position, tooth, ierr)
  use kinds, only: dp, ik
  use contact_table, only: tooth_contact_table, contact_table_at, evaluate_contact, ct_ok
  implicit none
  integer(ik), intent(in) :: handle                        !< handle from contact_table_create [-]
  integer(ik), intent(in) :: n_mesh                        !< number of meshes [-]
  integer(ik), intent(in) :: max_pairs                     !< pairs per mesh of the table [-]
  real(dp), intent(in) :: theta(n_mesh)                    !< gear 1 rotation relative to the carrier [rad]
  real(dp), intent(out) :: stiffness(n_mesh)               !< k_m [N/m]
  integer(ik), intent(out) :: n_pairs(n_mesh)              !< pairs in contact [-]
  integer(ik), intent(out) :: n_loaded(n_mesh)             !< pairs carrying load [-]
  real(dp), intent(out) :: position(max_pairs, n_mesh)     !< p_k, -1 unused [mesh cycles]
  integer(ik), intent(out) :: tooth(2, max_pairs, n_mesh)  !< i_k, j_k, -1 unused [-]
  integer(ik), intent(out) :: ierr                         !< error code (0 = ok)
  type(tooth_contact_table), pointer :: table

  call contact_table_at(handle, n_mesh, table, ierr, max_pairs)
  if (ierr /= ct_ok) return  ! outputs stay as f2py made them (zeros)
  call evaluate_contact(table, theta, stiffness, n_pairs, n_loaded, position, tooth, ierr)
end subroutine contact_table_evaluate

subroutine contact_table_series(handle, n_state, n_mesh, max_pairs, theta, stiffness, n_pairs, &
                                n_loaded, position, tooth, bad_state, ierr)
  use kinds, only: dp, ik
  use contact_table, only: tooth_contact_table, contact_table_at, evaluate_contact_series, ct_ok
  implicit none
  integer(ik), intent(in) :: handle                                 !< handle from contact_table_create [-]
  integer(ik), intent(in) :: n_state                                !< number of states [-]
  integer(ik), intent(in) :: n_mesh                                 !< number of meshes [-]
  integer(ik), intent(in) :: max_pairs                              !< pairs per mesh of the table [-]
  real(dp), intent(in) :: theta(n_mesh, n_state)                    !< gear 1 rotations relative to the carrier [rad]
  real(dp), intent(out) :: stiffness(n_mesh, n_state)               !< k_m [N/m]
  integer(ik), intent(out) :: n_pairs(n_mesh, n_state)              !< pairs in contact [-]
  integer(ik), intent(out) :: n_loaded(n_mesh, n_state)             !< pairs carrying load [-]
  real(dp), intent(out) :: position(max_pairs, n_mesh, n_state)     !< p_k, -1 unused [mesh cycles]
  integer(ik), intent(out) :: tooth(2, max_pairs, n_mesh, n_state)  !< i_k, j_k, -1 unused [-]
  integer(ik), intent(out) :: bad_state                             !< first failing state (1-based), 0 if none [-]
  integer(ik), intent(out) :: ierr                                  !< error code (0 = ok)
  type(tooth_contact_table), pointer :: table

  bad_state = 0
  call contact_table_at(handle, n_mesh, table, ierr, max_pairs)
  if (ierr /= ct_ok) return  ! outputs stay as f2py made them (zeros)
  call evaluate_contact_series(table, theta, stiffness, n_pairs, n_loaded, position, tooth, &
                               bad_state, ierr)
end subroutine contact_table_series

!> The displacement excitation e_m of every mesh at many states (0 without one).
subroutine contact_table_excitation(handle, n_state, n_mesh, theta, excitation, ierr)
  use kinds, only: dp, ik
  use contact_table, only: tooth_contact_table, contact_table_at, evaluate_excitation, ct_ok
  implicit none
  integer(ik), intent(in) :: handle                      !< handle from contact_table_create [-]
  integer(ik), intent(in) :: n_state                     !< number of states [-]
  integer(ik), intent(in) :: n_mesh                      !< number of meshes [-]
  real(dp), intent(in) :: theta(n_mesh, n_state)         !< gear 1 rotations relative to the carrier [rad]
  real(dp), intent(out) :: excitation(n_mesh, n_state)   !< e_m along the drive compression [m]
  integer(ik), intent(out) :: ierr                       !< error code (0 = ok)
  type(tooth_contact_table), pointer :: table
  integer(ik) :: t

  call contact_table_at(handle, n_mesh, table, ierr)
  if (ierr /= ct_ok) return
  do t = 1, n_state
    call evaluate_excitation(table, theta(:, t), excitation(:, t), ierr)
    if (ierr /= ct_ok) return
  end do
end subroutine contact_table_excitation

!> Timing loop for benchmarks: evaluates n_state states n_repeat times inside
!> one call and returns the wall time of the loop alone (system_clock).
subroutine contact_table_benchmark(handle, n_state, n_mesh, theta, n_repeat, elapsed, checksum, ierr)
  use kinds, only: dp, ik
  use contact_table, only: tooth_contact_table, contact_table_at, evaluate_contact, ct_ok
  implicit none
  integer(ik), intent(in) :: handle                   !< handle from contact_table_create [-]
  integer(ik), intent(in) :: n_state                  !< number of states [-]
  integer(ik), intent(in) :: n_mesh                   !< number of meshes [-]
  real(dp), intent(in) :: theta(n_mesh, n_state)      !< gear 1 rotations relative to the carrier [rad]
  integer(ik), intent(in) :: n_repeat                 !< passes over all states [-]
  real(dp), intent(out) :: elapsed                    !< wall time of all passes [s]
  real(dp), intent(out) :: checksum                   !< sum of every k_m, keeps the loop alive [N/m]
  integer(ik), intent(out) :: ierr                    !< error code (0 = ok)
  integer, parameter :: i8 = selected_int_kind(18)
  type(tooth_contact_table), pointer :: table
  integer(i8) :: start, finish, rate
  integer(ik) :: r, t
  real(dp), allocatable :: stiffness(:), position(:, :)
  integer(ik), allocatable :: n_pairs(:), n_loaded(:), tooth(:, :, :)

  checksum = 0.0_dp
  elapsed = 0.0_dp
  call contact_table_at(handle, n_mesh, table, ierr)
  if (ierr /= ct_ok) return
  allocate (stiffness(n_mesh), position(table%max_pairs, n_mesh), n_pairs(n_mesh), &
            n_loaded(n_mesh), tooth(2, table%max_pairs, n_mesh))
  call system_clock(start, rate)
  do r = 1, n_repeat
    do t = 1, n_state
      call evaluate_contact(table, theta(:, t), stiffness, n_pairs, n_loaded, position, tooth, ierr)
      if (ierr /= ct_ok) return
      checksum = checksum + sum(stiffness)
    end do
  end do
  call system_clock(finish)
  elapsed = real(finish - start, dp) / real(rate, dp)
end subroutine contact_table_benchmark
