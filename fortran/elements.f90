!> Element matrices of the rigid multibody gear model (docs/model.md section 3).
!>
!> Every elastic element is a set of linear springs, each given by a deflection
!> vector b over the element's node DOFs (deflection = b . q) and a stiffness k,
!> so that its stiffness matrix is k b b^T.  Node DOF order:
!>   central member, gear, housing: x, y, z, theta_x, theta_y, theta_z
!>   planet (revolving frame):      zeta, eta, z, theta_zeta, theta_eta, theta_z, phi
!> A planet's theta_z is its spin relative to the revolving frame and phi its
!> revolution angle about the stage axis (tied to the carrier's theta_z later).
module elements
  use kinds, only: dp, ik
  implicit none
  private

  public :: central_mass, planet_mass, central_bearing, planet_bearing
  public :: planetary_mesh, parallel_mesh, planet_speed_terms
  public :: formulation_improved, formulation_consistent, formulation_lin_parker
  public :: mesh_sun_planet, mesh_ring_planet
  public :: ok, err_argument, err_option
  public :: check_positive, check_non_negative

  integer(ik), parameter :: formulation_improved = 1    !< Yang 2016 as published
  integer(ik), parameter :: formulation_consistent = 2  !< exact planet kinetic energy
  integer(ik), parameter :: formulation_lin_parker = 3  !< Lin & Parker 1999, carrier frame

  integer(ik), parameter :: mesh_sun_planet = 1   !< external sun-planet mesh
  integer(ik), parameter :: mesh_ring_planet = 2  !< internal ring-planet mesh

  integer(ik), parameter :: ok = 0            !< success
  integer(ik), parameter :: err_argument = 1  !< a physical argument is out of range
  integer(ik), parameter :: err_option = 2    !< an unknown option code

contains

  !> Mass matrix of a central member or gear, split into its translational and
  !> rotational parts (their sum is the mass matrix).
  subroutine central_mass(mass, tilt_inertia, polar_inertia, mass_translation, mass_rotation, ierr)
    real(dp), intent(in) :: mass                    !< body mass [kg]
    real(dp), intent(in) :: tilt_inertia            !< inertia about x and y [kg m^2]
    real(dp), intent(in) :: polar_inertia           !< inertia about the axis z [kg m^2]
    real(dp), intent(out) :: mass_translation(6, 6) !< translational part [kg]
    real(dp), intent(out) :: mass_rotation(6, 6)    !< rotational part [kg m^2]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)
    integer :: i

    mass_translation = 0.0_dp
    mass_rotation = 0.0_dp
    ierr = check_positive([mass, tilt_inertia, polar_inertia])
    if (ierr /= ok) return
    do i = 1, 3
      mass_translation(i, i) = mass
    end do
    mass_rotation(4, 4) = tilt_inertia
    mass_rotation(5, 5) = tilt_inertia
    mass_rotation(6, 6) = polar_inertia
  end subroutine central_mass

  !> Mass matrix of a planet in its revolving frame (7 DOFs), split into its
  !> translational and rotational parts.
  !>
  !> improved:    diag(m, m, m, I_t, I_t, I_p, m r_c^2) (Yang 2016, as published)
  !> consistent:  kinetic energy 1/2 m [zeta'^2 + (eta' + r_c phi')^2 + z'^2]
  !>              + 1/2 I_p (theta_z' + phi')^2 + 1/2 I_t (theta_zeta'^2 + theta_eta'^2)
  !> lin-parker:  diag(m, m, m, I_t, I_t, I_p) and no revolution DOF (row 7 zero)
  subroutine planet_mass(formulation, mass, tilt_inertia, polar_inertia, carrier_radius, &
                         mass_translation, mass_rotation, ierr)
    integer(ik), intent(in) :: formulation          !< formulation code (1, 2, 3) [-]
    real(dp), intent(in) :: mass                    !< planet mass [kg]
    real(dp), intent(in) :: tilt_inertia            !< inertia about zeta and eta [kg m^2]
    real(dp), intent(in) :: polar_inertia           !< inertia about its own axis [kg m^2]
    real(dp), intent(in) :: carrier_radius          !< sun-planet centre distance r_c [m]
    real(dp), intent(out) :: mass_translation(7, 7) !< translational part [kg, kg m, kg m^2]
    real(dp), intent(out) :: mass_rotation(7, 7)    !< rotational part [kg m^2]
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)
    integer :: i

    mass_translation = 0.0_dp
    mass_rotation = 0.0_dp
    ierr = check_positive([mass, tilt_inertia, polar_inertia, carrier_radius])
    if (ierr /= ok) return
    do i = 1, 3
      mass_translation(i, i) = mass
    end do
    mass_rotation(4, 4) = tilt_inertia
    mass_rotation(5, 5) = tilt_inertia
    mass_rotation(6, 6) = polar_inertia
    select case (formulation)
    case (formulation_improved)
      mass_translation(7, 7) = mass * carrier_radius**2
    case (formulation_consistent)
      mass_translation(7, 7) = mass * carrier_radius**2
      mass_translation(2, 7) = mass * carrier_radius
      mass_translation(7, 2) = mass * carrier_radius
      mass_rotation(7, 7) = polar_inertia
      mass_rotation(6, 7) = polar_inertia
      mass_rotation(7, 6) = polar_inertia
    case (formulation_lin_parker)
      continue
    case default
      ierr = err_option
    end select
  end subroutine planet_mass

  !> Bearing of a central member to the housing: six independent springs on
  !> (member - housing), the housing point taken at the member's centre.
  subroutine central_bearing(radial, axial, tilt, torsional, offset, deflection, stiffness, ierr)
    real(dp), intent(in) :: radial              !< radial stiffness, x and y [N/m]
    real(dp), intent(in) :: axial               !< axial stiffness, z [N/m]
    real(dp), intent(in) :: tilt                !< tilting stiffness, theta_x and theta_y [N m/rad]
    real(dp), intent(in) :: torsional           !< torsional stiffness, theta_z [N m/rad]
    real(dp), intent(in) :: offset(3)           !< member centre minus housing reference point [m]
    real(dp), intent(out) :: deflection(12, 6)  !< b vectors over [member(6), housing(6)]
    real(dp), intent(out) :: stiffness(6)       !< spring stiffnesses [N/m, N m/rad]
    integer(ik), intent(out) :: ierr            !< error code (0 = ok)
    integer :: i

    deflection = 0.0_dp
    stiffness = [radial, radial, axial, tilt, tilt, torsional]
    ierr = check_non_negative(stiffness)
    if (ierr /= ok) return
    do i = 1, 6
      deflection(i, i) = 1.0_dp
      deflection(6 + i, i) = -1.0_dp
    end do
    ! housing point at the member: u_h + theta_h x offset, so -(theta_h x r) = r x theta_h
    deflection(6 + 4:6 + 6, 1:3) = transpose(cross_matrix(offset))
  end subroutine central_bearing

  !> Planet bearing between the carrier and planet n, in the planet's revolving
  !> frame (docs/model.md section 3.3); springs on zeta, eta, z, theta_zeta, theta_eta.
  subroutine planet_bearing(planet_angle, carrier_radius, radial, axial, tilt, &
                            deflection, stiffness, ierr)
    real(dp), intent(in) :: planet_angle        !< planet angle psi_n [rad]
    real(dp), intent(in) :: carrier_radius      !< r_c [m]
    real(dp), intent(in) :: radial              !< radial and tangential stiffness [N/m]
    real(dp), intent(in) :: axial               !< axial stiffness [N/m]
    real(dp), intent(in) :: tilt                !< tilting stiffness [N m/rad]
    real(dp), intent(out) :: deflection(13, 5)  !< b vectors over [carrier(6), planet(7)]
    real(dp), intent(out) :: stiffness(5)       !< spring stiffnesses [N/m, N m/rad]
    integer(ik), intent(out) :: ierr            !< error code (0 = ok)
    real(dp) :: c, s

    deflection = 0.0_dp
    stiffness = [radial, radial, axial, tilt, tilt]
    ierr = check_non_negative(stiffness)
    if (ierr == ok) ierr = check_positive([carrier_radius])
    if (ierr /= ok) return
    c = cos(planet_angle)
    s = sin(planet_angle)
    ! zeta
    deflection(1:2, 1) = [c, s]
    deflection(6 + 1, 1) = -1.0_dp
    ! eta (the revolution phi takes the carrier's rigid turning out)
    deflection(1:2, 2) = [-s, c]
    deflection(6, 2) = carrier_radius
    deflection(6 + 7, 2) = -carrier_radius
    deflection(6 + 2, 2) = -1.0_dp
    ! z
    deflection(3, 3) = 1.0_dp
    deflection(4:5, 3) = carrier_radius * [s, -c]
    deflection(6 + 3, 3) = -1.0_dp
    ! theta_zeta
    deflection(4:5, 4) = [c, s]
    deflection(6 + 4, 4) = -1.0_dp
    ! theta_eta
    deflection(4:5, 5) = [-s, c]
    deflection(6 + 5, 5) = -1.0_dp
  end subroutine planet_bearing

  !> Mesh of a central gear (sun or ring) with planet n (docs/model.md section 3.4).
  !>
  !> The contact normal is n = cos(beta_b) d + sin(beta_b) e_z with d the line of
  !> action in the transverse plane; translations see n, tilts see p x n with p
  !> the pitch point seen from each gear centre (one common point, so rigid
  !> tilting gives no deflection), and the spin arms are the base radii.
  subroutine planetary_mesh(mesh_kind, planet_angle, pressure_angle, base_radius_central, &
                            base_radius_planet, carrier_radius, base_helix_angle, deflection, ierr)
    integer(ik), intent(in) :: mesh_kind           !< 1 sun-planet, 2 ring-planet [-]
    real(dp), intent(in) :: planet_angle           !< planet angle psi_n [rad]
    real(dp), intent(in) :: pressure_angle         !< transverse pressure angle [rad]
    real(dp), intent(in) :: base_radius_central    !< base radius of sun or ring [m]
    real(dp), intent(in) :: base_radius_planet     !< base radius of the planet [m]
    real(dp), intent(in) :: carrier_radius         !< sun-planet centre distance r_c [m]
    real(dp), intent(in) :: base_helix_angle       !< signed base helix angle [rad]
    real(dp), intent(out) :: deflection(13)        !< b over [central(6), planet(7)]
    integer(ik), intent(out) :: ierr               !< error code (0 = ok)
    real(dp) :: line_angle, planet_spin_arm, pitch_distance
    real(dp) :: normal(3), pitch_central(3), pitch_planet(3), radial(3), tangential(3)

    deflection = 0.0_dp
    ierr = check_positive([base_radius_central, base_radius_planet, carrier_radius, &
                           cos(pressure_angle), cos(base_helix_angle)])
    if (ierr /= ok) return
    select case (mesh_kind)
    case (mesh_sun_planet)
      line_angle = planet_angle - pressure_angle
      planet_spin_arm = base_radius_planet
    case (mesh_ring_planet)
      line_angle = planet_angle + pressure_angle
      planet_spin_arm = -base_radius_planet
    case default
      ierr = err_option
      return
    end select
    radial = [cos(planet_angle), sin(planet_angle), 0.0_dp]
    tangential = [-sin(planet_angle), cos(planet_angle), 0.0_dp]
    normal = [-cos(base_helix_angle) * sin(line_angle), cos(base_helix_angle) * cos(line_angle), &
              sin(base_helix_angle)]
    pitch_distance = base_radius_central / cos(pressure_angle)
    pitch_central = pitch_distance * radial
    pitch_planet = (pitch_distance - carrier_radius) * radial

    ! central member, inertial frame
    deflection(1:3) = normal
    deflection(4:6) = cross(pitch_central, normal)
    deflection(6) = cos(base_helix_angle) * base_radius_central
    ! planet, revolving frame
    deflection(7) = -dot_product(normal, radial)
    deflection(8) = -dot_product(normal, tangential)
    deflection(9) = -normal(3)
    deflection(10) = -dot_product(cross(pitch_planet, normal), radial)
    deflection(11) = -dot_product(cross(pitch_planet, normal), tangential)
    deflection(12) = cos(base_helix_angle) * planet_spin_arm
    deflection(13) = -cos(base_helix_angle) * base_radius_central
  end subroutine planetary_mesh

  !> Mesh of an external fixed-axis gear pair (parallel stage). Gear 2's centre
  !> lies at gear 1's centre + centre_distance (cos a, sin a, 0), with the centre
  !> distance (r_b1 + r_b2)/cos(alpha) of a consistent pair.
  subroutine parallel_mesh(centre_angle, pressure_angle, base_radius_1, base_radius_2, &
                           base_helix_angle, deflection, ierr)
    real(dp), intent(in) :: centre_angle      !< direction of the line of centres [rad]
    real(dp), intent(in) :: pressure_angle    !< transverse pressure angle [rad]
    real(dp), intent(in) :: base_radius_1     !< base radius of gear 1 [m]
    real(dp), intent(in) :: base_radius_2     !< base radius of gear 2 [m]
    real(dp), intent(in) :: base_helix_angle  !< signed base helix angle [rad]
    real(dp), intent(out) :: deflection(12)   !< b over [gear 1(6), gear 2(6)]
    integer(ik), intent(out) :: ierr          !< error code (0 = ok)
    real(dp) :: line_angle, radial(3), normal(3), pitch_1(3), pitch_2(3)

    deflection = 0.0_dp
    ierr = check_positive([base_radius_1, base_radius_2, cos(pressure_angle), cos(base_helix_angle)])
    if (ierr /= ok) return
    line_angle = centre_angle - pressure_angle
    radial = [cos(centre_angle), sin(centre_angle), 0.0_dp]
    normal = [-cos(base_helix_angle) * sin(line_angle), cos(base_helix_angle) * cos(line_angle), &
              sin(base_helix_angle)]
    pitch_1 = base_radius_1 / cos(pressure_angle) * radial
    pitch_2 = -base_radius_2 / cos(pressure_angle) * radial
    deflection(1:3) = normal
    deflection(4:6) = cross(pitch_1, normal)
    deflection(7:9) = -normal
    deflection(10:12) = -cross(pitch_2, normal)
  end subroutine parallel_mesh

  !> Speed-dependent planet terms at nominal carrier speed (docs/model.md section 3.6):
  !> Coriolis 2 m Omega [[0, -1], [1, 0]] and centrifugal softening -m Omega^2
  !> on (zeta, eta).
  subroutine planet_speed_terms(mass, carrier_speed, gyroscopic, centrifugal)
    real(dp), intent(in) :: mass                 !< planet mass [kg]
    real(dp), intent(in) :: carrier_speed        !< nominal carrier speed Omega [rad/s]
    real(dp), intent(out) :: gyroscopic(7, 7)    !< Coriolis matrix [kg/s]
    real(dp), intent(out) :: centrifugal(7, 7)   !< centrifugal stiffness [N/m]

    gyroscopic = 0.0_dp
    centrifugal = 0.0_dp
    gyroscopic(1, 2) = -2.0_dp * mass * carrier_speed
    gyroscopic(2, 1) = 2.0_dp * mass * carrier_speed
    centrifugal(1, 1) = -mass * carrier_speed**2
    centrifugal(2, 2) = -mass * carrier_speed**2
  end subroutine planet_speed_terms

  !> Cross product a x b.
  pure function cross(a, b) result(c)
    real(dp), intent(in) :: a(3)  !< first factor [units of a]
    real(dp), intent(in) :: b(3)  !< second factor [units of b]
    real(dp) :: c(3)              !< a x b [units of a times b]
    c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
  end function cross

  !> Matrix R with R v = r x v.
  pure function cross_matrix(r) result(m)
    real(dp), intent(in) :: r(3)  !< lever arm [m]
    real(dp) :: m(3, 3)           !< R [m]
    m = reshape([0.0_dp, r(3), -r(2), -r(3), 0.0_dp, r(1), r(2), -r(1), 0.0_dp], [3, 3])
  end function cross_matrix

  !> err_argument unless every value is positive and finite.
  pure function check_positive(values) result(ierr)
    real(dp), intent(in) :: values(:)  !< stiffnesses, masses or lengths [SI]
    integer(ik) :: ierr                !< error code (0 = ok)
    ierr = ok
    if (any(.not. (values > 0.0_dp)) .or. any(values > huge(1.0_dp))) ierr = err_argument
  end function check_positive

  !> err_argument unless every value is non-negative and finite.
  pure function check_non_negative(values) result(ierr)
    real(dp), intent(in) :: values(:)  !< stiffnesses, masses or lengths [SI]
    integer(ik) :: ierr                !< error code (0 = ok)
    ierr = ok
    if (any(.not. (values >= 0.0_dp)) .or. any(values > huge(1.0_dp))) ierr = err_argument
  end function check_non_negative
end module elements
