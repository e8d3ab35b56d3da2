!> The step of each cycle from the current mesh (docs/theory.md, "A time step that follows the
!> mesh"): the element kernel leaves each element's L / c of the end-of-step geometry; here the
!> smallest over the elements of all ranks (MPI_MINLOC, so among equal steps the smallest global
!> element id controls, whatever the layout), times the mass-scaling factor of the element, sets
!> the clock's next step. Also the floor: a step below /control time_step_floor times the first
!> step stops the run with a message that names the element.
module time_step_control
  use mpi_f08
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: status_ok, status_numerical
  use shell_measures, only: part_wave_speed
  use step_clock, only: clock_choose_step, clock_finished
  use status_agreement, only: agree_on_status
  use solver_state, only: solver_t
  use contact_parallel, only: contact_travel_step
  use traffic_counter, only: count_allreduce
  implicit none
  private
  public :: next_time_step, check_time_step_floor

  !> the most the step grows in a cycle after the automatic contact limit set it
  real(wp), parameter :: closing_growth = 1.05_wp

contains

  !> After the forces at the current positions: the step from here on. The contact penalty's
  !> stability cap takes the new step too (contact_stages: k <= 0.25 m / dt^2, so the contact
  !> springs never set the step).
  subroutine next_time_step(s)
    type(solver_t), intent(inout) :: s
    real(wp) :: mine(2), least(2), d
    integer :: e
    mine = [huge(1.0_wp), -1.0_wp]
    do e = 1, s%dom%n_elements   ! ascending global ids: the first of equal steps is the smallest id
      d = s%elements%dt_element(e) * s%elements%step_scale(e)
      if (d < mine(1)) mine = [d, real(s%dom%elements(e) - 1, wp)]
    end do
    ! the contact's travel limit, divided by the safety factor the clock applies; id -2 = contact
    if (s%has_contact .and. s%control%contact_travel_limit > 0.0_wp) then
      d = contact_travel_step(s%contact, s%nodes%v, s%control%contact_travel_limit) / s%clock%safety
      if (d < mine(1)) mine = [d, -2.0_wp]
    end if
    ! the automatic limit of the pairs near each other (this cycle's local search); id -3
    if (s%has_contact .and. s%control%contact_closing_limit > 0.0_wp) then
      d = s%contact%c%near_step / s%clock%safety
      ! after a step it set, the step grows back by at most closing_growth a cycle: a step that
      ! jumps while springs act spoils the energy balance of the central difference
      if (s%clock%controlling == -3) d = min(d, closing_growth * s%clock%dt / s%clock%safety)
      if (d < mine(1)) mine = [d, -3.0_wp]
      s%contact%c%near_step = huge(1.0_wp)   ! used: a cycle whose contact does not run (idle) sets none
    end if
    if (mine(1) == huge(1.0_wp)) mine = [s%dt_rigid_only, -1.0_wp]   ! no deformable element: the rigid ones' step
    call MPI_Allreduce(mine, least, 1, MPI_2DOUBLE_PRECISION, MPI_MINLOC, s%halo%comm)
    call count_allreduce(s%halo%traffic, 16_i8, s%n_ranks)
    call clock_choose_step(s%clock, least(1), int(least(2), i8), s%control%dt_cap)
    if (s%clock%cycles == 0) s%clock%dt_first = s%clock%dt
    if (.not. clock_finished(s%clock)) then   ! the range of the mesh's stable step over the run
      s%dt_min = min(s%dt_min, s%clock%dt_stable)
      s%dt_max = max(s%dt_max, s%clock%dt_stable)
    end if
    if (s%has_contact) then
      s%contact%c%time_step = s%clock%dt
      s%contact%c%soft_step = max(s%contact%c%soft_step, s%clock%dt)
    end if
  end subroutine next_time_step

  !> status 3 with a message when the step fell below the floor: the rank that holds the
  !> controlling element names it, its part, its size L = area / longest side and the step.
  subroutine check_time_step_floor(s, status, message)
    type(solver_t), intent(inout) :: s
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer :: g, e, p
    real(wp) :: floor_dt
    status = status_ok
    message = ''
    floor_dt = s%control%time_step_floor * s%clock%dt_first
    if (s%clock%dt >= floor_dt .or. clock_finished(s%clock)) return
    s%floor_stop = .true.
    do g = 1, s%dom%n_groups
      do e = s%dom%group_first(g), s%dom%group_first(g) + s%dom%group_count(g) - 1
        if (s%dom%elements(e) - 1 /= s%clock%controlling) cycle
        p = s%dom%group_part(g)
        status = status_numerical
        write (message, '(a,es10.3,a,es10.3,a,es10.3,a,i0,a,es12.5,a,i0,a,i0,a,es10.3,a)') 'the time step ', &
          s%clock%dt, ' s fell below /control time_step_floor = ', s%control%time_step_floor, &
          ' x the first step ', s%clock%dt_first, ' s at cycle ', s%clock%cycles, ', time ', s%clock%time, &
          ' s: element ', s%clock%controlling, ' of part ', p - 1, ' has shrunk to L = area / longest side = ', &
          s%elements%dt_element(e) * part_wave_speed(s%props(p)), ' m; it is being crushed or inverted: '// &
          'check the mesh, the loads or contact near it, or add mass there ([run] mass_scaling_step)'
      end do
    end do
    if (s%clock%controlling == -1 .and. s%rank == 0) then
      status = status_numerical
      write (message, '(a,es10.3,a)') 'the time step ', s%clock%dt, ' s fell below /control time_step_floor '// &
        'x the first step, limited by a rigid wall''s penalty'
    else if (s%clock%controlling == -2 .and. s%rank == 0) then
      status = status_numerical
      write (message, '(a,es10.3,a)') 'the time step ', s%clock%dt, ' s fell below /control time_step_floor '// &
        'x the first step, limited by /control contact_travel_limit: a contact node moves too fast for its wall; '// &
        'check the velocities, or lower or switch off the limit'
    else if (s%clock%controlling == -3 .and. s%rank == 0) then
      status = status_numerical
      write (message, '(a,es10.3,a)') 'the time step ', s%clock%dt, ' s fell below /control time_step_floor '// &
        'x the first step, limited by /control contact_closing_limit: two contact surfaces close fast for their '// &
        'thinner wall; check the velocities, or lower the limit ([run] contact_closing_limit = 0 switches it off)'
    end if
    call agree_on_status(s%halo%comm, status, message)   ! every rank stops with the owner's message
    if (status == status_ok) then
      status = status_numerical
      write (message, '(a,es10.3,a)') 'the time step ', s%clock%dt, ' s fell below /control time_step_floor '// &
        'x the first step'
    end if
  end subroutine check_time_step_floor

end module time_step_control
