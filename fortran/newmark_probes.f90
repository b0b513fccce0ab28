!> The output channels of the Newmark kernel (module newmark): one column of probe values
!> per recorded step.  Linear probes are weights over the DOFs; mesh probes name a mesh
!> and read its force or stiffness in force (with tooth separation the flank force of
!> module flank_contact: drive > 0, free 0, coast < 0).  The force is the spring's and
!> the mesh damper's together, F = k c + c_m s_m b_m . v while the flanks touch
!> (c the compression of the flank in contact), and 0 while they are apart; c_m is the
!> damper the step used (c_used).  A mesh with a displacement excitation e_m (module
!> contact_table) has the compression s_m delta_m - e_m (shift = s_m e_m along delta_m).
module newmark_probes
  use kinds, only: dp, ik
  use newmark_support, only: sparse_rows, probe_displacement, probe_velocity, &
                             probe_acceleration, probe_mesh_force, probe_mesh_stiffness, &
                             probe_drive_torque, probe_load_torque, rs_drive, rs_load, &
                             n_rstate, ip_separation, nm_err_size
  use newmark_problem, only: transient_problem
  implicit none
  private

  public :: record_probes

contains

  !> Append one column of probe values to samples.
  pure subroutine record_probes(problem, probe_kind, probes, x, xd, xdd, k_used, c_used, rstate, &
                                samples, n_samples, ierr, shift)
    type(transient_problem), intent(in) :: problem     !< the problem
    integer(ik), intent(in) :: probe_kind(:)           !< probe codes [-]
    type(sparse_rows), intent(in) :: probes            !< probe weights (a mesh for mesh kinds) [-]
    real(dp), intent(in), contiguous :: x(:)           !< displacements [m, rad]
    real(dp), intent(in), contiguous :: xd(:)          !< velocities [m/s, rad/s]
    real(dp), intent(in), contiguous :: xdd(:)         !< accelerations [m/s^2, rad/s^2]
    real(dp), intent(in), contiguous :: k_used(:)      !< mesh stiffness in force [N/m]
    real(dp), intent(in), contiguous :: c_used(:)      !< mesh damper in force while touching [N s/m]
    real(dp), intent(in) :: rstate(n_rstate)           !< t_s [s], drive, load torque [N m]
    real(dp), intent(inout), contiguous :: samples(:, :) !< (probes, columns) channels [channel units]
    integer(ik), intent(inout) :: n_samples            !< columns written [-]
    integer(ik), intent(inout) :: ierr                 !< error code, nm_err_size when full
    real(dp), intent(in), optional :: shift(:)         !< s_m e_m of excited meshes along delta_m [m]
    integer(ik) :: p, m
    real(dp) :: d
    logical :: touching

    if (n_samples >= size(samples, 2)) then
      ierr = nm_err_size
      return
    end if
    n_samples = n_samples + 1
    do p = 1, int(size(probe_kind), ik)
      select case (probe_kind(p))
      case (probe_displacement)
        samples(p, n_samples) = dot(probes, p, x)
      case (probe_velocity)
        samples(p, n_samples) = dot(probes, p, xd)
      case (probe_acceleration)
        samples(p, n_samples) = dot(probes, p, xdd)
      case (probe_mesh_force)  ! F = k c (drive), 0 (free), k (c + b) (coast), + damper
        m = probes%index(probes%ptr(p) + 1)
        d = dot(problem%mesh, m, x)
        if (present(shift)) d = d - shift(m)
        d = real(problem%contact_sign(m), dp) * d
        touching = .true.
        if (problem%iparam(ip_separation) /= 0) then
          if (d < -problem%backlash(m)) then
            d = d + problem%backlash(m)
          else
            touching = d > 0.0_dp  ! as module flank_contact: free for -b <= c <= 0
            d = max(d, 0.0_dp)
          end if
        end if
        samples(p, n_samples) = k_used(m) * d
        if (touching .and. c_used(m) > 0.0_dp) &
          samples(p, n_samples) = samples(p, n_samples) + c_used(m) * &
                                  real(problem%contact_sign(m), dp) * dot(problem%mesh, m, xd)
      case (probe_mesh_stiffness)
        samples(p, n_samples) = k_used(probes%index(probes%ptr(p) + 1))
      case (probe_drive_torque)
        samples(p, n_samples) = rstate(rs_drive)
      case (probe_load_torque)
        samples(p, n_samples) = rstate(rs_load)
      case default
        samples(p, n_samples) = 0.0_dp
      end select
    end do

  contains

    !> w . x for row r of a packed set (newmark_support's sparse_dot, here so that the
    !> compiler inlines it: the probes are recorded every step).
    pure real(dp) function dot(rows, r, vector)
      type(sparse_rows), intent(in) :: rows  !< the packed set
      integer(ik), intent(in) :: r           !< row (1-based) [-]
      real(dp), intent(in), contiguous :: vector(:)  !< vector over the DOFs [DOF units]
      integer(ik) :: k
      dot = 0.0_dp
      do k = rows%ptr(r) + 1, rows%ptr(r + 1)
        dot = dot + rows%value(k) * vector(rows%index(k))
      end do
    end function dot
  end subroutine record_probes
end module newmark_probes
