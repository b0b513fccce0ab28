!> Element matrices of flexible drivetrains (docs/shaft_elements.md): Timoshenko shaft
!> elements, rigid discs, bearings and flexible couplings.
!>
!> Node DOF order: x, y, z, theta_x, theta_y, theta_z, the shaft axis along z.  In a
!> right-handed frame a positive theta_y turns the axis towards +x (dx/dz = +theta_y)
!> and a positive theta_x turns it towards -y (dy/dz = -theta_x).  Each bending plane is
!> therefore a planar beam in (w, psi) with psi = dw/dz for bending without shear:
!>   x-z plane: (w, psi) = (x, theta_y);   y-z plane: (w, psi) = (y, -theta_x).
!> The equations of motion are M q'' + (C + Omega G) q' + K q = F with G skew-symmetric
!> per unit spin speed Omega [rad/s] about +z.
!>
!> Shaft element: Nelson (1980), "A finite rotating shaft element using Timoshenko beam
!> theory", J. Mech. Des. 102, 793-803; Friswell, Penny, Garvey & Lees (2010),
!> "Dynamics of Rotating Machines", Cambridge University Press, chapter 5 (matrices
!> with the shear parameter Phi = 12 E I / (kappa G A L^2)); the shape functions solve
!> the static Timoshenko equations (Davis, Henshell & Warburton 1972, "A Timoshenko beam
!> element", J. Sound Vib. 22, 475-487).
!> Shear coefficient of a hollow circle: Hutchinson (2001), "Shear coefficients for
!> Timoshenko beam theory", J. Appl. Mech. 68, 87-92 (the hollow-circle expression).
module shaft_elements
  use kinds, only: dp, ik
  use elements, only: ok, err_argument, check_positive, check_non_negative
  implicit none
  private

  public :: hollow_shear_coefficient, timoshenko_shaft, rigid_disc
  public :: bearing_to_ground, bearing_between_nodes, flexible_coupling

  real(dp), parameter :: pi = 3.14159265358979323846264338327950288_dp

  !> Positions of (w1, psi1, w2, psi2) of each bending plane among the 12 element DOFs,
  !> and the signs that turn the node DOFs into (w, psi).
  integer, parameter :: plane_xz(4) = [1, 5, 7, 11]
  integer, parameter :: plane_yz(4) = [2, 4, 8, 10]
  real(dp), parameter :: sign_xz(4) = [1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp]
  real(dp), parameter :: sign_yz(4) = [1.0_dp, -1.0_dp, 1.0_dp, -1.0_dp]
  integer, parameter :: axial_dofs(2) = [3, 9]
  integer, parameter :: torsion_dofs(2) = [6, 12]

contains

  !> Shear coefficient kappa of a hollow circular section (Hutchinson 2001):
  !>   kappa = 6 (a^2 + b^2)^2 (1 + nu)^2 / [7 a^4 + 34 a^2 b^2 + 7 b^4
  !>           + nu (12 a^4 + 48 a^2 b^2 + 12 b^4) + nu^2 (4 a^4 + 16 a^2 b^2 + 4 b^4)]
  !> with a, b the outer and inner radii; b = 0 gives 6 (1 + nu)^2 / (7 + 12 nu + 4 nu^2).
  pure subroutine hollow_shear_coefficient(outer_diameter, inner_diameter, poisson_ratio, kappa, ierr)
    real(dp), intent(in) :: outer_diameter  !< outer diameter D [m]
    real(dp), intent(in) :: inner_diameter  !< inner diameter d, 0 <= d < D [m]
    real(dp), intent(in) :: poisson_ratio   !< Poisson's ratio nu, -1 < nu <= 0.5 [-]
    real(dp), intent(out) :: kappa          !< shear coefficient [-]
    integer(ik), intent(out) :: ierr        !< error code (0 = ok)
    real(dp) :: a2, b2, nu, denominator

    kappa = 0.0_dp
    ierr = check_section(outer_diameter, inner_diameter)
    if (ierr /= ok) return
    if (.not. (poisson_ratio > -1.0_dp .and. poisson_ratio <= 0.5_dp)) then
      ierr = err_argument
      return
    end if
    a2 = (0.5_dp * outer_diameter)**2
    b2 = (0.5_dp * inner_diameter)**2
    nu = poisson_ratio
    denominator = 7.0_dp * a2**2 + 34.0_dp * a2 * b2 + 7.0_dp * b2**2 &
                  + nu * (12.0_dp * a2**2 + 48.0_dp * a2 * b2 + 12.0_dp * b2**2) &
                  + nu**2 * (4.0_dp * a2**2 + 16.0_dp * a2 * b2 + 4.0_dp * b2**2)
    kappa = 6.0_dp * (a2 + b2)**2 * (1.0_dp + nu)**2 / denominator
  end subroutine hollow_shear_coefficient

  !> Timoshenko shaft element of a uniform hollow circular section, 2 nodes x 6 DOFs.
  !>
  !> Per bending plane in (w1, psi1, w2, psi2) (Friswell et al. 2010, chapter 5):
  !>   K = E I / ((1 + Phi) L^3) [12, 6L, -12, 6L; ., (4+Phi) L^2, -6L, (2-Phi) L^2; ...]
  !>   M_t = rho A L / (840 (1 + Phi)^2) [m1, m2 L, m3, m4 L; ...]
  !>   M_r = rho I / (30 L (1 + Phi)^2) [36, r2 L, -36, r2 L; ...]
  !> the consistent masses of the interdependent interpolation (Nelson 1980).
  !> The gyroscopic matrix per unit spin couples the rotations of the two planes through
  !> R = rho J int(N_psi^T N_psi) = 2 M_r (J = 2 I): G(xz, yz) = R, G(yz, xz) = -R in
  !> (w, psi) coordinates, which a rigid disc's G(theta_x, theta_y) = +I_p reproduces.
  !> Axial and torsional motion use linear interpolation (E A / L, G J / L; consistent
  !> masses rho A L / 6 [2 1; 1 2] and rho J L / 6 [2 1; 1 2]).
  pure subroutine timoshenko_shaft(length, outer_diameter, inner_diameter, youngs_modulus, &
                                   shear_modulus, density, shear_coefficient, shear_deformation, &
                                   rotary_inertia, mass, stiffness, gyroscopic, ierr)
    real(dp), intent(in) :: length               !< element length L [m]
    real(dp), intent(in) :: outer_diameter       !< outer diameter D [m]
    real(dp), intent(in) :: inner_diameter       !< inner diameter d, 0 <= d < D [m]
    real(dp), intent(in) :: youngs_modulus       !< E [Pa]
    real(dp), intent(in) :: shear_modulus        !< G [Pa]
    real(dp), intent(in) :: density              !< rho [kg/m^3]
    real(dp), intent(in) :: shear_coefficient    !< kappa, used when shear_deformation /= 0 [-]
    integer(ik), intent(in) :: shear_deformation !< 1 Timoshenko, 0 Euler-Bernoulli stiffness [-]
    integer(ik), intent(in) :: rotary_inertia    !< 1 with rotary inertia in M, 0 without [-]
    real(dp), intent(out) :: mass(12, 12)        !< consistent mass [kg, kg m, kg m^2]
    real(dp), intent(out) :: stiffness(12, 12)   !< stiffness [N/m, N/rad, N m/rad]
    real(dp), intent(out) :: gyroscopic(12, 12)  !< gyroscopic matrix per unit spin [kg m^2]
    integer(ik), intent(out) :: ierr             !< error code (0 = ok)
    real(dp) :: area, inertia, polar, phi, l
    real(dp) :: bending(4, 4), translation(4, 4), rotation(4, 4)

    mass = 0.0_dp
    stiffness = 0.0_dp
    gyroscopic = 0.0_dp
    ierr = check_section(outer_diameter, inner_diameter)
    if (ierr == ok) ierr = check_positive([length, youngs_modulus, shear_modulus, density])
    if (ierr /= ok) return
    if (shear_deformation /= 0 .and. .not. (shear_coefficient > 0.0_dp .and. &
                                            shear_coefficient <= 1.0_dp)) ierr = err_argument
    if (shear_deformation /= 0 .and. shear_deformation /= 1) ierr = err_argument
    if (rotary_inertia /= 0 .and. rotary_inertia /= 1) ierr = err_argument
    if (ierr /= ok) return

    l = length
    area = 0.25_dp * pi * (outer_diameter**2 - inner_diameter**2)
    inertia = pi / 64.0_dp * (outer_diameter**4 - inner_diameter**4)
    polar = 2.0_dp * inertia
    phi = 0.0_dp
    if (shear_deformation == 1) then
      phi = 12.0_dp * youngs_modulus * inertia / (shear_coefficient * shear_modulus * area * l**2)
    end if

    call plane_matrices(l, phi, bending, translation, rotation)
    bending = youngs_modulus * inertia / ((1.0_dp + phi) * l**3) * bending
    translation = density * area * l / (840.0_dp * (1.0_dp + phi)**2) * translation
    rotation = density * inertia / (30.0_dp * l * (1.0_dp + phi)**2) * rotation

    call scatter_plane(bending, plane_xz, sign_xz, plane_xz, sign_xz, stiffness)
    call scatter_plane(bending, plane_yz, sign_yz, plane_yz, sign_yz, stiffness)
    call scatter_plane(translation, plane_xz, sign_xz, plane_xz, sign_xz, mass)
    call scatter_plane(translation, plane_yz, sign_yz, plane_yz, sign_yz, mass)
    if (rotary_inertia == 1) then
      call scatter_plane(rotation, plane_xz, sign_xz, plane_xz, sign_xz, mass)
      call scatter_plane(rotation, plane_yz, sign_yz, plane_yz, sign_yz, mass)
    end if
    ! R = rho J int(N_psi^T N_psi) = 2 M_r: G(xz, yz) = R and G(yz, xz) = -R
    call scatter_plane(2.0_dp * rotation, plane_xz, sign_xz, plane_yz, sign_yz, gyroscopic)
    call scatter_plane(-2.0_dp * rotation, plane_yz, sign_yz, plane_xz, sign_xz, gyroscopic)

    call scatter_bar(youngs_modulus * area / l, density * area * l, axial_dofs, stiffness, mass)
    call scatter_bar(shear_modulus * polar / l, density * polar * l, torsion_dofs, stiffness, mass)
  end subroutine timoshenko_shaft

  !> Rigid disc at a node: mass diag(m, m, m, I_d, I_d, I_p) and gyroscopic matrix per
  !> unit spin with G(theta_x, theta_y) = I_p, G(theta_y, theta_x) = -I_p (the rate of
  !> change of the angular momentum I_p Omega (theta_y, -theta_x, 1) of a tilted disc).
  pure subroutine rigid_disc(disc_mass, polar_inertia, diametral_inertia, mass, gyroscopic, ierr)
    real(dp), intent(in) :: disc_mass          !< m [kg]
    real(dp), intent(in) :: polar_inertia      !< I_p about the axis z [kg m^2]
    real(dp), intent(in) :: diametral_inertia  !< I_d about x and y [kg m^2]
    real(dp), intent(out) :: mass(6, 6)        !< mass matrix [kg, kg m^2]
    real(dp), intent(out) :: gyroscopic(6, 6)  !< gyroscopic matrix per unit spin [kg m^2]
    integer(ik), intent(out) :: ierr           !< error code (0 = ok)
    integer :: i

    mass = 0.0_dp
    gyroscopic = 0.0_dp
    ierr = check_non_negative([disc_mass, polar_inertia, diametral_inertia])
    if (ierr /= ok) return
    do i = 1, 3
      mass(i, i) = disc_mass
    end do
    mass(4, 4) = diametral_inertia
    mass(5, 5) = diametral_inertia
    mass(6, 6) = polar_inertia
    gyroscopic(4, 5) = polar_inertia
    gyroscopic(5, 4) = -polar_inertia
  end subroutine rigid_disc

  !> Bearing from a node to the ground: a 6 x 6 stiffness and damping, symmetric or not
  !> (cross-coupled fluid-film coefficients), whose diagonals must be non-negative.
  pure subroutine bearing_to_ground(bearing_stiffness, bearing_damping, stiffness, damping, ierr)
    real(dp), intent(in) :: bearing_stiffness(6, 6)  !< K_b [N/m, N/rad, N m/rad]
    real(dp), intent(in) :: bearing_damping(6, 6)    !< C_b [N s/m, N s/rad, N m s/rad]
    real(dp), intent(out) :: stiffness(6, 6)         !< element stiffness [as K_b]
    real(dp), intent(out) :: damping(6, 6)           !< element damping [as C_b]
    integer(ik), intent(out) :: ierr                 !< error code (0 = ok)

    stiffness = 0.0_dp
    damping = 0.0_dp
    ierr = check_bearing(bearing_stiffness, bearing_damping)
    if (ierr /= ok) return
    stiffness = bearing_stiffness
    damping = bearing_damping
  end subroutine bearing_to_ground

  !> Bearing between two nodes (a shaft in a housing node, or one shaft in another):
  !> the 6 x 6 K_b acts on the relative motion q_1 - q_2, so K = [K_b, -K_b; -K_b, K_b].
  pure subroutine bearing_between_nodes(bearing_stiffness, bearing_damping, stiffness, damping, ierr)
    real(dp), intent(in) :: bearing_stiffness(6, 6)  !< K_b [N/m, N/rad, N m/rad]
    real(dp), intent(in) :: bearing_damping(6, 6)    !< C_b [N s/m, N s/rad, N m s/rad]
    real(dp), intent(out) :: stiffness(12, 12)       !< element stiffness [as K_b]
    real(dp), intent(out) :: damping(12, 12)         !< element damping [as C_b]
    integer(ik), intent(out) :: ierr                 !< error code (0 = ok)

    stiffness = 0.0_dp
    damping = 0.0_dp
    ierr = check_bearing(bearing_stiffness, bearing_damping)
    if (ierr /= ok) return
    call relative(bearing_stiffness, stiffness)
    call relative(bearing_damping, damping)
  end subroutine bearing_between_nodes

  !> Flexible coupling between two coincident nodes: independent springs and dampers on
  !> the relative radial (x, y), axial (z), angular (theta_x, theta_y) and torsional
  !> (theta_z) motion.
  pure subroutine flexible_coupling(torsional, radial, axial, angular, torsional_damping, &
                                    radial_damping, axial_damping, angular_damping, &
                                    stiffness, damping, ierr)
    real(dp), intent(in) :: torsional          !< torsional stiffness [N m/rad]
    real(dp), intent(in) :: radial             !< radial stiffness, x and y [N/m]
    real(dp), intent(in) :: axial              !< axial stiffness [N/m]
    real(dp), intent(in) :: angular            !< angular (tilt) stiffness [N m/rad]
    real(dp), intent(in) :: torsional_damping  !< torsional damping [N m s/rad]
    real(dp), intent(in) :: radial_damping     !< radial damping [N s/m]
    real(dp), intent(in) :: axial_damping      !< axial damping [N s/m]
    real(dp), intent(in) :: angular_damping    !< angular damping [N m s/rad]
    real(dp), intent(out) :: stiffness(12, 12) !< element stiffness [N/m, N m/rad]
    real(dp), intent(out) :: damping(12, 12)   !< element damping [N s/m, N m s/rad]
    integer(ik), intent(out) :: ierr           !< error code (0 = ok)
    real(dp) :: node_stiffness(6, 6), node_damping(6, 6)
    real(dp) :: stiffness_diagonal(6), damping_diagonal(6)
    integer :: i

    stiffness = 0.0_dp
    damping = 0.0_dp
    stiffness_diagonal = [radial, radial, axial, angular, angular, torsional]
    damping_diagonal = [radial_damping, radial_damping, axial_damping, angular_damping, &
                        angular_damping, torsional_damping]
    ierr = check_non_negative([stiffness_diagonal, damping_diagonal])
    if (ierr /= ok) return
    node_stiffness = 0.0_dp
    node_damping = 0.0_dp
    do i = 1, 6
      node_stiffness(i, i) = stiffness_diagonal(i)
      node_damping(i, i) = damping_diagonal(i)
    end do
    call relative(node_stiffness, stiffness)
    call relative(node_damping, damping)
  end subroutine flexible_coupling

  !> Unscaled per-plane matrices of the Timoshenko element in (w1, psi1, w2, psi2):
  !> bending stiffness times (1 + Phi) L^3 / (E I), translational mass times
  !> 840 (1 + Phi)^2 / (rho A L), rotary mass times 30 L (1 + Phi)^2 / (rho I).
  pure subroutine plane_matrices(l, phi, bending, translation, rotation)
    real(dp), intent(in) :: l                  !< element length [m]
    real(dp), intent(in) :: phi                !< shear parameter Phi [-]
    real(dp), intent(out) :: bending(4, 4)     !< unscaled stiffness [m^0..m^2]
    real(dp), intent(out) :: translation(4, 4) !< unscaled translational mass [m^0..m^2]
    real(dp), intent(out) :: rotation(4, 4)    !< unscaled rotary mass [m^0..m^2]
    real(dp) :: m1, m2, m3, m4, m5, m6, r2, r3, r4

    bending = reshape([12.0_dp, 6.0_dp * l, -12.0_dp, 6.0_dp * l, &
                       6.0_dp * l, (4.0_dp + phi) * l**2, -6.0_dp * l, (2.0_dp - phi) * l**2, &
                       -12.0_dp, -6.0_dp * l, 12.0_dp, -6.0_dp * l, &
                       6.0_dp * l, (2.0_dp - phi) * l**2, -6.0_dp * l, (4.0_dp + phi) * l**2], [4, 4])

    m1 = 312.0_dp + 588.0_dp * phi + 280.0_dp * phi**2
    m2 = (44.0_dp + 77.0_dp * phi + 35.0_dp * phi**2) * l
    m3 = 108.0_dp + 252.0_dp * phi + 140.0_dp * phi**2
    m4 = -(26.0_dp + 63.0_dp * phi + 35.0_dp * phi**2) * l
    m5 = (8.0_dp + 14.0_dp * phi + 7.0_dp * phi**2) * l**2
    m6 = -(6.0_dp + 14.0_dp * phi + 7.0_dp * phi**2) * l**2
    translation = reshape([m1, m2, m3, m4, &
                           m2, m5, -m4, m6, &
                           m3, -m4, m1, -m2, &
                           m4, m6, -m2, m5], [4, 4])

    r2 = (3.0_dp - 15.0_dp * phi) * l
    r3 = (4.0_dp + 5.0_dp * phi + 10.0_dp * phi**2) * l**2
    r4 = (-1.0_dp - 5.0_dp * phi + 5.0_dp * phi**2) * l**2
    rotation = reshape([36.0_dp, r2, -36.0_dp, r2, &
                        r2, r3, -r2, r4, &
                        -36.0_dp, -r2, 36.0_dp, -r2, &
                        r2, r4, -r2, r3], [4, 4])
  end subroutine plane_matrices

  !> Adds the 4 x 4 block of one plane's (w, psi) coordinates (rows) against another's
  !> (columns) into a 12 x 12 element matrix through the DOF positions and signs.
  pure subroutine scatter_plane(block, rows, row_signs, columns, column_signs, matrix)
    real(dp), intent(in) :: block(4, 4)        !< block in (w, psi) coordinates [SI]
    integer, intent(in) :: rows(4)             !< element DOFs of the row plane [-]
    real(dp), intent(in) :: row_signs(4)       !< signs of the row plane's DOFs [-]
    integer, intent(in) :: columns(4)          !< element DOFs of the column plane [-]
    real(dp), intent(in) :: column_signs(4)    !< signs of the column plane's DOFs [-]
    real(dp), intent(inout) :: matrix(12, 12)  !< element matrix [SI]
    integer :: i, j

    do j = 1, 4
      do i = 1, 4
        matrix(rows(i), columns(j)) = matrix(rows(i), columns(j)) &
                                      + row_signs(i) * column_signs(j) * block(i, j)
      end do
    end do
  end subroutine scatter_plane

  !> Adds a two-node bar (axial or torsional): stiffness k [1 -1; -1 1] and consistent
  !> mass (m / 6) [2 1; 1 2].
  pure subroutine scatter_bar(bar_stiffness, bar_mass, dofs, stiffness, mass)
    real(dp), intent(in) :: bar_stiffness       !< E A / L or G J / L [N/m, N m/rad]
    real(dp), intent(in) :: bar_mass            !< rho A L or rho J L [kg, kg m^2]
    integer, intent(in) :: dofs(2)              !< element DOFs of the bar [-]
    real(dp), intent(inout) :: stiffness(12, 12) !< element stiffness [SI]
    real(dp), intent(inout) :: mass(12, 12)      !< element mass [SI]

    stiffness(dofs, dofs) = stiffness(dofs, dofs) &
                            + bar_stiffness * reshape([1.0_dp, -1.0_dp, -1.0_dp, 1.0_dp], [2, 2])
    mass(dofs, dofs) = mass(dofs, dofs) &
                       + bar_mass / 6.0_dp * reshape([2.0_dp, 1.0_dp, 1.0_dp, 2.0_dp], [2, 2])
  end subroutine scatter_bar

  !> [A, -A; -A, A]: a 6 x 6 law on the relative motion of two nodes.
  pure subroutine relative(node_matrix, matrix)
    real(dp), intent(in) :: node_matrix(6, 6)  !< law on q_1 - q_2 [SI]
    real(dp), intent(out) :: matrix(12, 12)    !< two-node element matrix [SI]

    matrix(1:6, 1:6) = node_matrix
    matrix(7:12, 7:12) = node_matrix
    matrix(1:6, 7:12) = -node_matrix
    matrix(7:12, 1:6) = -node_matrix
  end subroutine relative

  !> err_argument unless 0 <= d < D, both finite.
  pure function check_section(outer_diameter, inner_diameter) result(ierr)
    real(dp), intent(in) :: outer_diameter  !< D [m]
    real(dp), intent(in) :: inner_diameter  !< d [m]
    integer(ik) :: ierr                     !< error code (0 = ok)

    ierr = check_positive([outer_diameter])
    if (ierr == ok) ierr = check_non_negative([inner_diameter])
    if (ierr == ok .and. .not. (inner_diameter < outer_diameter)) ierr = err_argument
  end function check_section

  !> err_argument unless every entry is finite and the diagonals are non-negative.
  pure function check_bearing(bearing_stiffness, bearing_damping) result(ierr)
    real(dp), intent(in) :: bearing_stiffness(6, 6)  !< K_b [SI]
    real(dp), intent(in) :: bearing_damping(6, 6)    !< C_b [SI]
    integer(ik) :: ierr                              !< error code (0 = ok)
    integer :: i

    ierr = ok
    if (any(.not. (abs(bearing_stiffness) <= huge(1.0_dp))) .or. &
        any(.not. (abs(bearing_damping) <= huge(1.0_dp)))) ierr = err_argument
    do i = 1, 6
      if (.not. (bearing_stiffness(i, i) >= 0.0_dp .and. bearing_damping(i, i) >= 0.0_dp)) then
        ierr = err_argument
      end if
    end do
  end function check_bearing

end module shaft_elements
