!> The flat layer f2py sees for ISO 6336-1 method B tooth stiffness (module
!> iso6336_stiffness): scalars in (packed into a gear pair), every factor out (unpacked
!> from the module's result), an error code instead of a stop.

subroutine iso6336_mesh_stiffness(teeth1, teeth2, internal, shift1, shift2, helix_deg, &
                                  base_helix_deg, pressure_angle_deg, dedendum1, dedendum2, &
                                  web_width_ratio, rim_thickness_ratio, line_load, contact_ratio, &
                                  face_width, zn1, zn2, flexibility, theoretical, blank_factor, &
                                  rack_factor, load_factor, single, mesh_alpha, mesh_beta, &
                                  total_single, total_alpha, total_beta, ierr)
  use kinds, only: dp, ik
  use iso6336_stiffness, only: iso_gear_pair, iso_stiffness, iso_mesh_stiffness
  implicit none
  real(dp), intent(in) :: teeth1               !< z1 [-]
  real(dp), intent(in) :: teeth2               !< |z2| [-]
  integer(ik), intent(in) :: internal          !< 1 internal mesh, 0 external [-]
  real(dp), intent(in) :: shift1               !< x1 [-]
  real(dp), intent(in) :: shift2               !< x2, ISO 21771 sign [-]
  real(dp), intent(in) :: helix_deg            !< |beta| [deg]
  real(dp), intent(in) :: base_helix_deg       !< |beta_b| [deg]
  real(dp), intent(in) :: pressure_angle_deg   !< alpha_n [deg]
  real(dp), intent(in) :: dedendum1            !< h_fP1/m_n [-]
  real(dp), intent(in) :: dedendum2            !< h_fP2/m_n [-]
  real(dp), intent(in) :: web_width_ratio      !< b_s/b, 1 solid [-]
  real(dp), intent(in) :: rim_thickness_ratio  !< s_R/m_n [-]
  real(dp), intent(in) :: line_load            !< K_A F_t/b [N/mm]
  real(dp), intent(in) :: contact_ratio        !< eps_alpha [-]
  real(dp), intent(in) :: face_width           !< b [m]
  real(dp), intent(out) :: zn1                 !< virtual teeth, gear 1 [-]
  real(dp), intent(out) :: zn2                 !< virtual teeth, gear 2 (0 internal) [-]
  real(dp), intent(out) :: flexibility         !< q' [mm um/N]
  real(dp), intent(out) :: theoretical         !< c'_th [N/(mm um)]
  real(dp), intent(out) :: blank_factor        !< C_R [-]
  real(dp), intent(out) :: rack_factor         !< C_B [-]
  real(dp), intent(out) :: load_factor         !< low-load factor [-]
  real(dp), intent(out) :: single              !< c' [N/(mm um)]
  real(dp), intent(out) :: mesh_alpha          !< c_gamma_alpha [N/(mm um)]
  real(dp), intent(out) :: mesh_beta           !< c_gamma_beta [N/(mm um)]
  real(dp), intent(out) :: total_single        !< c' b [N/m]
  real(dp), intent(out) :: total_alpha         !< c_gamma_alpha b [N/m]
  real(dp), intent(out) :: total_beta          !< c_gamma_beta b [N/m]
  integer(ik), intent(out) :: ierr             !< error code (0 = ok)
  type(iso_stiffness) :: factors

  call iso_mesh_stiffness(iso_gear_pair(teeth1, teeth2, internal, shift1, shift2, helix_deg, &
                                        base_helix_deg, pressure_angle_deg, dedendum1, dedendum2, &
                                        web_width_ratio, rim_thickness_ratio, line_load, &
                                        contact_ratio, face_width), factors, ierr)
  zn1 = factors%zn1
  zn2 = factors%zn2
  flexibility = factors%flexibility
  theoretical = factors%theoretical
  blank_factor = factors%blank_factor
  rack_factor = factors%rack_factor
  load_factor = factors%load_factor
  single = factors%single
  mesh_alpha = factors%mesh_alpha
  mesh_beta = factors%mesh_beta
  total_single = factors%total_single
  total_alpha = factors%total_alpha
  total_beta = factors%total_beta
end subroutine iso6336_mesh_stiffness
