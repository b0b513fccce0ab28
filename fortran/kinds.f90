!> Kind parameters shared by every pygear kernel module.
module kinds
  implicit none
  private
  public :: dp, ik

  integer, parameter :: dp = selected_real_kind(15, 307)  !< double precision reals
  integer, parameter :: ik = selected_int_kind(9)         !< default integers (32 bit)
end module kinds
