!> The effects of a step as a pipeline (issue 13): at set-up the solver keeps the members of the
!> nodal effect family that the deck declares and the scene did not switch off, and the step
!> calls them at their stage; this module runs those stages and keeps the effect table's
!> counters. An effect that is not declared is not built, not called and not timed; one that is
!> idle (nothing to do at this time) is not called and counts a skipped cycle.
module effect_pipeline
  use paradyn_kinds, only: wp
  use paradyn_schema, only: effect_time_integration, effect_mass_damping, effect_fixed_boundaries, &
                            effect_elastic_shells, effect_plastic_shells, effect_hourglass
  use phase_timers, only: wall_clock
  use effect_table, only: effect_count, effect_time
  use nodal_effect, only: stage_loads, stage_constraints, stage_corners
  use point_loads, only: point_load_work
  use solver_state, only: solver_t
  use step_clock, only: clock_finished
  implicit none
  private
  public :: pipeline_setup, apply_loads, apply_constraints, apply_corner_loads, count_every_cycle_effects

  integer, parameter :: every_cycle(*) = [effect_time_integration, effect_mass_damping, effect_fixed_boundaries, &
                                          effect_elastic_shells, effect_plastic_shells, effect_hourglass]

contains

  !> Which stages have members (the step skips a stage without any).
  subroutine pipeline_setup(s)
    type(solver_t), intent(inout) :: s
    integer :: k
    s%has_loads = .false.
    s%has_constraints = .false.
    s%has_corner_loads = .false.
    do k = 1, size(s%nodal_effects)
      associate (e => s%nodal_effects(k)%effect)
        s%has_loads = s%has_loads .or. e%acts_at(stage_loads)
        s%has_constraints = s%has_constraints .or. e%acts_at(stage_constraints)
        s%has_corner_loads = s%has_corner_loads .or. e%acts_at(stage_corners)
      end associate
    end do
  end subroutine pipeline_setup

  !> The external forces at the current time from the members that are not idle, and their work
  !> since the last step (trapezoidal rule over f_ext). Once every member is idle and the forces
  !> have gone to zero, the stage costs nothing.
  subroutine apply_loads(s)
    type(solver_t), intent(inout) :: s
    logical :: active(size(s%nodal_effects))
    integer :: k
    real(wp) :: t0
    active = .false.
    do k = 1, size(s%nodal_effects)
      associate (e => s%nodal_effects(k)%effect)
        if (.not. e%acts_at(stage_loads)) cycle
        active(k) = .not. e%idle(s%clock%time)
        if (counting(s)) call effect_count(s%effects, e%id, active(k))
      end associate
    end do
    if (.not. any(active) .and. s%external_forces_zero) return
    t0 = wall_clock()
    associate (ns => s%nodes)
      ns%f_ext_old = ns%f_ext
      ns%f_ext = 0.0_wp
      call effect_time(s%effects, effect_time_integration, wall_clock() - t0)
      do k = 1, size(s%nodal_effects)
        if (.not. active(k)) cycle
        t0 = wall_clock()
        call s%nodal_effects(k)%effect%add_forces(ns, s%clock%time)
        call effect_time(s%effects, s%nodal_effects(k)%effect%id, wall_clock() - t0)
      end do
      t0 = wall_clock()
      if (s%clock%cycles > 0) call point_load_work(ns%n, s%clock%dt_previous, ns%weight, ns%v, ns%w, ns%f_ext_old, &
                                                   ns%f_ext, s%external_work)
      call effect_time(s%effects, effect_time_integration, wall_clock() - t0)
    end associate
    s%external_forces_zero = .not. any(active)
  end subroutine apply_loads

  !> The constraints on the half-step velocities of the step that starts now.
  subroutine apply_constraints(s)
    type(solver_t), intent(inout) :: s
    if (allocated(s%nodes%eps_p)) call node_plastic_strain(s)
    call run_members(s, stage_constraints, counting(s))
  end subroutine apply_constraints

  !> Each held node's largest effective plastic strain of this rank's shell integration points
  !> around it, for the members that asked for it (ns%eps_p: welds that fail by plastic strain).
  subroutine node_plastic_strain(s)
    type(solver_t), intent(inout) :: s
    integer :: g, i, e, m
    real(wp) :: most
    s%nodes%eps_p = 0.0_wp
    do g = 1, s%dom%n_groups
      if (s%props(s%dom%group_part(g))%rigid) cycle
      do i = 1, s%dom%group_count(g)
        e = s%dom%group_first(g) + i - 1
        most = real(maxval(s%elements%groups(g)%eps_p(i, :)), wp)
        do m = 1, 4
          s%nodes%eps_p(s%dom%connectivity(m, e)) = max(s%nodes%eps_p(s%dom%connectivity(m, e)), most)
        end do
      end do
    end do
  end subroutine node_plastic_strain

  !> The loads on element corners at the current positions, before the corners are exchanged (the
  !> forces at the start are not a cycle of the count).
  subroutine apply_corner_loads(s)
    type(solver_t), intent(inout) :: s
    call run_members(s, stage_corners, s%started)
  end subroutine apply_corner_loads

  !> The members acting at stage (constraints or corners) that are not idle, each timed, its work
  !> taken into the external work; with count, the cycle counted as active or skipped.
  subroutine run_members(s, stage, count)
    type(solver_t), intent(inout) :: s
    integer, intent(in) :: stage
    logical, intent(in) :: count
    integer :: k
    logical :: idle
    real(wp) :: t0
    do k = 1, size(s%nodal_effects)
      associate (e => s%nodal_effects(k)%effect)
        if (.not. e%acts_at(stage)) cycle
        idle = e%idle(s%clock%time)
        if (count) call effect_count(s%effects, e%id, .not. idle)
        if (idle) cycle
        t0 = wall_clock()
        if (stage == stage_constraints) then
          call e%constrain(s%nodes, s%clock%time, s%clock%dt, s%clock%dt_previous)
        else
          call e%add_corner_forces(s%dom%connectivity, s%nodes%x, s%clock%time, s%corner)
        end if
        call effect_time(s%effects, e%id, wall_clock() - t0)
        call take_work(s, e%work)
      end associate
    end do
  end subroutine run_members

  !> Whether this call is a cycle of the count: the loop's last pass (at the end time, for the
  !> final half-step velocities) and the forces at the start are not.
  pure logical function counting(s)
    type(solver_t), intent(in) :: s
    counting = .not. clock_finished(s%clock)
  end function counting

  !> A member's work goes into the external work (which the checkpoint keeps).
  subroutine take_work(s, work)
    type(solver_t), intent(inout) :: s
    real(wp), intent(inout) :: work
    s%external_work = s%external_work + work
    work = 0.0_wp
  end subroutine take_work

  !> The effects that work every cycle they run (the update, damping, fixed dofs, the shells).
  pure subroutine count_every_cycle_effects(s)
    type(solver_t), intent(inout) :: s
    integer :: k
    do k = 1, size(every_cycle)
      if (s%effects%running(every_cycle(k))) call effect_count(s%effects, every_cycle(k), .true.)
    end do
  end subroutine count_every_cycle_effects

end module effect_pipeline
