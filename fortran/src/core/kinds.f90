!> Numeric kinds used everywhere in the engine.
module paradyn_kinds
  use, intrinsic :: iso_fortran_env, only: real64, int32, int64
  implicit none
  private
  public :: wp, ip, i8

  integer, parameter :: wp = real64  !< working precision for all reals
  integer, parameter :: ip = int32   !< default integer for indices
  integer, parameter :: i8 = int64   !< counters that may exceed 2**31
end module paradyn_kinds
