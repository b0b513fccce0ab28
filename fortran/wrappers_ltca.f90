!> The flat layer f2py sees for the loaded tooth contact analysis (module ltca):
!> explicit-shape arrays, sizes passed in, error codes out.
!>
!> Arrays over (slice, pair, position) hold, for slice i of tooth pair k at mesh
!> position j, its structural and Hertz compliance, whether it lies on the path of
!> contact, and its initial separation along the transverse line of action.
!> bad_param: 1 coupling, 2 c_struct, 3 c_hertz, 4 gap, 100 + l force(l); the position
!>   (1-based) for no contact or no convergence.

subroutine ltca_mesh(n_slice, n_pair, n_pos, n_load, c_struct, c_hertz, in_path, gap, &
                     coupling, force, te_unloaded, te_loaded, load, iterations, bad_param, ierr)
  use kinds, only: dp, ik
  use ltca, only: ltca_solve
  implicit none
  integer(ik), intent(in) :: n_slice                              !< slices along the face [-]
  integer(ik), intent(in) :: n_pair                               !< tooth pairs considered [-]
  integer(ik), intent(in) :: n_pos                                !< mesh positions [-]
  integer(ik), intent(in) :: n_load                               !< loads [-]
  real(dp), intent(in) :: c_struct(n_slice, n_pair, n_pos)        !< structural slice compliance [m/N]
  real(dp), intent(in) :: c_hertz(n_slice, n_pair, n_pos)         !< Hertz slice compliance [m/N]
  integer(ik), intent(in) :: in_path(n_slice, n_pair, n_pos)      !< 1: slice on the path [-]
  real(dp), intent(in) :: gap(n_slice, n_pair, n_pos)             !< initial separation [m]
  real(dp), intent(in) :: coupling                                !< (lambda / w)^2 [-]
  real(dp), intent(in) :: force(n_load)                           !< transmitted force [N]
  real(dp), intent(out) :: te_unloaded(n_pos)                     !< unloaded TE [m]
  real(dp), intent(out) :: te_loaded(n_pos, n_load)               !< loaded TE [m]
  real(dp), intent(out) :: load(n_slice, n_pair, n_pos, n_load)   !< slice loads [N]
  integer(ik), intent(out) :: iterations(n_pos, n_load)           !< active-set iterations [-]
  integer(ik), intent(out) :: bad_param                           !< offending entry, 0 if none [-]
  integer(ik), intent(out) :: ierr                                !< error code (0 = ok)
  call ltca_solve(n_slice, n_pair, n_pos, n_load, c_struct, c_hertz, in_path, gap, coupling, &
                  force, te_unloaded, te_loaded, load, iterations, bad_param, ierr)
end subroutine ltca_mesh
