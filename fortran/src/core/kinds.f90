!> Numeric kinds used everywhere in the engine.
!>
!> ek, the element kernel's kind, is the one build-time choice of precision (fortran/CMakeLists.txt,
!> PARADYN_PRECISION; docs/theory.md, "Precision"): double (real64, the default and the reference)
!> or, in the mixed engine (compiled with -DPARADYN_MIXED), single (real32) for the element kernel,
!> the material return and the element state they update. Everything else (positions, velocities,
!> accelerations, the nodal force sums, energies, histories) is wp, double, in both engines.
module paradyn_kinds
  use, intrinsic :: iso_fortran_env, only: real32, real64, int32, int64
  implicit none
  private
  public :: wp, ek, ip, i8

  integer, parameter :: wp = real64  !< working precision for all reals but the element kernel's
#ifdef PARADYN_MIXED
  integer, parameter :: ek = real32  !< element kernel: single in the mixed engine
#else
  integer, parameter :: ek = real64  !< element kernel: double, the same as wp
#endif
  integer, parameter :: ip = int32   !< default integer for indices
  integer, parameter :: i8 = int64   !< counters that may exceed 2**31
end module paradyn_kinds
