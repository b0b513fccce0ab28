!> Tooth-pair stiffness of involute gears by the potential-energy method
!> (Yang & Lin 1987; Tian 2004; Wu, Zuo & Parey 2008; Chaari, Fakhfakh & Haddar 2009),
!> evaluated once per mesh before a run.  docs/potential_energy.md has the equations.
!>
!> Each tooth is a non-uniform cantilever along its centre line X (from the gear axis),
!> clamped where its flank meets the root circle.  A unit force acts along the line of
!> action at the contact point P = (X_p, Y_p); beta is the angle between the force and
!> the normal to the centre line (compressive when positive).  Per unit face width:
!>   c_b = int 12 [cos(beta) d - sin(beta) Y_p]^2 / (E H^3) dX     (bending)
!>   c_s = int 1.2 cos(beta)^2 / (G H) dX                          (shear)
!>   c_a = int sin(beta)^2 / (E H) dX                              (axial compression)
!> with d = |X_p - X| and H(X) the load-bearing height of the section at X.  Below the
!> base circle (root circle smaller) the flank is a straight line of constant half
!> height r_b sin(psi_b) (Tian 2004; Chen & Shao 2011).  External teeth add the
!> fillet-foundation compliance of Sainsot, Velex & Duverger (2004); the ring's rim is
!> taken as rigid.  The pair adds the Hertz compliance of Yang & Lin (1987).
!>
!> Integrals are Gauss-Legendre on segments in the involute parameter (the pressure
!> angle at the section), split wherever a fault makes the integrand kink, so they
!> converge exponentially with the points per segment.
!>
!> Faults (one tooth of one gear): a root crack clips the section on the cracked side at
!> the crack tip's distance from the centre line (Tian 2004); a spall removes material of
!> a given depth over its profile band and cuts the contact width while the contact lies
!> in it (Chaari et al. 2008; Saxena et al. 2016); a chipped tooth has lost the part above
!> a radius, where it makes no contact.  A fault may cover part of the face width: the
!> damaged and the intact widths then act in parallel (face-width slicing, Chen & Shao 2011).
module tooth_potential_energy
  use kinds, only: dp, ik
  implicit none
  private

  public :: n_gear_param, n_mesh_param, n_fault_param, n_geometry_out, n_compliance_out
  public :: fault_none, fault_crack, fault_spall, fault_chip
  public :: pe_ok, pe_err_argument, pe_err_geometry, pe_err_size, pe_err_fault
  public :: mesh_geometry_summary, mesh_stiffness_curves, tooth_compliance

  integer(ik), parameter :: n_gear_param = 12      !< entries of one gear's parameter column
  integer(ik), parameter :: n_mesh_param = 2       !< centre distance, working pressure angle
  integer(ik), parameter :: n_fault_param = 8      !< entries of the fault description
  integer(ik), parameter :: n_geometry_out = 16    !< entries of the geometry summary
  integer(ik), parameter :: n_compliance_out = 9   !< rows of the compliance breakdown

  ! gear parameter indices (derived transverse geometry, see docs/potential_energy.md)
  integer, parameter :: gp_teeth = 1, gp_base = 2, gp_tip = 3, gp_root = 4, gp_form = 5
  integer, parameter :: gp_half_angle = 6, gp_helix_base = 7, gp_width = 8
  integer, parameter :: gp_bore = 9, gp_young = 10, gp_poisson = 11, gp_internal = 12
  ! mesh parameter indices
  integer, parameter :: mp_centre = 1, mp_pressure = 2
  ! fault parameter indices
  integer, parameter :: fp_kind = 1, fp_gear = 2, fp_face_start = 3, fp_face_width = 4
  integer, parameter :: fp_a = 5, fp_b = 6, fp_c = 7

  integer(ik), parameter :: fault_none = 0   !< healthy
  integer(ik), parameter :: fault_crack = 1  !< root crack: a = depth q [m], b = angle nu [rad]
  integer(ik), parameter :: fault_spall = 2  !< spall: a = centre radius, b = length on profile, c = depth [m]
  integer(ik), parameter :: fault_chip = 3   !< chipped tooth: a = missing fraction of the tooth height

  integer(ik), parameter :: pe_ok = 0            !< success
  integer(ik), parameter :: pe_err_argument = 1  !< a parameter is out of range (bad_param says which)
  integer(ik), parameter :: pe_err_geometry = 2  !< the gears cannot mesh as given
  integer(ik), parameter :: pe_err_size = 3      !< an array size is too small
  integer(ik), parameter :: pe_err_fault = 4     !< the fault does not fit the tooth

  real(dp), parameter :: pi = 3.14159265358979323846264338327950288_dp
  integer, parameter :: max_quad = 256

  !> Coefficients of Sainsot, Velex & Duverger (2004) for L*, M*, P*, Q*:
  !> X* = A/theta_f^2 + B h_fi^2 + C h_fi/theta_f + D/theta_f + E h_fi + F.
  real(dp), parameter :: sainsot(6, 4) = reshape([ &
    -5.574e-5_dp, -1.9986e-3_dp, -2.3015e-4_dp, 4.7702e-3_dp, 0.0271_dp, 6.8045_dp, &
    60.111e-5_dp, 28.100e-3_dp, -83.431e-4_dp, -9.9256e-3_dp, 0.1624_dp, 0.9086_dp, &
    -50.952e-5_dp, 185.50e-3_dp, 0.0538e-4_dp, 53.300e-3_dp, 0.2895_dp, 0.9236_dp, &
    -6.2042e-5_dp, 9.0889e-3_dp, -4.0964e-4_dp, 7.8297e-3_dp, -0.1472_dp, 0.6904_dp], [6, 4])

  !> One gear's transverse tooth geometry.
  type :: tooth_shape
    logical :: internal = .false.
    real(dp) :: teeth = 0, r_b = 0, r_a = 0, r_f = 0, r_form = 0, r_int = 0
    real(dp) :: helix_base = 0, psi_b = 0, young = 0, poisson = 0, shear = 0
    real(dp) :: width = 0
    logical :: straight = .false.      ! external tooth with a straight flank below r_b
    real(dp) :: x_root = 0, x_base = 0, h_base = 0, alpha_root = 0, theta_f = 0
    real(dp) :: y_root = 0             ! half height where the flank meets the root circle
    real(dp) :: lmpq(4) = 0
    logical :: foundation = .false.
  end type tooth_shape

  !> The damage of one tooth, in the tooth's own terms.
  type :: tooth_damage
    integer(ik) :: kind = fault_none
    real(dp) :: face_start = 0, face_width = 0
    real(dp) :: y_tip = 0                      ! crack: tip distance from the centre line
    real(dp) :: alpha_lo = 0, alpha_hi = 0     ! spall: profile band (pressure angles)
    real(dp) :: depth = 0                      ! spall depth
    real(dp) :: r_chip = 0                     ! chip: radius beyond which the tooth is gone
  end type tooth_damage

  !> The mesh: both teeth and the path of contact.
  type :: mesh_shape
    type(tooth_shape) :: tooth(2)
    real(dp) :: base_pitch = 0, s_start = 0, s_end = 0, eps_alpha = 0, eps_beta = 0
    real(dp) :: centre_distance = 0, alpha_w = 0, tangent_span = 0, width = 0
    real(dp) :: hertz_per_width = 0
    logical :: swapped = .false.       ! gear 1 internal: computed with gear 2 first
  end type mesh_shape

contains

  ! ----------------------------------------------------------------- geometry

  pure real(dp) function involute(alpha)
    real(dp), intent(in) :: alpha   !< pressure angle [rad]
    involute = tan(alpha) - alpha
  end function involute

  !> Pressure angle whose involute is target (Newton from a cube-root start).
  pure real(dp) function inverse_involute(target)
    real(dp), intent(in) :: target   !< involute value [rad]
    real(dp) :: a
    integer :: k
    a = (3.0_dp * target)**(1.0_dp / 3.0_dp)
    do k = 1, 50
      a = a - (tan(a) - a - target) / tan(a)**2
    end do
    inverse_involute = a
  end function inverse_involute

  !> Half tooth angle at pressure angle alpha (radius r_b / cos alpha).
  pure real(dp) function half_angle(t, alpha)
    type(tooth_shape), intent(in) :: t  !< the tooth
    real(dp), intent(in) :: alpha   !< pressure angle of the radius [rad]
    if (t%internal) then
      half_angle = t%psi_b + involute(alpha)
    else
      half_angle = t%psi_b - involute(alpha)
    end if
  end function half_angle

  !> Half tooth angle where the tooth meets its body: at the base circle, or at the
  !> root circle of an external tooth whose root lies above the base circle (a large
  !> positively shifted gear, whose involute extended to the base circle would overlap
  !> its neighbour inside the body).  Less than pi / z leaves a tooth space.
  pure real(dp) function root_half_angle(p)
    real(dp), intent(in) :: p(n_gear_param)   !< gear parameters [m, rad, Pa, -]
    root_half_angle = p(gp_half_angle)
    if (p(gp_internal) == 0.0_dp .and. p(gp_root) > p(gp_base)) then
      root_half_angle = p(gp_half_angle) - involute(acos(p(gp_base) / p(gp_root)))
    end if
  end function root_half_angle

  !> Check one gear's parameters; bad names the first bad entry (0 if none).
  pure subroutine check_gear(p, bad)
    real(dp), intent(in) :: p(n_gear_param)   !< gear parameters [m, rad, Pa, -]
    integer(ik), intent(out) :: bad           !< first bad index, 0 if none [-]
    integer :: i
    bad = 0
    do i = 1, n_gear_param
      if (.not. abs(p(i)) < huge(1.0_dp)) then
        bad = int(i, ik)
        return
      end if
    end do
    if (p(gp_internal) /= 0.0_dp .and. p(gp_internal) /= 1.0_dp) then
      bad = gp_internal
    else if (p(gp_teeth) < 5.0_dp .or. abs(p(gp_teeth) - anint(p(gp_teeth))) > 0.0_dp) then
      bad = gp_teeth
    else if (.not. p(gp_base) > 0.0_dp) then
      bad = gp_base
    else if (.not. p(gp_tip) > p(gp_base)) then
      bad = gp_tip
    else if (p(gp_internal) == 0.0_dp .and. .not. (p(gp_root) > 0.0_dp .and. p(gp_root) < p(gp_tip))) then
      bad = gp_root
    else if (p(gp_internal) == 1.0_dp .and. .not. p(gp_root) > p(gp_tip)) then
      bad = gp_root
    else if (.not. p(gp_form) > 0.0_dp) then
      bad = gp_form
    else if (.not. (abs(root_half_angle(p)) < pi / p(gp_teeth))) then
      bad = gp_half_angle
    else if (.not. (p(gp_helix_base) >= 0.0_dp .and. p(gp_helix_base) < pi / 4)) then
      bad = gp_helix_base
    else if (.not. p(gp_width) > 0.0_dp) then
      bad = gp_width
    else if (p(gp_bore) < 0.0_dp) then
      bad = gp_bore
    else if (.not. p(gp_young) > 0.0_dp) then
      bad = gp_young
    else if (.not. (p(gp_poisson) >= 0.0_dp .and. p(gp_poisson) < 0.5_dp)) then
      bad = gp_poisson
    end if
  end subroutine check_gear

  !> One gear's tooth from its transverse geometry.  half_angle is the tooth's half
  !> angle at the base circle, extended along the involute: psi(r) = psi_b - inv(alpha_r)
  !> for an external tooth, psi_b + inv(alpha_r) for a ring tooth.  bad names the
  !> parameter at fault when the tooth cannot be built.
  pure subroutine build_tooth(p, t, bad, ierr)
    real(dp), intent(in) :: p(n_gear_param)   !< gear parameters [m, rad, Pa, -]
    type(tooth_shape), intent(out) :: t        !< the tooth
    integer(ik), intent(out) :: bad            !< bad parameter, 0 if none [-]
    integer(ik), intent(out) :: ierr           !< pe_ok, pe_err_argument or pe_err_geometry (error code)
    real(dp) :: sin_psi
    integer :: i

    ierr = pe_ok
    call check_gear(p, bad)
    if (bad /= 0) then
      ierr = pe_err_argument
      return
    end if
    t%internal = p(gp_internal) == 1.0_dp
    t%teeth = p(gp_teeth)
    t%r_b = p(gp_base)
    t%r_a = p(gp_tip)
    t%r_f = p(gp_root)
    t%r_form = p(gp_form)
    t%psi_b = p(gp_half_angle)
    t%helix_base = p(gp_helix_base)
    t%width = p(gp_width)
    t%young = p(gp_young)
    t%poisson = p(gp_poisson)
    t%shear = p(gp_young) / (2.0_dp * (1.0_dp + p(gp_poisson)))
    ! the tooth must keep a thickness at its tip
    if (.not. half_angle(t, acos(t%r_b / t%r_a)) > 0.0_dp) then
      bad = gp_half_angle
      ierr = pe_err_geometry
      return
    end if
    t%x_base = t%r_b * cos(t%psi_b)
    t%h_base = t%r_b * sin(t%psi_b)
    if (t%internal) then
      t%straight = .false.
      t%alpha_root = acos(t%r_b / t%r_f)
      t%theta_f = half_angle(t, t%alpha_root)
      t%x_root = t%r_f * cos(t%theta_f)
      t%y_root = t%r_f * sin(t%theta_f)
      t%foundation = .false.
      return
    end if
    if (.not. t%psi_b > 0.0_dp) then
      bad = gp_half_angle
      ierr = pe_err_geometry
      return
    end if
    t%straight = t%r_f < t%r_b
    if (t%straight) then
      t%alpha_root = 0.0_dp
      sin_psi = t%h_base / t%r_f
      t%theta_f = asin(min(sin_psi, 1.0_dp))
      t%x_root = t%r_f * cos(t%theta_f)
      t%y_root = t%h_base
    else
      t%alpha_root = acos(t%r_b / t%r_f)
      t%theta_f = half_angle(t, t%alpha_root)
      t%x_root = t%r_f * cos(t%theta_f)
      t%y_root = t%r_f * sin(t%theta_f)
    end if
    t%r_int = p(gp_bore)
    t%foundation = t%r_int > 0.0_dp
    if (t%foundation) then
      if (.not. t%r_int < t%r_f) then
        bad = gp_bore
        ierr = pe_err_geometry
        return
      end if
      do i = 1, 4
        t%lmpq(i) = sainsot_value(sainsot(:, i), t%r_f / t%r_int, t%theta_f)
      end do
    end if
  end subroutine build_tooth

  pure real(dp) function sainsot_value(c, h_fi, theta_f)
    real(dp), intent(in) :: c(6)      !< A..F of one coefficient [-]
    real(dp), intent(in) :: h_fi      !< r_f / r_int [-]
    real(dp), intent(in) :: theta_f   !< half tooth angle at the root circle [rad]
    sainsot_value = c(1) / theta_f**2 + c(2) * h_fi**2 + c(3) * h_fi / theta_f &
                    + c(4) / theta_f + c(5) * h_fi + c(6)
  end function sainsot_value

  !> Both teeth and the path of contact.  Gear 1 internal is computed with the
  !> gears swapped (swapped = .true.); the public routines run its path backwards.
  pure subroutine build_mesh(gear, mesh_param, mesh, bad_param, ierr)
    real(dp), intent(in) :: gear(n_gear_param, 2)      !< gear parameters [m, rad, Pa, -]
    real(dp), intent(in) :: mesh_param(n_mesh_param)   !< centre distance [m], alpha_wt [rad]
    type(mesh_shape), intent(out) :: mesh               !< the mesh
    integer(ik), intent(out) :: bad_param   !< 100 g + index, 300 + mesh index, 0 if none [-]
    integer(ik), intent(out) :: ierr        !< error code
    integer(ik) :: bad
    integer :: g, order(2)
    real(dp) :: reach1, reach2, base_sum

    bad_param = 0
    ierr = pe_ok
    if (gear(gp_internal, 1) == 1.0_dp .and. gear(gp_internal, 2) == 1.0_dp) then
      bad_param = 200 + gp_internal
      ierr = pe_err_argument
      return
    end if
    mesh%swapped = gear(gp_internal, 1) == 1.0_dp
    order = [1, 2]
    if (mesh%swapped) order = [2, 1]
    do g = 1, 2
      call build_tooth(gear(:, order(g)), mesh%tooth(g), bad, ierr)
      if (ierr /= pe_ok) then
        bad_param = 100 * order(g) + bad
        return
      end if
    end do
    associate (t1 => mesh%tooth(1), t2 => mesh%tooth(2))
      ! the teeth must share the base pitch and the base helix angle
      mesh%base_pitch = 2.0_dp * pi * t1%r_b / t1%teeth
      if (abs(2.0_dp * pi * t2%r_b / t2%teeth - mesh%base_pitch) > 1.0e-9_dp * mesh%base_pitch) then
        bad_param = 100 * order(2) + gp_base
        ierr = pe_err_argument
        return
      end if
      if (abs(t2%helix_base - t1%helix_base) > 1.0e-9_dp) then
        bad_param = 100 * order(2) + gp_helix_base
        ierr = pe_err_argument
        return
      end if
      mesh%centre_distance = mesh_param(mp_centre)
      mesh%alpha_w = mesh_param(mp_pressure)
      if (.not. (mesh%alpha_w > 0.0_dp .and. mesh%alpha_w < 0.5_dp * pi)) then
        bad_param = 300 + mp_pressure
        ierr = pe_err_argument
        return
      end if
      base_sum = t1%r_b + t2%r_b
      if (t2%internal) base_sum = t2%r_b - t1%r_b
      if (.not. abs(mesh%centre_distance * cos(mesh%alpha_w) - base_sum) <= 1.0e-9_dp * base_sum) then
        bad_param = 300 + mp_centre
        ierr = pe_err_argument
        return
      end if
      mesh%width = min(t1%width, t2%width)
      mesh%tangent_span = mesh%centre_distance * sin(mesh%alpha_w)
      ! roll distances of gear 1's contact point from its tangent point
      reach1 = sqrt(t1%r_a**2 - t1%r_b**2)
      reach2 = sqrt(t2%r_a**2 - t2%r_b**2)
      if (t2%internal) then
        mesh%s_start = reach2 - mesh%tangent_span
      else
        mesh%s_start = mesh%tangent_span - reach2
      end if
      mesh%s_end = reach1
      mesh%eps_alpha = (mesh%s_end - mesh%s_start) / mesh%base_pitch
      mesh%eps_beta = mesh%width * tan(t1%helix_base) / mesh%base_pitch
      ! both ends of the path must meet the involutes inside their form circles
      ! (no contact on the fillet: interference)
      if (.not. (mesh%s_start > 0.0_dp .and. &
                 mesh%s_start >= sqrt(max(t1%r_form**2 - t1%r_b**2, 0.0_dp)) * (1 - 1e-12_dp))) then
        bad_param = 100 * order(1) + gp_form
        ierr = pe_err_geometry
        return
      end if
      reach2 = contact_roll(mesh, 2, mesh%eps_alpha)
      if (t2%internal) then
        if (.not. reach2 <= sqrt(max(t2%r_form**2 - t2%r_b**2, 0.0_dp)) * (1 + 1e-12_dp)) &
          ierr = pe_err_geometry
      else
        if (.not. (reach2 > 0.0_dp .and. &
                   reach2 >= sqrt(max(t2%r_form**2 - t2%r_b**2, 0.0_dp)) * (1 - 1e-12_dp))) &
          ierr = pe_err_geometry
      end if
      if (ierr /= pe_ok) then
        bad_param = 100 * order(2) + gp_form
        return
      end if
      if (.not. mesh%eps_alpha >= 1.0_dp) then
        bad_param = 300 + mp_centre
        ierr = pe_err_geometry
        return
      end if
      mesh%hertz_per_width = pi / (2.0_dp * ((1.0_dp - t1%poisson**2) / t1%young &
                                             + (1.0_dp - t2%poisson**2) / t2%young))
    end associate
  end subroutine build_mesh

  !> Roll distance of the contact point on tooth g at transverse position p [mesh cycles].
  pure real(dp) function contact_roll(mesh, g, p)
    type(mesh_shape), intent(in) :: mesh  !< the mesh
    integer, intent(in) :: g          !< 1 or 2 (in the computation's order) [-]
    real(dp), intent(in) :: p         !< position along the path of contact [mesh cycles]
    real(dp) :: s1
    s1 = mesh%s_start + p * mesh%base_pitch
    if (g == 1) then
      contact_roll = s1
    else if (mesh%tooth(2)%internal) then
      contact_roll = s1 + mesh%tangent_span
    else
      contact_roll = mesh%tangent_span - s1
    end if
  end function contact_roll

  !> Translate the packed fault into the damaged tooth's terms.
  pure subroutine build_damage(t, fault, width, d, bad, ierr)
    type(tooth_shape), intent(in) :: t              !< the damaged tooth
    real(dp), intent(in) :: fault(n_fault_param)    !< packed fault [-, -, m, m, m or rad]
    real(dp), intent(in) :: width                   !< loaded face width [m]
    type(tooth_damage), intent(out) :: d            !< the damage
    integer(ik), intent(out) :: bad                 !< bad fault index, 0 if none [-]
    integer(ik), intent(out) :: ierr                !< error code
    real(dp) :: centre_roll, arc_centre, arc_lo, arc_hi, h_tip

    bad = 0
    ierr = pe_ok
    d%kind = nint(fault(fp_kind), ik)
    if (d%kind == fault_none) return
    d%face_start = fault(fp_face_start)
    d%face_width = fault(fp_face_width)
    if (.not. (d%face_start >= 0.0_dp .and. d%face_start < width)) then
      bad = fp_face_start
    else if (.not. (d%face_width > 0.0_dp .and. d%face_start + d%face_width <= width * (1 + 1e-12_dp))) &
      then
      bad = fp_face_width
    end if
    if (bad /= 0) then
      ierr = pe_err_argument
      return
    end if
    d%face_width = min(d%face_width, width - d%face_start)
    select case (d%kind)
    case (fault_crack)
      if (.not. (fault(fp_a) > 0.0_dp)) then
        bad = fp_a
      else if (.not. (fault(fp_b) > 0.0_dp .and. fault(fp_b) <= 0.5_dp * pi)) then
        bad = fp_b
      end if
      if (bad /= 0) then
        ierr = pe_err_argument
        return
      end if
      d%y_tip = t%y_root - fault(fp_a) * sin(fault(fp_b))
      ! every clipped section must keep some height: the tip's distance beyond the
      ! centre line stays below the tooth's half thickness at its tip
      h_tip = t%r_a * sin(half_angle(t, acos(t%r_b / t%r_a)))
      if (.not. d%y_tip > -h_tip) then
        bad = fp_a
        ierr = pe_err_fault
      end if
    case (fault_spall)
      if (.not. (fault(fp_a) > t%r_b)) then
        bad = fp_a
      else if (.not. fault(fp_b) > 0.0_dp) then
        bad = fp_b
      else if (.not. fault(fp_c) > 0.0_dp) then
        bad = fp_c
      end if
      if (bad /= 0) then
        ierr = pe_err_argument
        return
      end if
      ! the band in involute arc length from the base circle, r_b tan(alpha)^2 / 2
      centre_roll = sqrt(fault(fp_a)**2 - t%r_b**2) / t%r_b
      arc_centre = 0.5_dp * t%r_b * centre_roll**2
      arc_lo = arc_centre - 0.5_dp * fault(fp_b)
      arc_hi = arc_centre + 0.5_dp * fault(fp_b)
      if (.not. arc_lo > 0.0_dp) then
        bad = fp_b
        ierr = pe_err_fault
        return
      end if
      d%alpha_lo = atan(sqrt(2.0_dp * arc_lo / t%r_b))
      d%alpha_hi = atan(sqrt(2.0_dp * arc_hi / t%r_b))
      d%depth = fault(fp_c)
      ! the spall leaves material in every section of its band
      if (.not. d%depth < t%r_b / cos(max(d%alpha_lo, d%alpha_hi)) &
                         * sin(min(half_angle(t, d%alpha_lo), half_angle(t, d%alpha_hi)))) then
        bad = fp_c
        ierr = pe_err_fault
      end if
    case (fault_chip)
      if (.not. (fault(fp_a) > 0.0_dp .and. fault(fp_a) <= 1.0_dp)) then
        bad = fp_a
        ierr = pe_err_argument
        return
      end if
      d%r_chip = t%r_a + fault(fp_a) * (t%r_f - t%r_a)
    case default
      bad = fp_kind
      ierr = pe_err_argument
    end select
  end subroutine build_damage

  ! ------------------------------------------------------------- integration

  !> Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n).
  pure subroutine gauss_legendre(n, node, weight)
    integer, intent(in) :: n            !< number of points [-]
    real(dp), intent(out) :: node(n)    !< nodes [-]
    real(dp), intent(out) :: weight(n)  !< weights [-]
    integer :: i, k
    real(dp) :: x, p_n, dp_dx

    do i = 1, (n + 1) / 2
      x = cos(pi * (real(i, dp) - 0.25_dp) / (real(n, dp) + 0.5_dp))
      do k = 1, 100
        call legendre(n, x, p_n, dp_dx)
        if (abs(p_n / dp_dx) < 1.0e-16_dp) exit
        x = x - p_n / dp_dx
      end do
      call legendre(n, x, p_n, dp_dx)
      node(i) = -x
      node(n + 1 - i) = x
      weight(i) = 2.0_dp / ((1.0_dp - x * x) * dp_dx**2)
      weight(n + 1 - i) = weight(i)
    end do
  end subroutine gauss_legendre

  !> Legendre polynomial P_n(x) and its derivative by the three-term recurrence.
  pure subroutine legendre(n, x, p_n, dp_dx)
    integer, intent(in) :: n            !< degree, >= 1 [-]
    real(dp), intent(in) :: x           !< argument in (-1, 1) [-]
    real(dp), intent(out) :: p_n        !< P_n(x) [-]
    real(dp), intent(out) :: dp_dx      !< P_n'(x) [-]
    real(dp) :: p_previous, p_next
    integer :: j
    p_previous = 1.0_dp
    p_n = x
    do j = 2, n
      p_next = ((2 * j - 1) * x * p_n - (j - 1) * p_previous) / j
      p_previous = p_n
      p_n = p_next
    end do
    dp_dx = n * (x * p_n - p_previous) / (x * x - 1.0_dp)
  end subroutine legendre

  !> Load-bearing section at X: centre-line half height h and the height H that
  !> carries load, for the healthy tooth or its damaged width.
  pure real(dp) function bearing_height(h, alpha, damaged, d)
    real(dp), intent(in) :: h           !< healthy half height [m]
    real(dp), intent(in) :: alpha       !< involute parameter of the section, -1 on the straight flank [rad]
    logical, intent(in) :: damaged      !< the damaged width part
    type(tooth_damage), intent(in) :: d !< the damage
    bearing_height = 2.0_dp * h
    if (.not. damaged) return
    select case (d%kind)
    case (fault_crack)
      bearing_height = h + min(h, d%y_tip)
    case (fault_spall)
      if (alpha >= d%alpha_lo .and. alpha <= d%alpha_hi) bearing_height = 2.0_dp * h - d%depth
    end select
  end function bearing_height

  !> Bending, shear and axial compliance of one tooth per unit face width for a unit
  !> load at pressure angle alpha_c (contact radius r_b / cos alpha_c).
  pure subroutine beam_compliance(t, alpha_c, damaged, d, node, weight, c_b, c_s, c_a, beta)
    type(tooth_shape), intent(in) :: t  !< the tooth
    real(dp), intent(in) :: alpha_c        !< contact pressure angle [rad]
    logical, intent(in) :: damaged         !< integrate the damaged width's section
    type(tooth_damage), intent(in) :: d    !< the damage (used when damaged)
    real(dp), intent(in) :: node(:)    !< Gauss-Legendre nodes on [-1, 1] [-]
    real(dp), intent(in) :: weight(:)  !< Gauss-Legendre weights [-]
    real(dp), intent(out) :: c_b, c_s, c_a !< compliances per unit width [m/N m = 1/Pa]
    real(dp), intent(out) :: beta          !< load angle [rad]
    real(dp) :: r_c, psi_c, x_p, y_p, cos_b, sin_b, breaks(6), lo, hi, span, mid
    real(dp) :: alpha, x, h, dx, height, r, psi, arm, alpha_g
    integer :: nb, i, j, q

    r_c = t%r_b / cos(alpha_c)
    psi_c = half_angle(t, alpha_c)
    x_p = r_c * cos(psi_c)
    y_p = r_c * sin(psi_c)
    if (t%internal) then
      beta = alpha_c + psi_c
    else
      beta = alpha_c - psi_c
    end if
    cos_b = cos(beta)
    sin_b = sin(beta)
    c_b = 0.0_dp
    c_s = 0.0_dp
    c_a = 0.0_dp

    ! straight flank below the base circle: constant half height, integrand polynomial in X
    if (t%straight) then
      span = 0.5_dp * (t%x_base - t%x_root)
      mid = 0.5_dp * (t%x_base + t%x_root)
      height = bearing_height(t%h_base, -1.0_dp, damaged, d)
      do q = 1, size(node)
        x = mid + span * node(q)
        arm = cos_b * (x_p - x) - sin_b * y_p
        c_b = c_b + weight(q) * span * 12.0_dp * arm**2 / (t%young * height**3)
        c_s = c_s + weight(q) * span * 1.2_dp * cos_b**2 / (t%shear * height)
        c_a = c_a + weight(q) * span * sin_b**2 / (t%young * height)
      end do
    end if

    ! involute part, in the pressure angle alpha of the section's flank point
    if (t%internal) then
      lo = alpha_c
      hi = t%alpha_root
    else
      lo = t%alpha_root
      hi = alpha_c
    end if
    nb = 2
    breaks(1) = lo
    breaks(2) = hi
    if (damaged .and. d%kind == fault_crack) then
      alpha_g = clip_angle(t, d%y_tip)
      if (alpha_g > lo .and. alpha_g < hi) call insert_break(breaks, nb, alpha_g)
    else if (damaged .and. d%kind == fault_spall) then
      if (d%alpha_lo > lo .and. d%alpha_lo < hi) call insert_break(breaks, nb, d%alpha_lo)
      if (d%alpha_hi > lo .and. d%alpha_hi < hi) call insert_break(breaks, nb, d%alpha_hi)
    end if
    do j = 1, nb - 1
      span = 0.5_dp * (breaks(j + 1) - breaks(j))
      mid = 0.5_dp * (breaks(j + 1) + breaks(j))
      if (span <= 0.0_dp) cycle
      do i = 1, size(node)
        alpha = mid + span * node(i)
        r = t%r_b / cos(alpha)
        psi = half_angle(t, alpha)
        x = r * cos(psi)
        h = r * sin(psi)
        if (t%internal) then
          dx = r * tan(alpha) * (cos(psi) - tan(alpha) * sin(psi))
        else
          dx = r * tan(alpha) * (cos(psi) + tan(alpha) * sin(psi))
        end if
        dx = abs(dx) * span * weight(i)
        height = bearing_height(h, alpha, damaged, d)
        arm = cos_b * abs(x_p - x) - sin_b * y_p
        c_b = c_b + dx * 12.0_dp * arm**2 / (t%young * height**3)
        c_s = c_s + dx * 1.2_dp * cos_b**2 / (t%shear * height)
        c_a = c_a + dx * sin_b**2 / (t%young * height)
      end do
    end do
  end subroutine beam_compliance

  !> Pressure angle of the involute section whose half height equals y (bisection;
  !> -1 when no section of the involute has that half height).
  pure real(dp) function clip_angle(t, y)
    type(tooth_shape), intent(in) :: t  !< the tooth
    real(dp), intent(in) :: y          !< half height [m]
    real(dp) :: a, b, m, f_a, f_m
    integer :: k
    a = t%alpha_root
    b = acos(t%r_b / t%r_a)
    if (t%internal) then
      a = acos(t%r_b / t%r_a)
      b = t%alpha_root
    end if
    f_a = t%r_b / cos(a) * sin(half_angle(t, a)) - y
    if (f_a * (t%r_b / cos(b) * sin(half_angle(t, b)) - y) > 0.0_dp) then
      clip_angle = -1.0_dp
      return
    end if
    do k = 1, 200
      m = 0.5_dp * (a + b)
      f_m = t%r_b / cos(m) * sin(half_angle(t, m)) - y
      if (f_a * f_m <= 0.0_dp) then
        b = m
      else
        a = m
        f_a = f_m
      end if
      if (b - a < 1.0e-15_dp) exit
    end do
    clip_angle = 0.5_dp * (a + b)
  end function clip_angle

  pure subroutine insert_break(breaks, nb, value)
    real(dp), intent(inout) :: breaks(:)  !< sorted break points, involute angles [rad]
    integer, intent(inout) :: nb  !< break points in use [-]
    real(dp), intent(in) :: value  !< break point to insert [rad]
    integer :: k
    k = nb
    do while (k >= 1)
      if (breaks(k) <= value) exit
      breaks(k + 1) = breaks(k)
      k = k - 1
    end do
    breaks(k + 1) = value
    nb = nb + 1
  end subroutine insert_break

  !> Fillet-foundation compliance per unit face width, Sainsot et al. (2004).
  pure real(dp) function foundation_compliance(t, alpha_c, beta)
    type(tooth_shape), intent(in) :: t  !< the tooth
    real(dp), intent(in) :: alpha_c   !< contact pressure angle [rad]
    real(dp), intent(in) :: beta      !< load angle [rad]
    real(dp) :: r_c, psi_c, u_f, s_f
    foundation_compliance = 0.0_dp
    if (.not. t%foundation) return
    r_c = t%r_b / cos(alpha_c)
    psi_c = half_angle(t, alpha_c)
    u_f = r_c * cos(psi_c) - r_c * sin(psi_c) * tan(beta) - t%r_f
    s_f = 2.0_dp * t%r_f * t%theta_f
    foundation_compliance = cos(beta)**2 / t%young * (t%lmpq(1) * (u_f / s_f)**2 &
                            + t%lmpq(2) * u_f / s_f + t%lmpq(3) * (1.0_dp + t%lmpq(4) * tan(beta)**2))
  end function foundation_compliance

  ! ------------------------------------------------------------ tooth and pair

  !> Compliances of one tooth over a face-width slice [z0, z0 + w] with the damage
  !> (if any) at a contact of roll distance s.  loaded_width is the width in contact.
  pure subroutine slice_compliance(t, s, z0, w, has_damage, d, node, weight, c, loaded_width)
    type(tooth_shape), intent(in) :: t  !< the tooth
    real(dp), intent(in) :: s              !< roll distance of the contact [m]
    real(dp), intent(in) :: z0, w          !< slice start and width along the face [m]
    logical, intent(in) :: has_damage      !< this tooth carries the damage
    type(tooth_damage), intent(in) :: d  !< the damage
    real(dp), intent(in) :: node(:)    !< Gauss-Legendre nodes on [-1, 1] [-]
    real(dp), intent(in) :: weight(:)  !< Gauss-Legendre weights [-]
    real(dp), intent(out) :: c(4)          !< bending, shear, axial, foundation [m/N]
    real(dp), intent(out) :: loaded_width  !< width in contact [m]
    real(dp) :: alpha_c, hb(3), db(3), beta, w_dam, w_int, r_c
    logical :: in_band

    alpha_c = atan(s / t%r_b)
    r_c = t%r_b / cos(alpha_c)
    call beam_compliance(t, alpha_c, .false., d, node, weight, hb(1), hb(2), hb(3), beta)
    w_dam = 0.0_dp
    if (has_damage .and. d%kind /= fault_none) &
      w_dam = max(0.0_dp, min(z0 + w, d%face_start + d%face_width) - max(z0, d%face_start))
    w_int = w - w_dam
    loaded_width = w
    c(1:3) = hb / w
    if (w_dam > 0.0_dp) then
      select case (d%kind)
      case (fault_chip)
        ! the chipped width makes no contact beyond r_chip; below it the tooth is whole
        in_band = (.not. t%internal .and. r_c > d%r_chip) .or. (t%internal .and. r_c < d%r_chip)
        if (in_band) then
          loaded_width = w_int
          c(1:3) = 0.0_dp
          if (w_int > 0.0_dp) c(1:3) = hb / w_int
        end if
      case default
        call beam_compliance(t, alpha_c, .true., d, node, weight, db(1), db(2), db(3), beta)
        if (d%kind == fault_spall .and. alpha_c >= d%alpha_lo .and. alpha_c <= d%alpha_hi) &
          loaded_width = w_int
        ! damaged and intact widths in parallel, mechanism by mechanism
        c(1:3) = 1.0_dp / (w_int / hb + w_dam / db)
      end select
    end if
    if (loaded_width > 0.0_dp) then
      c(4) = foundation_compliance(t, alpha_c, beta) / loaded_width
    else
      c(4) = 0.0_dp
    end if
  end subroutine slice_compliance

  !> Stiffness of one tooth pair (a face-width slice) at transverse position p, with
  !> the breakdown of compliances (Hertz, then b s a f of tooth 1 and of tooth 2).
  pure subroutine slice_pair(mesh, p, z0, w, damaged_tooth, d, node, weight, k, breakdown)
    type(mesh_shape), intent(in) :: mesh  !< the mesh
    real(dp), intent(in) :: p               !< transverse position [mesh cycles]
    real(dp), intent(in) :: z0, w           !< slice along the face [m]
    integer, intent(in) :: damaged_tooth    !< 0, 1 or 2 (computation order) [-]
    type(tooth_damage), intent(in) :: d  !< the damage
    real(dp), intent(in) :: node(:)    !< Gauss-Legendre nodes on [-1, 1] [-]
    real(dp), intent(in) :: weight(:)  !< Gauss-Legendre weights [-]
    real(dp), intent(out) :: k              !< pair stiffness [N/m]
    real(dp), intent(out) :: breakdown(n_compliance_out)   !< compliances [m/N]
    real(dp) :: c(4), loaded(2), contact_width
    integer :: g

    breakdown = 0.0_dp
    k = 0.0_dp
    if (p < 0.0_dp .or. p > mesh%eps_alpha) return
    do g = 1, 2
      call slice_compliance(mesh%tooth(g), contact_roll(mesh, g, p), z0, w, damaged_tooth == g, &
                            d, node, weight, c, loaded(g))
      breakdown(4 * g - 2:4 * g + 1) = c
    end do
    contact_width = min(loaded(1), loaded(2))
    if (contact_width <= 0.0_dp) then
      breakdown = 0.0_dp
      return
    end if
    breakdown(1) = 1.0_dp / (mesh%hertz_per_width * contact_width)
    k = 1.0_dp / sum(breakdown)
  end subroutine slice_pair

  !> Pair stiffness at position p of a (helical) pair cut into n_slice face slices, each
  !> shifted by eps_beta / n_slice along the path; spur gears have one slice.
  pure real(dp) function pair_stiffness(mesh, p, n_slice, damaged_tooth, d, node, weight)
    type(mesh_shape), intent(in) :: mesh  !< the mesh
    real(dp), intent(in) :: p               !< position from the pair's entry [mesh cycles]
    integer, intent(in) :: n_slice          !< face-width slices [-]
    integer, intent(in) :: damaged_tooth    !< 0, 1 or 2 (computation order) [-]
    type(tooth_damage), intent(in) :: d  !< the damage
    real(dp), intent(in) :: node(:)    !< Gauss-Legendre nodes on [-1, 1] [-]
    real(dp), intent(in) :: weight(:)  !< Gauss-Legendre weights [-]
    real(dp) :: w, shift, k, breakdown(n_compliance_out)
    integer :: j

    pair_stiffness = 0.0_dp
    w = mesh%width / n_slice
    do j = 0, n_slice - 1
      shift = 0.0_dp
      if (mesh%eps_beta > 0.0_dp) shift = (j + 0.5_dp) * mesh%eps_beta / n_slice
      call slice_pair(mesh, p - shift, j * w, w, damaged_tooth, d, node, weight, k, breakdown)
      pair_stiffness = pair_stiffness + k
    end do
  end function pair_stiffness

  ! ------------------------------------------------------------- public entry

  !> Geometry of a mesh: summary(1:16) = eps_alpha, eps_beta, base pitch [m], centre
  !> distance [m], working pressure angle [rad], r_b1, r_a1, r_f1, r_b2, r_a2, r_f2 [m],
  !> roll distance of gear 1's contact at the start and end of contact [m], theta_f1,
  !> theta_f2 [rad], loaded face width [m].  Gear order as given.
  pure subroutine mesh_geometry_summary(gear, mesh_param, summary, bad_param, ierr)
    real(dp), intent(in) :: gear(n_gear_param, 2)   !< gear parameters (see docs) [m, rad, Pa, -]
    real(dp), intent(in) :: mesh_param(n_mesh_param) !< centre distance [m], alpha_wt [rad]
    real(dp), intent(out) :: summary(n_geometry_out) !< geometry summary [-, m, rad]
    integer(ik), intent(out) :: bad_param            !< 100 g + index of the bad parameter [-]
    integer(ik), intent(out) :: ierr                 !< error code
    type(mesh_shape) :: mesh
    integer :: a, b

    summary = 0.0_dp
    call build_mesh(gear, mesh_param, mesh, bad_param, ierr)
    if (ierr /= pe_ok) return
    a = 1
    b = 2
    if (mesh%swapped) then
      a = 2
      b = 1
    end if
    summary(1) = mesh%eps_alpha
    summary(2) = mesh%eps_beta
    summary(3) = mesh%base_pitch
    summary(4) = mesh%centre_distance
    summary(5) = mesh%alpha_w
    summary(6:8) = [mesh%tooth(a)%r_b, mesh%tooth(a)%r_a, mesh%tooth(a)%r_f]
    summary(9:11) = [mesh%tooth(b)%r_b, mesh%tooth(b)%r_a, mesh%tooth(b)%r_f]
    summary(12) = mesh%s_start
    summary(13) = mesh%s_end
    summary(14) = mesh%tooth(a)%theta_f
    summary(15) = mesh%tooth(b)%theta_f
    summary(16) = mesh%width
  end subroutine mesh_geometry_summary

  !> Single-pair curves and mesh stiffness of one mesh.
  !>
  !> pair_healthy(q) and pair_faulty(q) at p = eps (q - 1) / (n_sample - 1), eps =
  !> eps_alpha + eps_beta, p = 0 at the start of contact when gear 1 drives (gear 1's
  !> root, gear 2's tip).  pair_faulty is the pair that holds the damaged tooth.
  !> breakdown(:, q): the spur (one-slice, whole face) compliances at p = eps_alpha
  !> (q - 1) / (n_sample - 1): Hertz, then bending, shear, axial, foundation of gear 1
  !> and of gear 2.  mesh_healthy(j): total stiffness at s = (j - 1) / n_cycle;
  !> mesh_faulty(j): the same over n_window cycles while the damaged tooth passes,
  !> its pair entering at s = 0.
  pure subroutine mesh_stiffness_curves(gear, mesh_param, fault, n_sample, n_cycle, n_window, n_slice, n_quad, &
                                        pair_healthy, pair_faulty, breakdown, mesh_healthy, &
                                        mesh_faulty, bad_param, ierr)
    real(dp), intent(in) :: gear(n_gear_param, 2)   !< gear parameters [m, rad, Pa, -]
    real(dp), intent(in) :: mesh_param(n_mesh_param) !< centre distance [m], alpha_wt [rad]
    real(dp), intent(in) :: fault(n_fault_param)    !< packed fault (kind 0: none) [-, -, m, m, m or rad]
    integer(ik), intent(in) :: n_sample             !< samples of the pair curves [-]
    integer(ik), intent(in) :: n_cycle              !< samples per mesh cycle [-]
    integer(ik), intent(in) :: n_window             !< cycles of mesh_faulty [-]
    integer(ik), intent(in) :: n_slice              !< face-width slices (helical) [-]
    integer(ik), intent(in) :: n_quad               !< Gauss points per segment [-]
    real(dp), intent(out) :: pair_healthy(n_sample) !< healthy pair stiffness [N/m]
    real(dp), intent(out) :: pair_faulty(n_sample)  !< pair with the damaged tooth [N/m]
    real(dp), intent(out) :: breakdown(n_compliance_out, n_sample) !< spur compliances [m/N]
    real(dp), intent(out) :: mesh_healthy(n_cycle)  !< mesh stiffness over one cycle [N/m]
    real(dp), intent(out) :: mesh_faulty(n_cycle * n_window) !< mesh stiffness, damaged pass [N/m]
    integer(ik), intent(out) :: bad_param           !< 100 g + index, or 1000 + fault index [-]
    integer(ik), intent(out) :: ierr                !< error code
    type(mesh_shape) :: mesh
    type(tooth_damage) :: d, no_damage
    real(dp) :: node(max_quad), weight(max_quad), eps, p, k, s
    integer :: q, j, m, damaged_tooth, n_pair, slices
    integer(ik) :: bad

    pair_healthy = 0.0_dp
    pair_faulty = 0.0_dp
    breakdown = 0.0_dp
    mesh_healthy = 0.0_dp
    mesh_faulty = 0.0_dp
    bad_param = 0
    ierr = pe_ok
    if (n_sample < 2 .or. n_cycle < 1 .or. n_window < 1 .or. n_slice < 1 .or. n_quad < 1 &
        .or. n_quad > max_quad) then
      ierr = pe_err_size
      return
    end if
    call build_mesh(gear, mesh_param, mesh, bad_param, ierr)
    if (ierr /= pe_ok) return
    slices = int(n_slice)
    if (mesh%eps_beta <= 0.0_dp) slices = 1
    eps = mesh%eps_alpha + mesh%eps_beta
    if (real(n_window, dp) < eps) then
      ierr = pe_err_size
      return
    end if
    damaged_tooth = 0
    if (nint(fault(fp_kind)) /= fault_none) then
      if (.not. (fault(fp_gear) == 1.0_dp .or. fault(fp_gear) == 2.0_dp)) then
        bad_param = 1000 + fp_gear
        ierr = pe_err_argument
        return
      end if
      damaged_tooth = nint(fault(fp_gear))
      if (mesh%swapped) damaged_tooth = 3 - damaged_tooth
      call build_damage(mesh%tooth(damaged_tooth), fault, mesh%width, d, bad, ierr)
      if (ierr /= pe_ok) then
        bad_param = 1000 + bad
        return
      end if
    end if
    call gauss_legendre(int(n_quad), node(1:n_quad), weight(1:n_quad))
    associate (nd => node(1:n_quad), wt => weight(1:n_quad))
      do q = 1, int(n_sample)
        p = eps * (q - 1) / real(n_sample - 1, dp)
        pair_healthy(q) = oriented_pair(p, 0)
        pair_faulty(q) = pair_healthy(q)
        if (damaged_tooth /= 0) pair_faulty(q) = oriented_pair(p, damaged_tooth)
        p = mesh%eps_alpha * (q - 1) / real(n_sample - 1, dp)
        if (mesh%swapped) p = mesh%eps_alpha - p
        call slice_pair(mesh, p, 0.0_dp, mesh%width, 0, no_damage, nd, wt, k, breakdown(:, q))
        if (mesh%swapped) breakdown(2:9, q) = [breakdown(6:9, q), breakdown(2:5, q)]
      end do
      n_pair = ceiling(eps) + 1
      do j = 1, int(n_cycle)
        s = (j - 1) / real(n_cycle, dp)
        do m = 0, n_pair
          mesh_healthy(j) = mesh_healthy(j) + oriented_pair(s + m, 0)
        end do
      end do
      ! the damaged pair enters at s = 0; pair m entered m cycles earlier (m < 0: later)
      do j = 1, int(n_cycle * n_window)
        s = (j - 1) / real(n_cycle, dp)
        do m = -n_pair, n_pair
          if (m == 0) then
            mesh_faulty(j) = mesh_faulty(j) + oriented_pair(s, damaged_tooth)
          else
            mesh_faulty(j) = mesh_faulty(j) + oriented_pair(s - m, 0)
          end if
        end do
      end do
    end associate
  contains
    !> Pair stiffness at position p counted from the start of contact when gear 1
    !> drives; with gear 1 internal the computation runs the path backwards.
    pure real(dp) function oriented_pair(position, tooth)
      real(dp), intent(in) :: position   !< [mesh cycles]
      integer, intent(in) :: tooth       !< damaged tooth (computation order), 0 healthy [-]
      real(dp) :: p_comp
      oriented_pair = 0.0_dp
      if (position < 0.0_dp .or. position > eps) return
      p_comp = position
      if (mesh%swapped) p_comp = eps - position
      if (tooth == 0) then
        oriented_pair = pair_stiffness(mesh, p_comp, slices, 0, no_damage, node(1:n_quad), &
                                       weight(1:n_quad))
      else
        oriented_pair = pair_stiffness(mesh, p_comp, slices, tooth, d, node(1:n_quad), &
                                       weight(1:n_quad))
      end if
    end function oriented_pair
  end subroutine mesh_stiffness_curves

  !> Compliances of one tooth (gear parameters p) per its face width at contact radii
  !> contact_radius, with an optional fault (its gear index is ignored).
  !> compliance(:, i) = bending, shear, axial, foundation [m/N]; load_angle [rad].
  pure subroutine tooth_compliance(p, fault, n_point, contact_radius, n_quad, compliance, &
                                   load_angle, bad_param, ierr)
    real(dp), intent(in) :: p(n_gear_param)           !< gear parameters [m, rad, Pa, -]
    real(dp), intent(in) :: fault(n_fault_param)      !< packed fault (kind 0: none) [-, -, m, m, m or rad]
    integer(ik), intent(in) :: n_point                !< contact points [-]
    real(dp), intent(in) :: contact_radius(n_point)   !< contact radii [m]
    integer(ik), intent(in) :: n_quad                 !< Gauss points per segment [-]
    real(dp), intent(out) :: compliance(4, n_point)   !< b, s, a, f compliances [m/N]
    real(dp), intent(out) :: load_angle(n_point)      !< load angle beta [rad]
    integer(ik), intent(out) :: bad_param             !< index of the bad parameter [-]
    integer(ik), intent(out) :: ierr                  !< error code
    type(tooth_shape) :: t
    type(tooth_damage) :: d
    real(dp) :: node(max_quad), weight(max_quad), loaded, lo, hi, alpha_c, beta, c(3)
    integer :: i
    integer(ik) :: bad

    compliance = 0.0_dp
    load_angle = 0.0_dp
    bad_param = 0
    ierr = pe_ok
    if (n_quad < 1 .or. n_quad > max_quad) then
      ierr = pe_err_size
      return
    end if
    call build_tooth(p, t, bad, ierr)
    if (ierr /= pe_ok) then
      bad_param = 100 + bad
      return
    end if
    call build_damage(t, fault, t%width, d, bad, ierr)
    if (ierr /= pe_ok) then
      bad_param = 1000 + bad
      return
    end if
    lo = max(t%r_b, t%r_f)
    hi = t%r_a
    if (t%internal) then
      lo = t%r_a
      hi = t%r_f
    end if
    call gauss_legendre(int(n_quad), node(1:n_quad), weight(1:n_quad))
    do i = 1, int(n_point)
      if (.not. (contact_radius(i) >= lo .and. contact_radius(i) <= hi)) then
        bad_param = 2000 + i
        ierr = pe_err_argument
        return
      end if
      call slice_compliance(t, sqrt(contact_radius(i)**2 - t%r_b**2), 0.0_dp, t%width, &
                            d%kind /= fault_none, d, node(1:n_quad), weight(1:n_quad), &
                            compliance(:, i), loaded)
      alpha_c = acos(t%r_b / contact_radius(i))
      call beam_compliance(t, alpha_c, .false., d, node(1:n_quad), weight(1:n_quad), &
                           c(1), c(2), c(3), beta)
      load_angle(i) = beta
    end do
  end subroutine tooth_compliance
end module tooth_potential_energy
