!> The flat layer f2py sees for the rotor terms of a transient problem (module
!> newmark_gyroscopic): transient_problem_set_rotor attaches the gyroscopic matrix (its
!> strictly upper entries per unit reference speed), the speed source and the
!> unbalances to a problem created by transient_problem_create, before its first run.
!> Nothing is computed here.  Arrays hold at least one entry (f2py refuses empty
!> ones); the counts say how many are used.
subroutine transient_problem_set_rotor(handle, n, kd, n_mesh, n_entries, n_entries_stored, row, &
                                       column, value, source, n_samples, profile, n_speed, &
                                       speed_index, speed_value, n_unbalance, n_unbalance_stored, &
                                       unbalance_dof, unbalance, bad, ierr)
  use kinds, only: dp, ik
  use newmark_problem, only: transient_problem, transient_problem_at
  use newmark_support, only: solver_dense, solver_refined, ip_solver, nm_ok, nm_err_argument, &
                             nm_err_mass
  use newmark_gyroscopic, only: rotor_terms, attach_rotor_terms, rt_ok, rt_err_mass
  implicit none
  integer(ik), intent(in) :: handle                        !< handle from transient_problem_create [-]
  integer(ik), intent(in) :: n                             !< DOFs [-]
  integer(ik), intent(in) :: kd                            !< band subdiagonals [-]
  integer(ik), intent(in) :: n_mesh                        !< meshes [-]
  integer(ik), intent(in) :: n_entries                     !< entries of G used [-]
  integer(ik), intent(in) :: n_entries_stored              !< length of row, column, value (>= 1) [-]
  integer(ik), intent(in) :: row(n_entries_stored)         !< DOF i of G(i, j), kernel order, 1-based [-]
  integer(ik), intent(in) :: column(n_entries_stored)      !< DOF j [-]
  real(dp), intent(in) :: value(n_entries_stored)          !< G(i, j) = -G(j, i) per rad/s [kg m^2, kg m]
  integer(ik), intent(in) :: source                        !< 1 speed profile, 2 rotation w . v [-]
  integer(ik), intent(in) :: n_samples                     !< profile samples [-]
  real(dp), intent(in) :: profile(2, n_samples)            !< time [s], speed [rad/s]
  integer(ik), intent(in) :: n_speed                       !< entries of w [-]
  integer(ik), intent(in) :: speed_index(n_speed)          !< DOFs of w, 1-based [-]
  real(dp), intent(in) :: speed_value(n_speed)             !< w [rad/rad per DOF unit]
  integer(ik), intent(in) :: n_unbalance                   !< unbalances used [-]
  integer(ik), intent(in) :: n_unbalance_stored            !< columns of the unbalance arrays (>= 1) [-]
  integer(ik), intent(in) :: unbalance_dof(2, n_unbalance_stored) !< DOFs x, y, 1-based [-]
  real(dp), intent(in) :: unbalance(3, n_unbalance_stored) !< m e [kg m], angle [rad], speed ratio [-]
  integer(ik), intent(out) :: bad                          !< first wrong entry [-]
  integer(ik), intent(out) :: ierr                         !< error code (0 = ok)
  type(transient_problem), pointer :: problem
  type(rotor_terms) :: terms
  logical :: dense  ! the dense paths (inverse or refined) take the rotor share through M^-1

  bad = 0
  call transient_problem_at(handle, n, kd, n_mesh, problem, ierr)
  if (ierr /= nm_ok) return
  ierr = nm_err_argument
  if (n_entries < 0 .or. n_entries > n_entries_stored .or. n_unbalance < 0 .or. &
      n_unbalance > n_unbalance_stored) return
  terms%source = source
  terms%row = row(1:n_entries)
  terms%column = column(1:n_entries)
  terms%value = value(1:n_entries)
  allocate (terms%profile(3, n_samples))
  terms%profile(1:2, :) = profile
  terms%profile(3, :) = 0.0_dp
  terms%speed_index = speed_index
  terms%speed_value = speed_value
  terms%unbalance_dof = unbalance_dof(:, 1:n_unbalance)
  terms%unbalance = unbalance(:, 1:n_unbalance)
  dense = problem%iparam(ip_solver) == solver_dense .or. problem%iparam(ip_solver) == solver_refined
  call attach_rotor_terms(terms, n, kd, problem%mass_band, dense, bad, ierr)
  if (ierr /= rt_ok) then
    ierr = merge(nm_err_mass, nm_err_argument, ierr == rt_err_mass)
    return
  end if
  problem%rotor = terms
  ierr = nm_ok
end subroutine transient_problem_set_rotor
