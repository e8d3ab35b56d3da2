!> Named wall-clock timers of the phases of a step, and the clock they read.
module phase_timers
  use omp_lib, only: omp_get_wtime
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: phase_timers_t, wall_clock

  !> Wall seconds spent in each phase on this rank since the run started.
  type :: phase_timers_t
    real(wp) :: elements = 0       !< element forces and their nodal sum
    real(wp) :: contact = 0        !< contact search and forces, without its communication
    real(wp) :: communication = 0  !< corner exchange and contact sharing (mostly waiting for others)
    real(wp) :: output = 0         !< frames and history records
    real(wp) :: nodes = 0          !< the central-difference update of the nodes
  end type phase_timers_t

contains

  !> Seconds since an arbitrary start; differences are wall-clock intervals.
  function wall_clock() result(seconds)
    real(wp) :: seconds
    seconds = omp_get_wtime()
  end function wall_clock

end module phase_timers
