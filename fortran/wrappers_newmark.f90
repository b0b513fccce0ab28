!> The flat layer f2py sees for the banded Newmark integrator (module newmark):
!> explicit-shape arrays, sizes passed in, error code last.  Nothing is computed here.
!> transient_start factors Khat and finds the initial acceleration; transient_advance
!> runs a chunk of steps and returns the whole state, so Python can show progress,
!> stop between chunks and checkpoint.  Layouts of rparam, iparam, rstate and istate
!> are documented in fortran/newmark.f90 and mirrored in pygear/newmark.py.

subroutine transient_start(n, kd, mass_band, damping_band, stiffness_band, rparam, iparam, &
    n_mesh, mesh_ptr, n_mesh_nz, mesh_index, mesh_value, angle_ptr, &
    n_angle_nz, angle_index, angle_value, mean_stiffness, contact_sign, &
    teeth, cycle_sign, tooth_offset, contact_ratio, end_to_peak, phase, law, &
    curve_start, curve_size, n_curve, curve, factor_start, n_factor, factor, &
    max_pairs, load_ptr, n_load_nz, load_index, load_value, law_kind, &
    law_param, law_start, law_size, n_table, law_table, q, v, a, k_used, &
    mesh_var, k_factored, khat_band, khat_factor, rstate, istate, bad, ierr)
  use kinds, only: dp, ik
  use newmark, only: newmark_start
  implicit none
  integer(ik), intent(in) :: n                                 !< DOFs [-]
  integer(ik), intent(in) :: kd                                !< band subdiagonals [-]
  real(dp), intent(in) :: mass_band(kd + 1, n)                 !< M [kg, kg m^2]
  real(dp), intent(in) :: damping_band(kd + 1, n)              !< C [N s/m, N m s/rad]
  real(dp), intent(in) :: stiffness_band(kd + 1, n)            !< K0 [N/m, N m/rad]
  real(dp), intent(in) :: rparam(10)                           !< real settings (see layout) [SI]
  integer(ik), intent(in) :: iparam(8)                         !< integer settings (see layout) [-]
  integer(ik), intent(in) :: n_mesh                            !< meshes [-]
  integer(ik), intent(in) :: mesh_ptr(n_mesh + 1)              !< b_m in mesh_*(ptr(m)+1 : ptr(m+1)) [-]
  integer(ik), intent(in) :: n_mesh_nz                         !< entries of all b_m [-]
  integer(ik), intent(in) :: mesh_index(n_mesh_nz)             !< DOF of each entry (1-based) [-]
  real(dp), intent(in) :: mesh_value(n_mesh_nz)                !< b entries [m/m, m/rad]
  integer(ik), intent(in) :: angle_ptr(n_mesh + 1)             !< theta_m weights, as mesh_ptr [-]
  integer(ik), intent(in) :: n_angle_nz                        !< entries of all weights [-]
  integer(ik), intent(in) :: angle_index(n_angle_nz)           !< DOF of each weight [-]
  real(dp), intent(in) :: angle_value(n_angle_nz)              !< weights [rad/rad]
  real(dp), intent(in) :: mean_stiffness(n_mesh)               !< kbar_m [N/m]
  integer(ik), intent(in) :: contact_sign(n_mesh)              !< s_m = +1 or -1 [-]
  integer(ik), intent(in) :: teeth(2, n_mesh)                  !< contact table: Z1, Z2 [-]
  integer(ik), intent(in) :: cycle_sign(n_mesh)                !< contact table: sigma [-]
  integer(ik), intent(in) :: tooth_offset(2, n_mesh)           !< contact table: i0, j0 [-]
  real(dp), intent(in) :: contact_ratio(n_mesh)                !< contact table: eps [-]
  real(dp), intent(in) :: end_to_peak(n_mesh)                  !< contact table: lambda [-]
  real(dp), intent(in) :: phase(n_mesh)                        !< contact table: gamma [cycles]
  integer(ik), intent(in) :: law(n_mesh)                       !< contact table: pair law [-]
  integer(ik), intent(in) :: curve_start(n_mesh)               !< contact table: curve offsets [-]
  integer(ik), intent(in) :: curve_size(n_mesh)                !< contact table: curve sizes [-]
  integer(ik), intent(in) :: n_curve                           !< contact table: size of curve [-]
  real(dp), intent(in) :: curve(n_curve)                       !< contact table: curves [-]
  integer(ik), intent(in) :: factor_start(2, n_mesh)           !< contact table: factor offsets [-]
  integer(ik), intent(in) :: n_factor                          !< contact table: size of factor [-]
  real(dp), intent(in) :: factor(n_factor)                     !< contact table: tooth factors [-]
  integer(ik), intent(in) :: max_pairs                         !< contact table: pairs per mesh [-]
  integer(ik), intent(in) :: load_ptr(3)                       !< input (1) and output (2) member vectors [-]
  integer(ik), intent(in) :: n_load_nz                         !< entries of both [-]
  integer(ik), intent(in) :: load_index(n_load_nz)             !< DOF of each entry [-]
  real(dp), intent(in) :: load_value(n_load_nz)                !< member rotation per DOF [rad/rad]
  integer(ik), intent(in) :: law_kind(2)                       !< drive and load law codes [-]
  real(dp), intent(in) :: law_param(4, 2)                      !< drive and load law parameters [SI]
  integer(ik), intent(in) :: law_start(2)                      !< table offsets in law_table [-]
  integer(ik), intent(in) :: law_size(2)                       !< table samples [-]
  integer(ik), intent(in) :: n_table                           !< columns of law_table [-]
  real(dp), intent(in) :: law_table(2, n_table)                !< (time [s], torque [N m]) samples
  real(dp), intent(in) :: q(n)                                 !< initial displacements [m, rad]
  real(dp), intent(in) :: v(n)                                 !< initial velocities [m/s, rad/s]
  real(dp), intent(out) :: a(n)                                !< initial accelerations [m/s^2, rad/s^2]
  real(dp), intent(out) :: k_used(n_mesh)                      !< mesh stiffness in force [N/m]
  real(dp), intent(out) :: mesh_var(n_mesh)                    !< (k_m - kbar_m) delta_m [N]
  real(dp), intent(out) :: k_factored(n_mesh)                  !< stiffness in the factor kf_m [N/m]
  real(dp), intent(out) :: khat_band(kd + 1, n)                !< Khat at mean stiffness [N/m]
  real(dp), intent(out) :: khat_factor(kd + 1, n)              !< its Cholesky factor
  real(dp), intent(out) :: rstate(3)                           !< t_s [s], drive and load torque [N m]
  integer(ik), intent(out) :: istate(9)                        !< counters (see layout) [-]
  integer(ik), intent(out) :: bad                              !< offending index for ierr [-]
  integer(ik), intent(out) :: ierr                             !< error code (0 = ok)
  call newmark_start(n, kd, mass_band, damping_band, stiffness_band, rparam, iparam, &
    n_mesh, mesh_ptr, n_mesh_nz, mesh_index, mesh_value, angle_ptr, &
    n_angle_nz, angle_index, angle_value, mean_stiffness, contact_sign, &
    teeth, cycle_sign, tooth_offset, contact_ratio, end_to_peak, phase, law, &
    curve_start, curve_size, n_curve, curve, factor_start, n_factor, factor, &
    max_pairs, load_ptr, n_load_nz, load_index, load_value, law_kind, &
    law_param, law_start, law_size, n_table, law_table, q, v, a, k_used, &
    mesh_var, k_factored, khat_band, khat_factor, rstate, istate, bad, ierr)
end subroutine transient_start

subroutine transient_advance(n, kd, mass_band, damping_band, stiffness_band, khat_band, &
    khat_factor, rparam, iparam, n_mesh, mesh_ptr, n_mesh_nz, mesh_index, &
    mesh_value, angle_ptr, n_angle_nz, angle_index, angle_value, &
    mean_stiffness, contact_sign, teeth, cycle_sign, tooth_offset, &
    contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
    n_curve, curve, factor_start, n_factor, factor, max_pairs, load_ptr, &
    n_load_nz, load_index, load_value, law_kind, law_param, law_start, &
    law_size, n_table, law_table, n_probe, probe_kind, probe_ptr, &
    n_probe_nz, probe_index, probe_value, n_steps, q, v, a, k_used, &
    mesh_var, k_factored, velocity_sum, rstate, istate, max_samples, &
    samples, n_samples, bad, ierr)
  use kinds, only: dp, ik
  use newmark, only: newmark_advance
  implicit none
  integer(ik), intent(in) :: n                                 !< DOFs [-]
  integer(ik), intent(in) :: kd                                !< band subdiagonals [-]
  real(dp), intent(in) :: mass_band(kd + 1, n)                 !< M [kg, kg m^2]
  real(dp), intent(in) :: damping_band(kd + 1, n)              !< C [N s/m, N m s/rad]
  real(dp), intent(in) :: stiffness_band(kd + 1, n)            !< K0 [N/m, N m/rad]
  real(dp), intent(in) :: khat_band(kd + 1, n)                 !< Khat at mean stiffness [N/m]
  real(dp), intent(inout) :: khat_factor(kd + 1, n)            !< factor of Khat at k_factored
  real(dp), intent(in) :: rparam(10)                           !< real settings [SI]
  integer(ik), intent(in) :: iparam(8)                         !< integer settings [-]
  integer(ik), intent(in) :: n_mesh                            !< meshes [-]
  integer(ik), intent(in) :: mesh_ptr(n_mesh + 1)              !< b_m pointers [-]
  integer(ik), intent(in) :: n_mesh_nz                         !< entries of all b_m [-]
  integer(ik), intent(in) :: mesh_index(n_mesh_nz)             !< DOF of each entry [-]
  real(dp), intent(in) :: mesh_value(n_mesh_nz)                !< b entries [m/m, m/rad]
  integer(ik), intent(in) :: angle_ptr(n_mesh + 1)             !< theta_m weight pointers [-]
  integer(ik), intent(in) :: n_angle_nz                        !< entries of all weights [-]
  integer(ik), intent(in) :: angle_index(n_angle_nz)           !< DOF of each weight [-]
  real(dp), intent(in) :: angle_value(n_angle_nz)              !< weights [rad/rad]
  real(dp), intent(in) :: mean_stiffness(n_mesh)               !< kbar_m [N/m]
  integer(ik), intent(in) :: contact_sign(n_mesh)              !< s_m [-]
  integer(ik), intent(in) :: teeth(2, n_mesh)                  !< contact table: Z1, Z2 [-]
  integer(ik), intent(in) :: cycle_sign(n_mesh)                !< contact table: sigma [-]
  integer(ik), intent(in) :: tooth_offset(2, n_mesh)           !< contact table: i0, j0 [-]
  real(dp), intent(in) :: contact_ratio(n_mesh)                !< contact table: eps [-]
  real(dp), intent(in) :: end_to_peak(n_mesh)                  !< contact table: lambda [-]
  real(dp), intent(in) :: phase(n_mesh)                        !< contact table: gamma [cycles]
  integer(ik), intent(in) :: law(n_mesh)                       !< contact table: pair law [-]
  integer(ik), intent(in) :: curve_start(n_mesh)               !< contact table: curve offsets [-]
  integer(ik), intent(in) :: curve_size(n_mesh)                !< contact table: curve sizes [-]
  integer(ik), intent(in) :: n_curve                           !< contact table: size of curve [-]
  real(dp), intent(in) :: curve(n_curve)                       !< contact table: curves [-]
  integer(ik), intent(in) :: factor_start(2, n_mesh)           !< contact table: factor offsets [-]
  integer(ik), intent(in) :: n_factor                          !< contact table: size of factor [-]
  real(dp), intent(in) :: factor(n_factor)                     !< contact table: tooth factors [-]
  integer(ik), intent(in) :: max_pairs                         !< contact table: pairs per mesh [-]
  integer(ik), intent(in) :: load_ptr(3)                       !< input/output member pointers [-]
  integer(ik), intent(in) :: n_load_nz                         !< entries of both [-]
  integer(ik), intent(in) :: load_index(n_load_nz)             !< DOF of each entry [-]
  real(dp), intent(in) :: load_value(n_load_nz)                !< member rotation per DOF [rad/rad]
  integer(ik), intent(in) :: law_kind(2)                       !< drive and load law codes [-]
  real(dp), intent(in) :: law_param(4, 2)                      !< law parameters [SI]
  integer(ik), intent(in) :: law_start(2)                      !< table offsets [-]
  integer(ik), intent(in) :: law_size(2)                       !< table samples [-]
  integer(ik), intent(in) :: n_table                           !< columns of law_table [-]
  real(dp), intent(in) :: law_table(2, n_table)                !< (time [s], torque [N m])
  integer(ik), intent(in) :: n_probe                           !< probes [-]
  integer(ik), intent(in) :: probe_kind(n_probe)               !< probe codes [-]
  integer(ik), intent(in) :: probe_ptr(n_probe + 1)            !< probe weight pointers [-]
  integer(ik), intent(in) :: n_probe_nz                        !< entries of all weights [-]
  integer(ik), intent(in) :: probe_index(n_probe_nz)           !< DOF (or mesh) of each entry [-]
  real(dp), intent(in) :: probe_value(n_probe_nz)              !< weights [channel unit per DOF unit]
  integer(ik), intent(in) :: n_steps                           !< steps to advance [-]
  real(dp), intent(inout) :: q(n)                              !< displacements [m, rad]
  real(dp), intent(inout) :: v(n)                              !< velocities [m/s, rad/s]
  real(dp), intent(inout) :: a(n)                              !< accelerations [m/s^2, rad/s^2]
  real(dp), intent(inout) :: k_used(n_mesh)                    !< mesh stiffness in force [N/m]
  real(dp), intent(inout) :: mesh_var(n_mesh)                  !< (k_m - kbar_m) delta_m [N]
  real(dp), intent(inout) :: k_factored(n_mesh)                !< stiffness in the factor [N/m]
  real(dp), intent(inout) :: velocity_sum(n)                   !< sum of v over the window [m/s, rad/s]
  real(dp), intent(inout) :: rstate(3)                         !< t_s [s], drive, load torque [N m]
  integer(ik), intent(inout) :: istate(9)                      !< counters (see layout) [-]
  integer(ik), intent(in) :: max_samples                       !< columns of samples [-]
  real(dp), intent(inout) :: samples(n_probe, max_samples)     !< recorded channels [channel units]
  integer(ik), intent(out) :: n_samples                        !< columns written [-]
  integer(ik), intent(out) :: bad                              !< offending DOF, mesh or index [-]
  integer(ik), intent(out) :: ierr                             !< error code (0 = ok)
  call newmark_advance(n, kd, mass_band, damping_band, stiffness_band, khat_band, &
    khat_factor, rparam, iparam, n_mesh, mesh_ptr, n_mesh_nz, mesh_index, &
    mesh_value, angle_ptr, n_angle_nz, angle_index, angle_value, &
    mean_stiffness, contact_sign, teeth, cycle_sign, tooth_offset, &
    contact_ratio, end_to_peak, phase, law, curve_start, curve_size, &
    n_curve, curve, factor_start, n_factor, factor, max_pairs, load_ptr, &
    n_load_nz, load_index, load_value, law_kind, law_param, law_start, &
    law_size, n_table, law_table, n_probe, probe_kind, probe_ptr, &
    n_probe_nz, probe_index, probe_value, n_steps, q, v, a, k_used, &
    mesh_var, k_factored, velocity_sum, rstate, istate, max_samples, &
    samples, n_samples, bad, ierr)
end subroutine transient_advance
