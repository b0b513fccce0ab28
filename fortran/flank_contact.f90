!> The force law of one mesh whose teeth may separate: drive flank, backlash, coast flank.
!>
!> Mesh m has the deflection delta_m = b_m . q along its line of action and the contact
!> sign s_m (s_m delta_m > 0: the drive flanks pressed together).  With the backlash
!> b_m >= 0 (the gap between the coast flanks along the same line, measured when the
!> drive flanks just touch) the compression c = s_m delta_m gives
!>   c > 0          drive flank:  F = k_drive c            (k_drive from the contact table)
!>   -b_m <= c <= 0 free flight:  F = 0
!>   c < -b_m       coast flank:  F = k_coast (c + b_m)    (negative: the coast flanks push)
!> with F the force along s_m b_m.  Along delta_m the force is f = s_m F = k_eff (delta_m -
!> offset), k_eff the stiffness of the flank in contact (0 in free flight) and offset = 0
!> (drive, free) or -s_m b_m (coast).  An infinite backlash leaves the coast flank out:
!> the teeth may then part without limit (a contact-only spring).  b_m = 0 is a two-sided
!> contact with a stiffness that changes at c = 0 when k_coast /= k_drive.
!>
!> This is the backlash law of Kahraman & Singh (1990, J. Sound Vib. 142(1) 49-75) with
!> a stiffness of its own on each side.  The coast flank's stiffness comes from the same
!> tooth-contact table, evaluated with the mesh cycle shifted by a coast phase offset:
!> for symmetric teeth the coast flanks engage along the mirrored line of action with
!> the same single-pair law, so the coast mesh stiffness is the drive one shifted in
!> phase (Guo & Parker 2014, Mech. Mach. Theory 78, 263-271, derive the shift from the
!> tooth thickness and the backlash).  An offset of 0 (the callers' default) ASSUMES
!> the drive flank's phase.
module flank_contact
  use kinds, only: dp, ik
  implicit none
  private

  public :: flank_force_law, flank_compression
  public :: flank_free, flank_drive, flank_coast

  integer(ik), parameter :: flank_free = 0   !< free flight inside the backlash
  integer(ik), parameter :: flank_drive = 1  !< drive flanks in contact
  integer(ik), parameter :: flank_coast = 2  !< coast flanks in contact

contains

  !> The flank in contact, its stiffness and the deflection offset of its force.
  pure subroutine flank_force_law(contact_sign, delta, backlash, k_drive, k_coast, k_eff, offset, &
                                  flank)
    integer(ik), intent(in) :: contact_sign  !< s_m = +1 or -1 [-]
    real(dp), intent(in) :: delta            !< mesh deflection delta_m [m]
    real(dp), intent(in) :: backlash         !< b_m >= 0 along the line of action, may be +inf [m]
    real(dp), intent(in) :: k_drive          !< drive-flank mesh stiffness [N/m]
    real(dp), intent(in) :: k_coast          !< coast-flank mesh stiffness [N/m]
    real(dp), intent(out) :: k_eff           !< stiffness of the flank in contact, 0 free [N/m]
    real(dp), intent(out) :: offset          !< force along delta is k_eff (delta - offset) [m]
    integer(ik), intent(out) :: flank        !< flank_free, flank_drive or flank_coast [-]
    real(dp) :: compression

    compression = real(contact_sign, dp) * delta
    if (compression > 0.0_dp) then
      k_eff = k_drive
      offset = 0.0_dp
      flank = flank_drive
    else if (compression < -backlash) then
      k_eff = k_coast
      offset = -real(contact_sign, dp) * backlash
      flank = flank_coast
    else
      k_eff = 0.0_dp
      offset = 0.0_dp
      flank = flank_free
    end if
  end subroutine flank_force_law

  !> How far the flank in contact is pressed in: s delta on the drive side, -(s delta) - b
  !> on the coast side, 0 in free flight [m].
  pure real(dp) function flank_compression(contact_sign, delta, backlash)
    integer(ik), intent(in) :: contact_sign  !< s_m = +1 or -1 [-]
    real(dp), intent(in) :: delta            !< mesh deflection delta_m [m]
    real(dp), intent(in) :: backlash         !< b_m >= 0, may be +inf [m]
    real(dp) :: compression

    compression = real(contact_sign, dp) * delta
    flank_compression = max(compression, -compression - backlash, 0.0_dp)
  end function flank_compression
end module flank_contact
