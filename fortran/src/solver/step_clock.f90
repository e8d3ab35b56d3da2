!> Where the time loop stands: the step, the time, the cycle, and which output is due next.
!>
!> The step follows the mesh (docs/theory.md, "A time step that follows the mesh"): after the
!> forces at t(n), clock_choose_step takes the smallest element step L / c of the current geometry
!> times the safety factor as dt(n+1/2). A requested step below it is used as a fixed step: all
!> steps equal, end_time / n for a whole n, as before the step varied (so such runs keep their
!> answers bit for bit); once the mesh's stable step falls below it, the step follows the mesh.
!> The varying step ends exactly at end_time: the step is the time left over the whole number of
!> stable steps that fit in it (rounded up), recomputed only when that number changes, so a
!> constant or slowly changing stable step gives equal steps, as the fixed step, and a change is
!> spread over the steps left instead of one sliver at the end (every change of the step moves the
!> energy that central differences conserve). Counters are 64-bit.
module step_clock
  use paradyn_kinds, only: wp, i8
  implicit none
  private
  public :: step_clock_t, clock_setup, clock_advance, clock_choose_step, clock_finished, output_due, &
            next_output_index, half_step

  type :: step_clock_t
    real(wp) :: dt = 0            !< the step from time on, dt(n+1/2)
    real(wp) :: dt_previous = 0   !< the step that ended at time, dt(n-1/2); 0 before the first
    real(wp) :: dt_stable = 0     !< the mesh's stable step now, safety factor included
    real(wp) :: dt_first = 0      !< the first step of the run (the floor is a fraction of it)
    real(wp) :: safety = 1        !< /control time_step_safety
    integer(i8) :: controlling = -1   !< 0-based global id of the element with the smallest step
    logical :: fixed = .false.    !< the requested step is in use (all steps equal)
    real(wp) :: time = 0, end_time = 0
    integer(i8) :: cycles = 0
    integer(i8) :: n_steps = 0    !< steps of the fixed step; for the varying step, end_time / first step
    integer(i8) :: steps_left = 0 !< varying step: the steps to end_time at dt, this one included (0: to be set)
    integer(i8) :: first_cycle = 0  !< the cycle this process started from (a restart starts later)
    integer(i8) :: frame_index = 0, record_index = 0   !< the next frame and history record due
  end type step_clock_t

  !> a count of steps at or beyond this is not computed (the caller refuses such a run)
  real(wp), parameter :: count_limit = 0.25_wp * real(huge(1_i8), wp)

contains

  !> The first step: the stable step (smallest element step times safety), or the requested one
  !> where it is smaller, then fixed; a fixed step is reduced, if need be, to end_time / n for a
  !> whole n. too_large says that the requested step was above the stable one (and was not used).
  subroutine clock_setup(clock, dt_element_min, safety, requested, end_time, too_large)
    type(step_clock_t), intent(out) :: clock
    real(wp), intent(in) :: dt_element_min, safety, requested, end_time
    logical, intent(out) :: too_large
    clock%safety = safety
    clock%dt_stable = safety * dt_element_min
    clock%dt = clock%dt_stable
    too_large = .false.
    if (requested > 0.0_wp) then
      if (requested <= clock%dt_stable) then
        clock%dt = requested
        clock%fixed = .true.
      else
        too_large = .true.
      end if
    end if
    clock%end_time = end_time
    if (end_time / clock%dt > count_limit) then   ! the caller refuses the run (no integer overflow here)
      clock%n_steps = huge(1_i8)
      clock%dt_first = clock%dt
      return
    end if
    if (clock%fixed) then   ! whole steps of equal size that end exactly at end_time (never above the request)
      clock%dt = end_time / real(max(1_i8, ceiling(end_time / clock%dt - 1.0e-9_wp, i8)), wp)
      clock%n_steps = max(1_i8, nint(end_time / clock%dt, i8))
    else
      clock%n_steps = max(1_i8, ceiling(end_time / clock%dt - 1.0e-9_wp, i8))
    end if
    clock%dt_first = clock%dt
  end subroutine clock_setup

  !> The step dt(n+1/2) from the mesh's smallest element step now (dt_element_min, no safety
  !> factor; element its 0-based global id) and cap, the most any other part of the model allows
  !> (rigid walls; huge without). A fixed step stays while the stable step allows it; at the end
  !> time (the loop's last pass, for the final velocities) the step stays the last one.
  subroutine clock_choose_step(clock, dt_element_min, element, cap)
    type(step_clock_t), intent(inout) :: clock
    real(wp), intent(in) :: dt_element_min, cap
    integer(i8), intent(in) :: element
    real(wp) :: remaining, steps
    integer(i8) :: needed
    clock%dt_stable = clock%safety * dt_element_min
    clock%controlling = element
    if (cap < clock%dt_stable) then   ! a rigid wall's penalty spring, not an element, sets it
      clock%dt_stable = cap
      clock%controlling = -1
    end if
    if (clock%fixed .and. clock%dt <= clock%dt_stable) return
    clock%fixed = .false.
    remaining = clock%end_time - clock%time
    ! at the end the loop's last pass only completes the velocities: the step stays the last one
    ! taken, so the whole-step velocity and kinetic energy at end_time are those of a constant step
    if (remaining <= 0.0_wp) return
    if (clock%dt <= 0.0_wp) clock%dt = clock%dt_stable
    steps = remaining / clock%dt_stable
    if (steps >= count_limit) then
      clock%dt = clock%dt_stable
      clock%steps_left = 0
      return
    end if
    ! the steps left at the stable step, and at the present step: the step changes only when the
    ! count does (the stable step fell below it, or grew by more than one step in the time left)
    needed = max(1_i8, ceiling(steps - 1.0e-9_wp, i8))
    if (needed /= clock%steps_left) then
      clock%dt = remaining / real(needed, wp)
      clock%steps_left = needed
    end if
  end subroutine clock_choose_step

  !> The step between the two half-step velocities: (dt(n-1/2) + dt(n+1/2)) / 2, half a step at
  !> the start (Belytschko, Liu & Moran, Nonlinear Finite Elements, sec. 6.2.1).
  pure real(wp) function half_step(clock) result(h)
    type(step_clock_t), intent(in) :: clock
    h = 0.5_wp * (clock%dt_previous + clock%dt)
  end function half_step

  !> One step on; the last step lands exactly on end_time.
  subroutine clock_advance(clock)
    type(step_clock_t), intent(inout) :: clock
    logical :: last
    if (clock%fixed) then
      last = clock%cycles + 1 == clock%n_steps
    else   ! the last of the steps left lands on end_time (clock_choose_step)
      last = clock%steps_left == 1
      clock%steps_left = max(0_i8, clock%steps_left - 1)
    end if
    clock%time = merge(clock%end_time, clock%time + clock%dt, last)
    clock%cycles = clock%cycles + 1
    clock%dt_previous = clock%dt
  end subroutine clock_advance

  !> The run has reached its end time.
  pure logical function clock_finished(clock)
    type(step_clock_t), intent(in) :: clock
    clock_finished = clock%time >= clock%end_time
  end function clock_finished

  !> Output number k is due at the first step at or after k * interval, and at the end time.
  pure logical function output_due(clock, k, interval)
    type(step_clock_t), intent(in) :: clock
    integer(i8), intent(in) :: k
    real(wp), intent(in) :: interval
    output_due = clock%time >= real(k, wp) * interval - 1.0e-6_wp * clock%dt .or. clock_finished(clock)
  end function output_due

  !> Index of the first output time after the current step.
  pure integer(i8) function next_output_index(clock, interval)
    type(step_clock_t), intent(in) :: clock
    real(wp), intent(in) :: interval
    next_output_index = floor((clock%time + 1.0e-6_wp * clock%dt) / interval, i8) + 1
  end function next_output_index

end module step_clock
