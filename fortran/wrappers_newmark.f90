!> The flat layer f2py sees for the banded Newmark integrator (modules newmark and
!> newmark_problem): explicit-shape arrays, sizes passed in, error code last.  Nothing
!> is computed here.  transient_problem_create takes the matrices, settings, meshes
!> (with a contact-table handle) and loads once and returns a problem handle (the
!> matrices as bands, or, on the sparse path, kd = 0 and the sparse_* arrays);
!> transient_start factors Khat and finds the initial acceleration; transient_advance
!> runs a chunk of steps and returns the whole state, so Python can show progress,
!> stop between chunks and checkpoint.  Layouts of rparam, iparam, rstate and istate
!> are documented in fortran/newmark_support.f90 and mirrored in Python
!> (newmark_support.py).

subroutine transient_problem_create(n, kd, mass_band, damping_band, stiffness_band, rparam, iparam, &
                                    n_mesh, mesh_ptr, n_mesh_nz, mesh_index, mesh_value, angle_ptr, &
                                    n_angle_nz, angle_index, angle_value, mean_stiffness, &
                                    contact_sign, backlash, coast_phase, mesh_damping, &
                                    table_handle, load_ptr, &
                                    n_load_nz, load_index, &
                                    load_value, law_kind, law_param, law_start, law_size, n_table, &
                                    law_table, n_sparse_nz, sparse_column_start, &
                                    sparse_row_index, sparse_mass, sparse_damping, &
                                    sparse_stiffness, handle, bad, ierr)
  use kinds, only: dp, ik
  use newmark_support, only: sparse_rows, torque_laws
  use newmark_problem, only: transient_problem, create_transient_problem
  use newmark_sparse, only: sparse_operators
  implicit none
  integer(ik), intent(in) :: n                          !< DOFs [-]
  integer(ik), intent(in) :: kd                         !< band subdiagonals [-]
  real(dp), intent(in) :: mass_band(kd + 1, n)          !< M [kg, kg m^2]
  real(dp), intent(in) :: damping_band(kd + 1, n)       !< C [N s/m, N m s/rad]
  real(dp), intent(in) :: stiffness_band(kd + 1, n)     !< K0 [N/m, N m/rad]
  real(dp), intent(in) :: rparam(10)                    !< real settings (see layout) [SI]
  integer(ik), intent(in) :: iparam(7)                  !< integer settings (see layout) [-]
  integer(ik), intent(in) :: n_mesh                     !< meshes [-]
  integer(ik), intent(in) :: mesh_ptr(n_mesh + 1)       !< b_m in mesh_*(ptr(m)+1 : ptr(m+1)) [-]
  integer(ik), intent(in) :: n_mesh_nz                  !< entries of all b_m [-]
  integer(ik), intent(in) :: mesh_index(n_mesh_nz)      !< DOF of each entry (1-based) [-]
  real(dp), intent(in) :: mesh_value(n_mesh_nz)         !< b entries [m/m, m/rad]
  integer(ik), intent(in) :: angle_ptr(n_mesh + 1)      !< theta_m weights, as mesh_ptr [-]
  integer(ik), intent(in) :: n_angle_nz                 !< entries of all weights [-]
  integer(ik), intent(in) :: angle_index(n_angle_nz)    !< DOF of each weight [-]
  real(dp), intent(in) :: angle_value(n_angle_nz)       !< weights [rad/rad]
  real(dp), intent(in) :: mean_stiffness(n_mesh)        !< kbar_m [N/m]
  integer(ik), intent(in) :: contact_sign(n_mesh)       !< s_m = +1 or -1 [-]
  real(dp), intent(in) :: backlash(n_mesh)              !< b_m >= 0 on the line of action, +inf none [m]
  real(dp), intent(in) :: coast_phase(n_mesh)           !< coast-flank phase offset [mesh cycles]
  real(dp), intent(in) :: mesh_damping(n_mesh)          !< c_m, each mesh's damper inside C [N s/m]
  integer(ik), intent(in) :: table_handle               !< contact table (contact_table_create), 0 none [-]
  integer(ik), intent(in) :: load_ptr(3)                !< input (1) and output (2) member vectors [-]
  integer(ik), intent(in) :: n_load_nz                  !< entries of both [-]
  integer(ik), intent(in) :: load_index(n_load_nz)      !< DOF of each entry [-]
  real(dp), intent(in) :: load_value(n_load_nz)         !< member rotation per DOF [rad/rad]
  integer(ik), intent(in) :: law_kind(2)                !< drive and load law codes [-]
  real(dp), intent(in) :: law_param(4, 2)               !< drive and load law parameters [SI]
  integer(ik), intent(in) :: law_start(2)               !< table offsets in law_table [-]
  integer(ik), intent(in) :: law_size(2)                !< table samples [-]
  integer(ik), intent(in) :: n_table                    !< columns of law_table [-]
  real(dp), intent(in) :: law_table(2, n_table)         !< (time [s], torque [N m]) samples
  integer(ik), intent(in) :: n_sparse_nz                !< stored entries of the sparse pattern [-]
  integer(ik), intent(in) :: sparse_column_start(n + 1) !< 0-based CSC column pointers (sparse path) [-]
  integer(ik), intent(in) :: sparse_row_index(n_sparse_nz) !< 0-based rows, lower triangle [-]
  real(dp), intent(in) :: sparse_mass(n_sparse_nz)      !< M on the pattern [kg, kg m^2]
  real(dp), intent(in) :: sparse_damping(n_sparse_nz)   !< C on the pattern [N s/m, N m s/rad]
  real(dp), intent(in) :: sparse_stiffness(n_sparse_nz) !< K0 on the pattern [N/m, N m/rad]
  integer(ik), intent(out) :: handle                    !< the problem's handle, 0 on error [-]
  integer(ik), intent(out) :: bad                       !< offending index for ierr [-]
  integer(ik), intent(out) :: ierr                      !< error code (0 = ok)
  call create_transient_problem(transient_problem(n=n, kd=kd, n_mesh=n_mesh, mass_band=mass_band, &
                                                  damping_band=damping_band, &
                                                  stiffness_band=stiffness_band, rparam=rparam, &
                                                  iparam=iparam, &
                                                  mesh=sparse_rows(mesh_ptr, mesh_index, mesh_value), &
                                                  angle=sparse_rows(angle_ptr, angle_index, angle_value), &
                                                  mean_stiffness=mean_stiffness, &
                                                  contact_sign=contact_sign, &
                                                  backlash=backlash, coast_phase=coast_phase, &
                                                  mesh_damping=mesh_damping, &
                                                  members=sparse_rows(load_ptr, load_index, load_value), &
                                                  laws=torque_laws(law_kind, law_param, law_start, &
                                                                   law_size, law_table), &
                                                  sparse=sparse_operators( &
                                                  n=n, column_start=sparse_column_start, &
                                                  row_index=sparse_row_index, mass=sparse_mass, &
                                                  damping=sparse_damping, &
                                                  stiffness=sparse_stiffness)), &
                                table_handle, handle, bad, ierr)
end subroutine transient_problem_create

subroutine transient_problem_free(handle, ierr)
  use kinds, only: ik
  use newmark_problem, only: free_transient_problem
  implicit none
  integer(ik), intent(in) :: handle   !< handle from transient_problem_create [-]
  integer(ik), intent(out) :: ierr    !< error code (0 = ok)
  call free_transient_problem(handle, ierr)
end subroutine transient_problem_free

subroutine transient_start(handle, n, kd, n_mesh, q, v, a, k_used, mesh_var, k_factored, &
                           khat_factor, rstate, istate, bad, ierr)
  use kinds, only: dp, ik
  use newmark_problem, only: transient_problem, transient_problem_at
  use newmark, only: newmark_start
  implicit none
  integer(ik), intent(in) :: handle                    !< handle from transient_problem_create [-]
  integer(ik), intent(in) :: n                         !< DOFs [-]
  integer(ik), intent(in) :: kd                        !< band subdiagonals [-]
  integer(ik), intent(in) :: n_mesh                    !< meshes [-]
  real(dp), intent(in) :: q(n)                         !< initial displacements [m, rad]
  real(dp), intent(in) :: v(n)                         !< initial velocities [m/s, rad/s]
  real(dp), intent(out) :: a(n)                        !< initial accelerations [m/s^2, rad/s^2]
  real(dp), intent(out) :: k_used(n_mesh)              !< mesh stiffness in force [N/m]
  real(dp), intent(out) :: mesh_var(n_mesh)            !< equivalent mesh load N_m at the state [N]
  real(dp), intent(out) :: k_factored(n_mesh)          !< stiffness in the factor kf_m [N/m]
  real(dp), intent(out) :: khat_factor(kd + 1, n)      !< Cholesky factor of Khat [N/m]
  real(dp), intent(out) :: rstate(3)                   !< t_s [s], drive and load torque [N m]
  integer(ik), intent(out) :: istate(10)                !< counters (see layout) [-]
  integer(ik), intent(out) :: bad                      !< offending index for ierr [-]
  integer(ik), intent(out) :: ierr                     !< error code (0 = ok)
  type(transient_problem), pointer :: problem

  bad = 0
  call transient_problem_at(handle, n, kd, n_mesh, problem, ierr)
  if (ierr /= 0) return
  call newmark_start(problem, q, v, a, k_used, mesh_var, k_factored, khat_factor, rstate, istate, &
                     bad, ierr)
end subroutine transient_start

subroutine transient_advance(handle, n, kd, n_mesh, n_probe, probe_kind, probe_ptr, n_probe_nz, &
                             probe_index, probe_value, n_steps, decimation, window_first_step, &
                             phase, tooth_offset, q, v, a, k_used, mesh_var, k_factored, &
                             khat_factor, velocity_sum, rstate, istate, max_samples, samples, &
                             n_samples, bad, ierr)
  use kinds, only: dp, ik
  use newmark_support, only: sparse_rows
  use newmark_problem, only: transient_problem, transient_problem_at
  use newmark, only: newmark_advance
  implicit none
  integer(ik), intent(in) :: handle                        !< handle from transient_problem_create [-]
  integer(ik), intent(in) :: n                             !< DOFs [-]
  integer(ik), intent(in) :: kd                            !< band subdiagonals [-]
  integer(ik), intent(in) :: n_mesh                        !< meshes [-]
  integer(ik), intent(in) :: n_probe                       !< probes [-]
  integer(ik), intent(in) :: probe_kind(n_probe)           !< probe codes [-]
  integer(ik), intent(in) :: probe_ptr(n_probe + 1)        !< probe weight pointers [-]
  integer(ik), intent(in) :: n_probe_nz                    !< entries of all weights [-]
  integer(ik), intent(in) :: probe_index(n_probe_nz)       !< DOF (or mesh) of each entry [-]
  real(dp), intent(in) :: probe_value(n_probe_nz)          !< weights [channel unit per DOF unit]
  integer(ik), intent(in) :: n_steps                       !< steps to advance [-]
  integer(ik), intent(in) :: decimation                    !< steps per recorded sample [-]
  integer(ik), intent(in) :: window_first_step             !< first step averaged, 0 none [-]
  real(dp), intent(in) :: phase(n_mesh)                    !< contact table gamma now [mesh cycles]
  integer(ik), intent(in) :: tooth_offset(2, n_mesh)       !< contact table i0, j0 now [-]
  real(dp), intent(inout) :: q(n)                          !< displacements [m, rad]
  real(dp), intent(inout) :: v(n)                          !< velocities [m/s, rad/s]
  real(dp), intent(inout) :: a(n)                          !< accelerations [m/s^2, rad/s^2]
  real(dp), intent(inout) :: k_used(n_mesh)                !< mesh stiffness in force [N/m]
  real(dp), intent(inout) :: mesh_var(n_mesh)              !< equivalent mesh load N_m at the state [N]
  real(dp), intent(inout) :: k_factored(n_mesh)            !< stiffness in the factor [N/m]
  real(dp), intent(inout) :: khat_factor(kd + 1, n)        !< factor of Khat at k_factored (banded path) [N/m]
  real(dp), intent(inout) :: velocity_sum(n)               !< sum of v over the window [m/s, rad/s]
  real(dp), intent(inout) :: rstate(3)                     !< t_s [s], drive, load torque [N m]
  integer(ik), intent(inout) :: istate(10)                  !< counters (see layout) [-]
  integer(ik), intent(in) :: max_samples                   !< columns of samples [-]
  real(dp), intent(inout) :: samples(n_probe, max_samples) !< recorded channels [channel units]
  integer(ik), intent(out) :: n_samples                    !< columns written [-]
  integer(ik), intent(out) :: bad                          !< offending DOF, mesh or index [-]
  integer(ik), intent(out) :: ierr                         !< error code (0 = ok)
  type(transient_problem), pointer :: problem

  n_samples = 0
  bad = 0
  call transient_problem_at(handle, n, kd, n_mesh, problem, ierr)
  if (ierr /= 0) return
  call newmark_advance(problem, probe_kind, sparse_rows(probe_ptr, probe_index, probe_value), &
                       n_steps, decimation, window_first_step, phase, tooth_offset, q, v, a, &
                       k_used, mesh_var, k_factored, khat_factor, velocity_sum, rstate, istate, &
                       samples, n_samples, bad, ierr)
end subroutine transient_advance
