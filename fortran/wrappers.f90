!> The flat layer f2py sees: explicit-shape arrays, no derived types, error codes out.
!> Each routine forwards to a kernel module; nothing is computed here.

subroutine central_mass_matrix(mass, tilt_inertia, polar_inertia, mass_translation, mass_rotation, ierr)
  use kinds, only: dp, ik
  use elements, only: central_mass
  implicit none
  real(dp), intent(in) :: mass                    !< body mass [kg]
  real(dp), intent(in) :: tilt_inertia            !< inertia about x and y [kg m^2]
  real(dp), intent(in) :: polar_inertia           !< inertia about z [kg m^2]
  real(dp), intent(out) :: mass_translation(6, 6) !< translational part [kg]
  real(dp), intent(out) :: mass_rotation(6, 6)    !< rotational part [kg m^2]
  integer(ik), intent(out) :: ierr                !< error code (0 = ok)
  call central_mass(mass, tilt_inertia, polar_inertia, mass_translation, mass_rotation, ierr)
end subroutine central_mass_matrix

subroutine planet_mass_matrix(formulation, mass, tilt_inertia, polar_inertia, carrier_radius, &
                              mass_translation, mass_rotation, ierr)
  use kinds, only: dp, ik
  use elements, only: planet_mass
  implicit none
  integer(ik), intent(in) :: formulation          !< 1 improved, 2 consistent, 3 lin-parker [-]
  real(dp), intent(in) :: mass                    !< planet mass [kg]
  real(dp), intent(in) :: tilt_inertia            !< inertia about zeta and eta [kg m^2]
  real(dp), intent(in) :: polar_inertia           !< inertia about its axis [kg m^2]
  real(dp), intent(in) :: carrier_radius          !< r_c [m]
  real(dp), intent(out) :: mass_translation(7, 7) !< translational part [kg, kg m, kg m^2]
  real(dp), intent(out) :: mass_rotation(7, 7)    !< rotational part [kg m^2]
  integer(ik), intent(out) :: ierr                !< error code (0 = ok)
  call planet_mass(formulation, mass, tilt_inertia, polar_inertia, carrier_radius, &
                   mass_translation, mass_rotation, ierr)
end subroutine planet_mass_matrix

subroutine central_bearing_springs(radial, axial, tilt, torsional, offset, deflection, stiffness, ierr)
  use kinds, only: dp, ik
  use elements, only: central_bearing
  implicit none
  real(dp), intent(in) :: radial              !< x and y stiffness [N/m]
  real(dp), intent(in) :: axial               !< z stiffness [N/m]
  real(dp), intent(in) :: tilt                !< tilting stiffness [N m/rad]
  real(dp), intent(in) :: torsional           !< torsional stiffness [N m/rad]
  real(dp), intent(in) :: offset(3)           !< member centre minus housing point [m]
  real(dp), intent(out) :: deflection(12, 6)  !< b vectors over [member, housing]
  real(dp), intent(out) :: stiffness(6)       !< spring stiffnesses [N/m, N m/rad]
  integer(ik), intent(out) :: ierr            !< error code (0 = ok)
  call central_bearing(radial, axial, tilt, torsional, offset, deflection, stiffness, ierr)
end subroutine central_bearing_springs

subroutine planet_bearing_springs(planet_angle, carrier_radius, radial, axial, tilt, &
                                  deflection, stiffness, ierr)
  use kinds, only: dp, ik
  use elements, only: planet_bearing
  implicit none
  real(dp), intent(in) :: planet_angle        !< psi_n [rad]
  real(dp), intent(in) :: carrier_radius      !< r_c [m]
  real(dp), intent(in) :: radial              !< radial and tangential stiffness [N/m]
  real(dp), intent(in) :: axial               !< axial stiffness [N/m]
  real(dp), intent(in) :: tilt                !< tilting stiffness [N m/rad]
  real(dp), intent(out) :: deflection(13, 5)  !< b vectors over [carrier, planet]
  real(dp), intent(out) :: stiffness(5)       !< spring stiffnesses [N/m, N m/rad]
  integer(ik), intent(out) :: ierr            !< error code (0 = ok)
  call planet_bearing(planet_angle, carrier_radius, radial, axial, tilt, deflection, stiffness, ierr)
end subroutine planet_bearing_springs

subroutine planetary_mesh_vector(mesh_kind, planet_angle, pressure_angle, base_radius_central, &
                                 base_radius_planet, carrier_radius, base_helix_angle, deflection, ierr)
  use kinds, only: dp, ik
  use elements, only: planetary_mesh
  implicit none
  integer(ik), intent(in) :: mesh_kind         !< 1 sun-planet, 2 ring-planet [-]
  real(dp), intent(in) :: planet_angle         !< psi_n [rad]
  real(dp), intent(in) :: pressure_angle       !< transverse pressure angle [rad]
  real(dp), intent(in) :: base_radius_central  !< sun or ring base radius [m]
  real(dp), intent(in) :: base_radius_planet   !< planet base radius [m]
  real(dp), intent(in) :: carrier_radius       !< r_c [m]
  real(dp), intent(in) :: base_helix_angle     !< signed base helix angle [rad]
  real(dp), intent(out) :: deflection(13)      !< b over [central, planet]
  integer(ik), intent(out) :: ierr             !< error code (0 = ok)
  call planetary_mesh(mesh_kind, planet_angle, pressure_angle, base_radius_central, &
                      base_radius_planet, carrier_radius, base_helix_angle, deflection, ierr)
end subroutine planetary_mesh_vector

subroutine parallel_mesh_vector(centre_angle, pressure_angle, base_radius_1, base_radius_2, &
                                base_helix_angle, deflection, ierr)
  use kinds, only: dp, ik
  use elements, only: parallel_mesh
  implicit none
  real(dp), intent(in) :: centre_angle      !< direction of the line of centres [rad]
  real(dp), intent(in) :: pressure_angle    !< transverse pressure angle [rad]
  real(dp), intent(in) :: base_radius_1     !< gear 1 base radius [m]
  real(dp), intent(in) :: base_radius_2     !< gear 2 base radius [m]
  real(dp), intent(in) :: base_helix_angle  !< signed base helix angle [rad]
  real(dp), intent(out) :: deflection(12)   !< b over [gear 1, gear 2]
  integer(ik), intent(out) :: ierr          !< error code (0 = ok)
  call parallel_mesh(centre_angle, pressure_angle, base_radius_1, base_radius_2, &
                     base_helix_angle, deflection, ierr)
end subroutine parallel_mesh_vector

subroutine planet_speed_matrices(mass, carrier_speed, gyroscopic, centrifugal)
  use kinds, only: dp
  use elements, only: planet_speed_terms
  implicit none
  real(dp), intent(in) :: mass                !< planet mass [kg]
  real(dp), intent(in) :: carrier_speed       !< nominal carrier speed [rad/s]
  real(dp), intent(out) :: gyroscopic(7, 7)   !< Coriolis matrix [kg/s]
  real(dp), intent(out) :: centrifugal(7, 7)  !< centrifugal stiffness [N/m]
  call planet_speed_terms(mass, carrier_speed, gyroscopic, centrifugal)
end subroutine planet_speed_matrices
