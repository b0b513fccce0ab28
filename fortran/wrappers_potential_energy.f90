!> The flat layer f2py sees for the potential-energy tooth stiffness (module
!> tooth_potential_energy): explicit-shape arrays, sizes passed in, error codes out.
!> The fixed sizes 12, 8, 16 and 9 are the module's n_gear_param, n_fault_param,
!> n_geometry_out and n_compliance_out.
!>
!> gear(:, g): teeth, base radius, tip radius, root radius, root form radius [m], half
!>   tooth angle at the base circle along the involute [rad], base helix angle [rad],
!>   face width [m], bore radius [m] (0: rigid foundation), Young's modulus [Pa],
!>   Poisson's ratio [-], internal (0 or 1).
!> mesh: operating centre distance [m], working transverse pressure angle [rad].
!> fault: kind (0 none, 1 crack, 2 spall, 3 chip), gear (1 or 2), start along the face
!>   [m], width along the face [m], then crack: depth [m], angle [rad]; spall: centre
!>   radius [m], length along the profile [m], depth [m]; chip: missing height fraction.
!> bad_param: 100 g + index of a gear parameter, 300 + index of a mesh parameter,
!>   1000 + index of a fault parameter,
!>   2000 + index of a contact radius, 0 when the error is not tied to one entry.

subroutine pe_mesh_geometry(gear, mesh, summary, bad_param, ierr)
  use kinds, only: dp, ik
  use tooth_potential_energy, only: mesh_geometry_summary
  implicit none
  real(dp), intent(in) :: gear(12, 2)         !< gear parameters (see above) [m, rad, Pa, -]
  real(dp), intent(in) :: mesh(2)             !< centre distance [m], alpha_wt [rad]
  real(dp), intent(out) :: summary(16)        !< eps_a, eps_b, p_b, a_w, alpha_w, radii, ... [-, m, rad]
  integer(ik), intent(out) :: bad_param       !< the bad entry, 0 if none [-]
  integer(ik), intent(out) :: ierr            !< error code (0 = ok)
  call mesh_geometry_summary(gear, mesh, summary, bad_param, ierr)
end subroutine pe_mesh_geometry

subroutine pe_mesh_stiffness(gear, mesh, fault, n_sample, n_cycle, n_window, n_slice, n_quad, &
                             pair_healthy, pair_faulty, breakdown, mesh_healthy, mesh_faulty, &
                             bad_param, ierr)
  use kinds, only: dp, ik
  use tooth_potential_energy, only: mesh_stiffness_curves
  implicit none
  real(dp), intent(in) :: gear(12, 2)                    !< gear parameters [m, rad, Pa, -]
  real(dp), intent(in) :: mesh(2)                        !< centre distance [m], alpha_wt [rad]
  real(dp), intent(in) :: fault(8)                       !< packed fault [-, -, m, m, m or rad]
  integer(ik), intent(in) :: n_sample                    !< samples of the pair curves [-]
  integer(ik), intent(in) :: n_cycle                     !< samples per mesh cycle [-]
  integer(ik), intent(in) :: n_window                    !< cycles of the damaged pass (>= eps) [-]
  integer(ik), intent(in) :: n_slice                     !< face-width slices (helical) [-]
  integer(ik), intent(in) :: n_quad                      !< Gauss points per segment [-]
  real(dp), intent(out) :: pair_healthy(n_sample)        !< healthy pair [N/m]
  real(dp), intent(out) :: pair_faulty(n_sample)         !< pair holding the damaged tooth [N/m]
  real(dp), intent(out) :: breakdown(9, n_sample)        !< spur compliances [m/N]
  real(dp), intent(out) :: mesh_healthy(n_cycle)         !< mesh stiffness over a cycle [N/m]
  real(dp), intent(out) :: mesh_faulty(n_cycle * n_window) !< mesh stiffness, damaged pass [N/m]
  integer(ik), intent(out) :: bad_param                  !< the bad entry, 0 if none [-]
  integer(ik), intent(out) :: ierr                       !< error code (0 = ok)
  call mesh_stiffness_curves(gear, mesh, fault, n_sample, n_cycle, n_window, n_slice, n_quad, &
                             pair_healthy, pair_faulty, breakdown, mesh_healthy, mesh_faulty, &
                             bad_param, ierr)
end subroutine pe_mesh_stiffness

subroutine pe_tooth_compliance(gear, fault, n_point, contact_radius, n_quad, compliance, &
                               load_angle, bad_param, ierr)
  use kinds, only: dp, ik
  use tooth_potential_energy, only: tooth_compliance
  implicit none
  real(dp), intent(in) :: gear(12)                  !< one gear's parameters [m, rad, Pa, -]
  real(dp), intent(in) :: fault(8)                  !< packed fault on this tooth [-, -, m, m, m or rad]
  integer(ik), intent(in) :: n_point                !< contact points [-]
  real(dp), intent(in) :: contact_radius(n_point)   !< contact radii [m]
  integer(ik), intent(in) :: n_quad                 !< Gauss points per segment [-]
  real(dp), intent(out) :: compliance(4, n_point)   !< bending, shear, axial, foundation [m/N]
  real(dp), intent(out) :: load_angle(n_point)      !< load angle [rad]
  integer(ik), intent(out) :: bad_param             !< the bad entry, 0 if none [-]
  integer(ik), intent(out) :: ierr                  !< error code (0 = ok)
  call tooth_compliance(gear, fault, n_point, contact_radius, n_quad, compliance, load_angle, &
                        bad_param, ierr)
end subroutine pe_tooth_compliance
