!> Where the time loop stands: the step, the time, the cycle, and which output is due next.
!> Every step has the same size dt, chosen at set-up so that whole steps end exactly at end_time.
module step_clock
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: step_clock_t, clock_setup, clock_advance, output_due, next_output_index, half_step

  type :: step_clock_t
    real(wp) :: dt = 0          !< the step used
    real(wp) :: dt_stable = 0   !< the mesh's stable step, safety factor included
    real(wp) :: time = 0, end_time = 0
    integer :: cycles = 0, n_steps = 0
    integer :: first_cycle = 0  !< the cycle this process started from (a restart starts later)
    integer :: frame_index = 0, record_index = 0   !< the next frame and history record due
  end type step_clock_t

contains

  !> The step: the stable step (smallest element step times safety), or the requested one where
  !> it is smaller; then reduced, if need be, to end_time / n for a whole n. too_large says that
  !> the requested step was above the stable one (and was not used).
  subroutine clock_setup(clock, dt_element_min, safety, requested, end_time, too_large)
    type(step_clock_t), intent(out) :: clock
    real(wp), intent(in) :: dt_element_min, safety, requested, end_time
    logical, intent(out) :: too_large
    clock%dt_stable = safety * dt_element_min
    clock%dt = clock%dt_stable
    too_large = .false.
    if (requested > 0.0_wp) then
      if (requested <= clock%dt_stable) then
        clock%dt = requested
      else
        too_large = .true.
      end if
    end if
    clock%end_time = end_time
    if (end_time / clock%dt > 0.5_wp * huge(1)) then   ! the caller refuses the run (no integer overflow here)
      clock%n_steps = huge(1)
      return
    end if
    ! whole steps of equal size that end exactly at end_time (never above the chosen step)
    clock%dt = end_time / max(1, ceiling(end_time / clock%dt - 1.0e-9_wp))
    clock%n_steps = max(1, nint(end_time / clock%dt))
  end subroutine clock_setup

  !> The step between the two half-step velocities: half a step at the start.
  pure real(wp) function half_step(clock) result(h)
    type(step_clock_t), intent(in) :: clock
    h = merge(0.5_wp * clock%dt, clock%dt, clock%cycles == 0)
  end function half_step

  !> One step on; the last step lands exactly on end_time.
  subroutine clock_advance(clock)
    type(step_clock_t), intent(inout) :: clock
    clock%time = merge(clock%end_time, clock%time + clock%dt, clock%cycles + 1 == clock%n_steps)
    clock%cycles = clock%cycles + 1
  end subroutine clock_advance

  !> Output number k is due at the first step at or after k * interval, and at the last step.
  pure logical function output_due(clock, k, interval)
    type(step_clock_t), intent(in) :: clock
    integer, intent(in) :: k
    real(wp), intent(in) :: interval
    output_due = clock%time >= k * interval - 1.0e-6_wp * clock%dt .or. clock%cycles == clock%n_steps
  end function output_due

  !> Index of the first output time after the current step.
  pure integer function next_output_index(clock, interval)
    type(step_clock_t), intent(in) :: clock
    real(wp), intent(in) :: interval
    next_output_index = floor((clock%time + 1.0e-6_wp * clock%dt) / interval) + 1
  end function next_output_index

end module step_clock
