!> Tooth and mesh stiffness of cylindrical involute gears by ISO 6336-1:2019,
!> clause 9, method B (docs/gear_geometry.md gives the equations and sources).
!>
!>   q'      = C1 + C2/zn1 + C3/zn2 + C4 x1 + C5 x1/zn1 + C6 x2 + C7 x2/zn2
!>             + C8 x1**2 + C9 x2**2                         [mm um/N]
!>   c'_th   = 1/q'                                          [N/(mm um)]
!>   c'      = c'_th C_M C_R C_B cos(beta) (K_A F_t/b / 100)**0.25 below 100 N/mm
!>   c_ga    = c' (0.75 eps_alpha + 0.25),   c_gb = 0.85 c_ga
!>
!> zn = z / (cos(beta_b)**2 cos(beta)) is the virtual number of teeth; for an
!> internal gear (gear 2 of an internal mesh) ISO sets zn2 to infinity, so the
!> terms in 1/zn2 vanish.  Solid gear blanks have C_R = 1 (web width equal to
!> the face width).  Every routine is pure; the one entry point that checks its
!> pair returns an error code instead of stopping.
module iso6336_stiffness
  use kinds, only: dp, ik
  implicit none
  private

  public :: virtual_teeth, minimum_flexibility, basic_rack_factor, gear_blank_factor
  public :: low_load_factor, mesh_stiffness_from_single, total_stiffness
  public :: iso_gear_pair, iso_stiffness, iso_mesh_stiffness
  public :: iso_ok, iso_err_argument, iso_err_range
  public :: correction_factor_cm, reference_line_load

  integer(ik), parameter :: iso_ok = 0            !< success
  integer(ik), parameter :: iso_err_argument = 1  !< a physical argument is out of range
  integer(ik), parameter :: iso_err_range = 3     !< outside the range of ISO's regression

  !> Coefficients C1..C9 of the q' series, ISO 6336-1:2019 clause 9 (method B)
  real(dp), parameter :: c1 = 0.04723_dp, c2 = 0.15551_dp, c3 = 0.25791_dp
  real(dp), parameter :: c4 = -0.00635_dp, c5 = -0.11654_dp, c6 = -0.00193_dp
  real(dp), parameter :: c7 = -0.24188_dp, c8 = 0.00529_dp, c9 = 0.00182_dp

  real(dp), parameter :: correction_factor_cm = 0.8_dp  !< C_M, solid-disc correction [-]
  real(dp), parameter :: reference_line_load = 100.0_dp !< K_A F_t/b above which c' is load-free [N/mm]
  real(dp), parameter :: deg = 0.017453292519943295769236907684886_dp  !< one degree [rad]

  !> One gear pair and its load, as method B takes them.
  type :: iso_gear_pair
    real(dp) :: teeth1 = 0.0_dp               !< z1, gear 1 (pinion) [-]
    real(dp) :: teeth2 = 0.0_dp               !< |z2|, gear 2 [-]
    integer(ik) :: internal = 0               !< 1: gear 2 internal, 0: external [-]
    real(dp) :: shift1 = 0.0_dp               !< x1 [-]
    real(dp) :: shift2 = 0.0_dp               !< x2 (ISO 21771 sign) [-]
    real(dp) :: helix_deg = 0.0_dp            !< |beta| at the reference circle [deg]
    real(dp) :: base_helix_deg = 0.0_dp       !< |beta_b| [deg]
    real(dp) :: pressure_angle_deg = 0.0_dp   !< alpha_n = alpha_Pn [deg]
    real(dp) :: dedendum1 = 0.0_dp            !< h_fP1/m_n [-]
    real(dp) :: dedendum2 = 0.0_dp            !< h_fP2/m_n [-]
    real(dp) :: web_width_ratio = 1.0_dp      !< b_s/b; 1 for solid gears [-]
    real(dp) :: rim_thickness_ratio = 0.0_dp  !< s_R/m_n [-]
    real(dp) :: line_load = 0.0_dp            !< K_A F_t/b [N/mm]
    real(dp) :: contact_ratio = 0.0_dp        !< eps_alpha [-]
    real(dp) :: face_width = 0.0_dp           !< b [m]
  end type iso_gear_pair

  !> Every factor of method B for one pair.
  type :: iso_stiffness
    real(dp) :: zn1 = 0.0_dp           !< virtual teeth of gear 1 [-]
    real(dp) :: zn2 = 0.0_dp           !< virtual teeth of gear 2 (0 when internal) [-]
    real(dp) :: flexibility = 0.0_dp   !< q' [mm um/N]
    real(dp) :: theoretical = 0.0_dp   !< c'_th [N/(mm um)]
    real(dp) :: blank_factor = 0.0_dp  !< C_R [-]
    real(dp) :: rack_factor = 0.0_dp   !< C_B = (C_B1 + C_B2)/2 [-]
    real(dp) :: load_factor = 0.0_dp   !< (K_A F_t/b / 100)**0.25 or 1 [-]
    real(dp) :: single = 0.0_dp        !< c' [N/(mm um)]
    real(dp) :: mesh_alpha = 0.0_dp    !< c_gamma_alpha [N/(mm um)]
    real(dp) :: mesh_beta = 0.0_dp     !< c_gamma_beta [N/(mm um)]
    real(dp) :: total_single = 0.0_dp  !< c' b [N/m]
    real(dp) :: total_alpha = 0.0_dp   !< c_gamma_alpha b [N/m]
    real(dp) :: total_beta = 0.0_dp    !< c_gamma_beta b [N/m]
  end type iso_stiffness

contains

  !> Virtual (normal-section) number of teeth zn = z / (cos(beta_b)**2 cos(beta)).
  pure elemental function virtual_teeth(teeth, helix_deg, base_helix_deg) result(zn)
    real(dp), intent(in) :: teeth           !< number of teeth z [-]
    real(dp), intent(in) :: helix_deg       !< reference helix angle beta [deg]
    real(dp), intent(in) :: base_helix_deg  !< base helix angle beta_b [deg]
    real(dp) :: zn                          !< virtual number of teeth [-]
    zn = teeth / (cos(base_helix_deg * deg)**2 * cos(helix_deg * deg))
  end function virtual_teeth

  !> Minimum flexibility of a tooth pair q' [mm um/N], ISO 6336-1 method B.
  !> With internal /= 0, zn2 is taken as infinite (ISO's rule for internal gears).
  pure function minimum_flexibility(zn1, zn2, x1, x2, internal) result(q)
    real(dp), intent(in) :: zn1       !< virtual teeth of gear 1 (pinion) [-]
    real(dp), intent(in) :: zn2       !< virtual teeth of gear 2; unused when internal [-]
    real(dp), intent(in) :: x1        !< profile shift coefficient of gear 1 [-]
    real(dp), intent(in) :: x2        !< profile shift coefficient of gear 2 [-]
    integer(ik), intent(in) :: internal  !< 1: gear 2 is an internal gear, 0: external [-]
    real(dp) :: q                     !< q' [mm um/N]
    real(dp) :: inv_zn2

    inv_zn2 = 0.0_dp
    if (internal == 0) inv_zn2 = 1.0_dp / zn2
    q = c1 + c2 / zn1 + c3 * inv_zn2 + c4 * x1 + c5 * x1 / zn1 + c6 * x2 &
        + c7 * x2 * inv_zn2 + c8 * x1**2 + c9 * x2**2
  end function minimum_flexibility

  !> Basic rack factor of one gear, C_B = [1 + 0.5 (1.2 - h_fP/m_n)] [1 - 0.02 (20 - alpha_Pn)].
  pure elemental function basic_rack_factor(dedendum_factor, pressure_angle_deg) result(cb)
    real(dp), intent(in) :: dedendum_factor     !< h_fP/m_n of the basic rack [-]
    real(dp), intent(in) :: pressure_angle_deg  !< alpha_Pn, basic rack pressure angle [deg]
    real(dp) :: cb                              !< C_B [-]
    cb = (1.0_dp + 0.5_dp * (1.2_dp - dedendum_factor)) &
         * (1.0_dp - 0.02_dp * (20.0_dp - pressure_angle_deg))
  end function basic_rack_factor

  !> Gear blank factor C_R = 1 + ln(b_s/b) / (5 exp(s_R/(5 m_n))), with b_s/b held
  !> in [0.2, 1.2] and s_R/m_n at 1 or more as ISO prescribes; b_s/b = 1 (solid
  !> disc) gives exactly 1.
  pure elemental function gear_blank_factor(web_width_ratio, rim_thickness_ratio) result(cr)
    real(dp), intent(in) :: web_width_ratio      !< b_s/b, web width over face width [-]
    real(dp), intent(in) :: rim_thickness_ratio  !< s_R/m_n, rim thickness over module [-]
    real(dp) :: cr                               !< C_R [-]
    real(dp) :: ratio, rim

    ratio = min(max(web_width_ratio, 0.2_dp), 1.2_dp)
    rim = max(rim_thickness_ratio, 1.0_dp)
    cr = 1.0_dp + log(ratio) / (5.0_dp * exp(rim / 5.0_dp))
  end function gear_blank_factor

  !> Load correction of c': (K_A F_t/b / 100)**0.25 below 100 N/mm, 1 above.
  pure elemental function low_load_factor(line_load) result(factor)
    real(dp), intent(in) :: line_load  !< K_A F_t/b [N/mm]
    real(dp) :: factor                 !< multiplier of c' [-]
    if (line_load >= reference_line_load) then
      factor = 1.0_dp
    else
      factor = (line_load / reference_line_load)**0.25_dp
    end if
  end function low_load_factor

  !> Mean mesh stiffness per unit face width c_gamma_alpha = c' (0.75 eps_alpha + 0.25)
  !> and c_gamma_beta = 0.85 c_gamma_alpha.
  pure subroutine mesh_stiffness_from_single(single, contact_ratio, mesh_alpha, mesh_beta)
    real(dp), intent(in) :: single         !< c' [N/(mm um)]
    real(dp), intent(in) :: contact_ratio  !< transverse contact ratio eps_alpha [-]
    real(dp), intent(out) :: mesh_alpha    !< c_gamma_alpha [N/(mm um)]
    real(dp), intent(out) :: mesh_beta     !< c_gamma_beta [N/(mm um)]
    mesh_alpha = single * (0.75_dp * contact_ratio + 0.25_dp)
    mesh_beta = 0.85_dp * mesh_alpha
  end subroutine mesh_stiffness_from_single

  !> Stiffness of the whole face width: c [N/(mm um)] x b [mm] = c b 1e3 [N/um] = c b 1e9 [N/m].
  pure elemental function total_stiffness(per_width, face_width) result(total)
    real(dp), intent(in) :: per_width   !< stiffness per unit face width [N/(mm um)]
    real(dp), intent(in) :: face_width  !< face width b [m]
    real(dp) :: total                   !< stiffness of the face width [N/m]
    total = per_width * face_width * 1.0e9_dp
  end function total_stiffness

  !> ISO 6336-1 method B single and mesh stiffness of one gear pair, with every
  !> factor returned.  The pair is checked first: ierr = iso_err_argument for a
  !> non-physical value, iso_err_range outside the regression's range (x1 >= x2
  !> for external pairs, -0.5 <= x1 + x2 <= 2).  Factors are zero on error.
  pure subroutine iso_mesh_stiffness(pair, factors, ierr)
    type(iso_gear_pair), intent(in) :: pair         !< the gear pair and its load
    type(iso_stiffness), intent(out) :: factors     !< every factor of the method
    integer(ik), intent(out) :: ierr                !< error code (0 = ok)

    factors = iso_stiffness()
    ierr = iso_ok

    associate (p => pair, f => factors)
      if (.not. (p%teeth1 >= 1.0_dp .and. p%teeth2 >= 1.0_dp) .or. (p%internal /= 0 .and. p%internal /= 1) &
          .or. .not. (p%helix_deg >= 0.0_dp .and. p%helix_deg < 45.0_dp) &
          .or. .not. (p%base_helix_deg >= 0.0_dp .and. p%base_helix_deg <= p%helix_deg) &
          .or. .not. (p%pressure_angle_deg > 0.0_dp .and. p%pressure_angle_deg < 45.0_dp) &
          .or. .not. (p%dedendum1 > 0.0_dp .and. p%dedendum2 > 0.0_dp) &
          .or. .not. (p%web_width_ratio > 0.0_dp .and. p%rim_thickness_ratio > 0.0_dp) &
          .or. .not. (p%line_load > 0.0_dp) .or. .not. (p%contact_ratio >= 1.0_dp) &
          .or. .not. (p%face_width > 0.0_dp) .or. .not. (abs(p%shift1) <= 3.0_dp) &
          .or. .not. (abs(p%shift2) <= 3.0_dp)) then
        ierr = iso_err_argument
        return
      end if
      if ((p%internal == 0 .and. p%shift1 < p%shift2) .or. p%shift1 + p%shift2 < -0.5_dp &
          .or. p%shift1 + p%shift2 > 2.0_dp) then
        ierr = iso_err_range
        return
      end if

      f%zn1 = virtual_teeth(p%teeth1, p%helix_deg, p%base_helix_deg)
      if (p%internal == 0) f%zn2 = virtual_teeth(p%teeth2, p%helix_deg, p%base_helix_deg)
      f%flexibility = minimum_flexibility(f%zn1, f%zn2, p%shift1, p%shift2, p%internal)
      if (.not. (f%flexibility > 0.0_dp)) then
        ierr = iso_err_range
        return
      end if
      f%theoretical = 1.0_dp / f%flexibility
      f%blank_factor = gear_blank_factor(p%web_width_ratio, p%rim_thickness_ratio)
      f%rack_factor = 0.5_dp * (basic_rack_factor(p%dedendum1, p%pressure_angle_deg) &
                                + basic_rack_factor(p%dedendum2, p%pressure_angle_deg))
      f%load_factor = low_load_factor(p%line_load)
      f%single = f%theoretical * correction_factor_cm * f%blank_factor * f%rack_factor &
                 * cos(p%helix_deg * deg) * f%load_factor
      call mesh_stiffness_from_single(f%single, p%contact_ratio, f%mesh_alpha, f%mesh_beta)
      f%total_single = total_stiffness(f%single, p%face_width)
      f%total_alpha = total_stiffness(f%mesh_alpha, p%face_width)
      f%total_beta = total_stiffness(f%mesh_beta, p%face_width)
    end associate
  end subroutine iso_mesh_stiffness

end module iso6336_stiffness
