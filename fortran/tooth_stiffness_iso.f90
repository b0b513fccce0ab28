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
!> arguments returns an error code instead of stopping.
module iso6336_stiffness
  use kinds, only: dp, ik
  implicit none
  private

  public :: virtual_teeth, minimum_flexibility, basic_rack_factor, gear_blank_factor
  public :: low_load_factor, mesh_stiffness_from_single, total_stiffness
  public :: iso_mesh_stiffness
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
  !> factor returned.  Arguments are checked first: ierr = iso_err_argument for a
  !> non-physical value, iso_err_range outside the regression's range (x1 >= x2
  !> for external pairs, -0.5 <= x1 + x2 <= 2).  Outputs are zero on error.
  pure subroutine iso_mesh_stiffness(teeth1, teeth2, internal, shift1, shift2, helix_deg, &
                                     base_helix_deg, pressure_angle_deg, dedendum1, dedendum2, &
                                     web_width_ratio, rim_thickness_ratio, line_load, &
                                     contact_ratio, face_width, zn1, zn2, flexibility, &
                                     theoretical, blank_factor, rack_factor, load_factor, &
                                     single, mesh_alpha, mesh_beta, total_single, total_alpha, &
                                     total_beta, ierr)
    real(dp), intent(in) :: teeth1               !< z1, gear 1 (pinion) [-]
    real(dp), intent(in) :: teeth2               !< |z2|, gear 2 [-]
    integer(ik), intent(in) :: internal          !< 1: gear 2 internal, 0: external [-]
    real(dp), intent(in) :: shift1               !< x1 [-]
    real(dp), intent(in) :: shift2               !< x2 (ISO 21771 sign) [-]
    real(dp), intent(in) :: helix_deg            !< |beta| at the reference circle [deg]
    real(dp), intent(in) :: base_helix_deg       !< |beta_b| [deg]
    real(dp), intent(in) :: pressure_angle_deg   !< alpha_n = alpha_Pn [deg]
    real(dp), intent(in) :: dedendum1            !< h_fP1/m_n [-]
    real(dp), intent(in) :: dedendum2            !< h_fP2/m_n [-]
    real(dp), intent(in) :: web_width_ratio      !< b_s/b; 1 for solid gears [-]
    real(dp), intent(in) :: rim_thickness_ratio  !< s_R/m_n [-]
    real(dp), intent(in) :: line_load            !< K_A F_t/b [N/mm]
    real(dp), intent(in) :: contact_ratio        !< eps_alpha [-]
    real(dp), intent(in) :: face_width           !< b [m]
    real(dp), intent(out) :: zn1                 !< virtual teeth of gear 1 [-]
    real(dp), intent(out) :: zn2                 !< virtual teeth of gear 2 (0 when internal) [-]
    real(dp), intent(out) :: flexibility         !< q' [mm um/N]
    real(dp), intent(out) :: theoretical         !< c'_th [N/(mm um)]
    real(dp), intent(out) :: blank_factor        !< C_R [-]
    real(dp), intent(out) :: rack_factor         !< C_B = (C_B1 + C_B2)/2 [-]
    real(dp), intent(out) :: load_factor         !< (K_A F_t/b / 100)**0.25 or 1 [-]
    real(dp), intent(out) :: single              !< c' [N/(mm um)]
    real(dp), intent(out) :: mesh_alpha          !< c_gamma_alpha [N/(mm um)]
    real(dp), intent(out) :: mesh_beta           !< c_gamma_beta [N/(mm um)]
    real(dp), intent(out) :: total_single        !< c' b [N/m]
    real(dp), intent(out) :: total_alpha         !< c_gamma_alpha b [N/m]
    real(dp), intent(out) :: total_beta          !< c_gamma_beta b [N/m]
    integer(ik), intent(out) :: ierr             !< error code (0 = ok)

    zn1 = 0.0_dp
    zn2 = 0.0_dp
    flexibility = 0.0_dp
    theoretical = 0.0_dp
    blank_factor = 0.0_dp
    rack_factor = 0.0_dp
    load_factor = 0.0_dp
    single = 0.0_dp
    mesh_alpha = 0.0_dp
    mesh_beta = 0.0_dp
    total_single = 0.0_dp
    total_alpha = 0.0_dp
    total_beta = 0.0_dp
    ierr = iso_ok

    if (.not. (teeth1 >= 1.0_dp .and. teeth2 >= 1.0_dp) .or. (internal /= 0 .and. internal /= 1) &
        .or. .not. (helix_deg >= 0.0_dp .and. helix_deg < 45.0_dp) &
        .or. .not. (base_helix_deg >= 0.0_dp .and. base_helix_deg <= helix_deg) &
        .or. .not. (pressure_angle_deg > 0.0_dp .and. pressure_angle_deg < 45.0_dp) &
        .or. .not. (dedendum1 > 0.0_dp .and. dedendum2 > 0.0_dp) &
        .or. .not. (web_width_ratio > 0.0_dp .and. rim_thickness_ratio > 0.0_dp) &
        .or. .not. (line_load > 0.0_dp) .or. .not. (contact_ratio >= 1.0_dp) &
        .or. .not. (face_width > 0.0_dp) .or. .not. (abs(shift1) <= 3.0_dp) &
        .or. .not. (abs(shift2) <= 3.0_dp)) then
      ierr = iso_err_argument
      return
    end if
    if ((internal == 0 .and. shift1 < shift2) .or. shift1 + shift2 < -0.5_dp &
        .or. shift1 + shift2 > 2.0_dp) then
      ierr = iso_err_range
      return
    end if

    zn1 = virtual_teeth(teeth1, helix_deg, base_helix_deg)
    if (internal == 0) zn2 = virtual_teeth(teeth2, helix_deg, base_helix_deg)
    flexibility = minimum_flexibility(zn1, zn2, shift1, shift2, internal)
    if (.not. (flexibility > 0.0_dp)) then
      ierr = iso_err_range
      return
    end if
    theoretical = 1.0_dp / flexibility
    blank_factor = gear_blank_factor(web_width_ratio, rim_thickness_ratio)
    rack_factor = 0.5_dp * (basic_rack_factor(dedendum1, pressure_angle_deg) &
                            + basic_rack_factor(dedendum2, pressure_angle_deg))
    load_factor = low_load_factor(line_load)
    single = theoretical * correction_factor_cm * blank_factor * rack_factor &
             * cos(helix_deg * deg) * load_factor
    call mesh_stiffness_from_single(single, contact_ratio, mesh_alpha, mesh_beta)
    total_single = total_stiffness(single, face_width)
    total_alpha = total_stiffness(mesh_alpha, face_width)
    total_beta = total_stiffness(mesh_beta, face_width)
  end subroutine iso_mesh_stiffness

end module iso6336_stiffness
