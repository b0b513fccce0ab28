!> The flat layer f2py sees for rolling bearings in a transient problem (module
!> rolling_bearing): transient_problem_bearings attaches a problem's bearings, once,
!> after transient_problem_create and before the first transient_start.  A problem on
!> the dense paths take none (their operators hold only the meshes' load columns).
!> Nothing is computed here.

subroutine transient_problem_bearings(handle, n, kd, n_mesh, n_bearing, elements, param, &
                                      rows_ptr, n_rows_nz, rows_index, rows_value, n_defect, &
                                      defect, defect_value, bad, ierr)
  use kinds, only: dp, ik
  use newmark_support, only: sparse_rows, nm_err_argument, ip_solver, solver_dense, solver_refined
  use newmark_problem, only: transient_problem, transient_problem_at
  use rolling_bearing, only: bearing_set, check_bearing_set, n_bearing_param
  implicit none
  integer(ik), intent(in) :: handle                        !< handle from transient_problem_create [-]
  integer(ik), intent(in) :: n                             !< DOFs [-]
  integer(ik), intent(in) :: kd                            !< band subdiagonals [-]
  integer(ik), intent(in) :: n_mesh                        !< meshes [-]
  integer(ik), intent(in) :: n_bearing                     !< bearings [-]
  integer(ik), intent(in) :: elements(n_bearing)           !< Z per bearing [-]
  real(dp), intent(in) :: param(8, n_bearing)              !< constants per bearing (bp_* layout) [SI]
  integer(ik), intent(in) :: rows_ptr(4 * n_bearing + 1)   !< x, y, theta_i, theta_o rows per bearing [-]
  integer(ik), intent(in) :: n_rows_nz                     !< entries of all rows [-]
  integer(ik), intent(in) :: rows_index(n_rows_nz)         !< DOF of each entry (1-based) [-]
  real(dp), intent(in) :: rows_value(n_rows_nz)            !< entries [m/m, rad/rad]
  integer(ik), intent(in) :: n_defect                      !< defects (0: one inert entry) [-]
  integer(ik), intent(in) :: defect(3, max(n_defect, 1))   !< bearing, ring, kind per defect [-]
  real(dp), intent(in) :: defect_value(3, max(n_defect, 1)) !< phi [rad], w [rad] or N [-], h or A [m]
  integer(ik), intent(out) :: bad                          !< offending entry for ierr [-]
  integer(ik), intent(out) :: ierr                         !< error code (0 = ok)
  type(transient_problem), pointer :: problem
  type(bearing_set) :: set

  bad = 0
  call transient_problem_at(handle, n, kd, n_mesh, problem, ierr)
  if (ierr /= 0) return
  ierr = nm_err_argument
  if (n_bearing < 0 .or. n_defect < 0 .or. size(param, 1) /= n_bearing_param) return
  if ((problem%iparam(ip_solver) == solver_dense .or. problem%iparam(ip_solver) == solver_refined) &
      .and. n_bearing > 0) then
    bad = -2
    return
  end if
  set = bearing_set(n_bearing=n_bearing, elements=elements, param=param, &
                    rows=sparse_rows(rows_ptr, rows_index, rows_value), n_defect=n_defect, &
                    defect=defect(:, 1:n_defect), defect_value=defect_value(:, 1:n_defect))
  bad = check_bearing_set(set, n)
  if (bad /= 0) return
  problem%bearings = set
  ierr = 0
end subroutine transient_problem_bearings
