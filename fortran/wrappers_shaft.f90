!> The flat layer f2py sees for the flexible-drivetrain elements (module shaft_elements):
!> scalars and explicit-shape arrays in and out, an error code last; nothing is computed here.

subroutine shaft_shear_coefficient(outer_diameter, inner_diameter, poisson_ratio, kappa, ierr)
  use kinds, only: dp, ik
  use shaft_elements, only: hollow_shear_coefficient
  implicit none
  real(dp), intent(in) :: outer_diameter  !< D [m]
  real(dp), intent(in) :: inner_diameter  !< d [m]
  real(dp), intent(in) :: poisson_ratio   !< nu [-]
  real(dp), intent(out) :: kappa          !< shear coefficient [-]
  integer(ik), intent(out) :: ierr        !< error code (0 = ok)
  call hollow_shear_coefficient(outer_diameter, inner_diameter, poisson_ratio, kappa, ierr)
end subroutine shaft_shear_coefficient

subroutine shaft_element_matrices(length, outer_diameter, inner_diameter, youngs_modulus, &
                                  shear_modulus, density, shear_coefficient, shear_deformation, &
                                  rotary_inertia, mass, stiffness, gyroscopic, ierr)
  use kinds, only: dp, ik
  use shaft_elements, only: timoshenko_shaft
  implicit none
  real(dp), intent(in) :: length               !< L [m]
  real(dp), intent(in) :: outer_diameter       !< D [m]
  real(dp), intent(in) :: inner_diameter       !< d [m]
  real(dp), intent(in) :: youngs_modulus       !< E [Pa]
  real(dp), intent(in) :: shear_modulus        !< G [Pa]
  real(dp), intent(in) :: density              !< rho [kg/m^3]
  real(dp), intent(in) :: shear_coefficient    !< kappa [-]
  integer(ik), intent(in) :: shear_deformation !< 1 with shear deformation, 0 without [-]
  integer(ik), intent(in) :: rotary_inertia    !< 1 with rotary inertia, 0 without [-]
  real(dp), intent(out) :: mass(12, 12)        !< mass [kg, kg m, kg m^2]
  real(dp), intent(out) :: stiffness(12, 12)   !< stiffness [N/m, N/rad, N m/rad]
  real(dp), intent(out) :: gyroscopic(12, 12)  !< gyroscopic per unit spin [kg m^2]
  integer(ik), intent(out) :: ierr             !< error code (0 = ok)
  call timoshenko_shaft(length, outer_diameter, inner_diameter, youngs_modulus, shear_modulus, &
                        density, shear_coefficient, shear_deformation, rotary_inertia, mass, &
                        stiffness, gyroscopic, ierr)
end subroutine shaft_element_matrices

subroutine disc_element_matrices(disc_mass, polar_inertia, diametral_inertia, mass, gyroscopic, ierr)
  use kinds, only: dp, ik
  use shaft_elements, only: rigid_disc
  implicit none
  real(dp), intent(in) :: disc_mass          !< m [kg]
  real(dp), intent(in) :: polar_inertia      !< I_p [kg m^2]
  real(dp), intent(in) :: diametral_inertia  !< I_d [kg m^2]
  real(dp), intent(out) :: mass(6, 6)        !< mass [kg, kg m^2]
  real(dp), intent(out) :: gyroscopic(6, 6)  !< gyroscopic per unit spin [kg m^2]
  integer(ik), intent(out) :: ierr           !< error code (0 = ok)
  call rigid_disc(disc_mass, polar_inertia, diametral_inertia, mass, gyroscopic, ierr)
end subroutine disc_element_matrices

subroutine ground_bearing_matrices(bearing_stiffness, bearing_damping, stiffness, damping, ierr)
  use kinds, only: dp, ik
  use shaft_elements, only: bearing_to_ground
  implicit none
  real(dp), intent(in) :: bearing_stiffness(6, 6)  !< K_b [N/m, N m/rad]
  real(dp), intent(in) :: bearing_damping(6, 6)    !< C_b [N s/m, N m s/rad]
  real(dp), intent(out) :: stiffness(6, 6)         !< element stiffness [N/m, N m/rad]
  real(dp), intent(out) :: damping(6, 6)           !< element damping [N s/m, N m s/rad]
  integer(ik), intent(out) :: ierr                 !< error code (0 = ok)
  call bearing_to_ground(bearing_stiffness, bearing_damping, stiffness, damping, ierr)
end subroutine ground_bearing_matrices

subroutine node_bearing_matrices(bearing_stiffness, bearing_damping, stiffness, damping, ierr)
  use kinds, only: dp, ik
  use shaft_elements, only: bearing_between_nodes
  implicit none
  real(dp), intent(in) :: bearing_stiffness(6, 6)  !< K_b [N/m, N m/rad]
  real(dp), intent(in) :: bearing_damping(6, 6)    !< C_b [N s/m, N m s/rad]
  real(dp), intent(out) :: stiffness(12, 12)       !< element stiffness [N/m, N m/rad]
  real(dp), intent(out) :: damping(12, 12)         !< element damping [N s/m, N m s/rad]
  integer(ik), intent(out) :: ierr                 !< error code (0 = ok)
  call bearing_between_nodes(bearing_stiffness, bearing_damping, stiffness, damping, ierr)
end subroutine node_bearing_matrices

subroutine coupling_element_matrices(torsional, radial, axial, angular, torsional_damping, &
                                     radial_damping, axial_damping, angular_damping, &
                                     stiffness, damping, ierr)
  use kinds, only: dp, ik
  use shaft_elements, only: flexible_coupling
  implicit none
  real(dp), intent(in) :: torsional          !< [N m/rad]
  real(dp), intent(in) :: radial             !< [N/m]
  real(dp), intent(in) :: axial              !< [N/m]
  real(dp), intent(in) :: angular            !< [N m/rad]
  real(dp), intent(in) :: torsional_damping  !< [N m s/rad]
  real(dp), intent(in) :: radial_damping     !< [N s/m]
  real(dp), intent(in) :: axial_damping      !< [N s/m]
  real(dp), intent(in) :: angular_damping    !< [N m s/rad]
  real(dp), intent(out) :: stiffness(12, 12) !< element stiffness [N/m, N m/rad]
  real(dp), intent(out) :: damping(12, 12)   !< element damping [N s/m, N m s/rad]
  integer(ik), intent(out) :: ierr           !< error code (0 = ok)
  call flexible_coupling(torsional, radial, axial, angular, torsional_damping, radial_damping, &
                         axial_damping, angular_damping, stiffness, damping, ierr)
end subroutine coupling_element_matrices
