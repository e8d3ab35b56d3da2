!> The explicit solver: set-up from the deck, and the time loop.
!>
!> Lifecycle: solver_setup (decompose, allocate everything, masses, time step, run control, the
!> effect pipeline; the deck can be released after it) -> solver_run (the time loop; nothing is
!> allocated inside it). Each step: loads -> half-step velocities -> constraints -> output when
!> due -> positions -> forces at the new positions (internal_forces: element groups on the
!> threads, corner loads, corner exchange, fixed-order nodal sum, contact). Effects that the deck
!> does not declare, or the scene switched off, are not built and not called (effect_pipeline).
module explicit_solver
  use mpi_f08
  use omp_lib, only: omp_get_max_threads
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: status_ok, status_bad_input, status_failure
  use paradyn_schema, only: material_is_plastic, effect_plastic_shells, effect_elastic_shells
  use model_deck, only: deck_t, part_properties, node_row
  use effect_table, only: effect_table_t
  use effect_factory, only: make_nodal_effects
  use effect_pipeline, only: pipeline_setup, apply_loads, apply_constraints, count_every_cycle_effects
  use distributed_decomposition, only: decompose_distributed
  use halo_exchange, only: halo_setup
  use traffic_counter, only: traffic_t, count_allreduce
  use nodal_state, only: nodal_state_setup, advance_velocities, advance_positions, keep_velocities
  use element_state, only: element_state_setup
  use step_clock, only: step_clock_t, clock_setup, clock_advance, clock_finished, output_due, next_output_index, &
                        half_step
  use time_step_control, only: next_time_step, check_time_step_floor
  use mass_scaling, only: mass_scaling_t, mass_scaling_setup, mass_scaling_message
  use ordered_sums, only: mass_scaling_totals
  use run_control, only: run_control_setup
  use phase_timers, only: wall_clock
  use contact_parallel, only: parallel_contact_setup, contact_log_line
  use eroded_contact, only: eroded_contact_setup
  use contact_births, only: contact_births_setup, contact_births_check
  use internal_forces, only: forces_at_current_state, lumped_masses, workspace_per_group
  use solver_output, only: write_record, write_frame, write_progress, run_record, write_phase_line
  use solver_state, only: solver_t
  use stop_signals, only: stop_signal_received
  use status_agreement, only: agree_on_status
  use contact_checks, only: check_contact_overlap
  use results_writer, only: results_file_t, run_record_t, results_failed, node_field_width, element_field_width
  implicit none
  private
  public :: solver_t, solver_setup, solver_run, record_at_stop

  integer, parameter :: signal_poll_cycles = 16   !< a collective check every few cycles costs nothing
  !> the most steps a run may take: beyond, it cannot finish on any machine (1e9 steps of the
  !> smallest mesh at 1e8 element-cycles/s are hours; the cycle counters are 64-bit, so the limit
  !> is about time, not overflow)
  real(wp), parameter :: max_steps = 1.0e9_wp

contains

  !> Everything the time loop needs, from the deck and its effect table (deck_effects, with the
  !> switched-off effects already taken out of the deck), on this rank of comm. The deck holds
  !> this rank's elements (model_deck's layout: they become the domain's) and the rows of their
  !> nodes (the crossing check and local contact's set-up run on them); contact: the deck in the
  !> global layout the contact state's set-up reads on one rank and in the replicated scheme
  !> (contact_global_rows; any deck otherwise), released once that state is built. status 2 with a
  !> message for a mesh that cannot run (a node without mass).
  subroutine solver_setup(s, deck, contact, effects, comm, status, message)
    type(solver_t), intent(inout) :: s
    type(deck_t), intent(in) :: deck
    type(deck_t), intent(inout) :: contact
    type(effect_table_t), intent(in) :: effects
    type(MPI_Comm), intent(in) :: comm
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer :: p, k
    type(mass_scaling_t) :: scaling
    logical :: too_large
    real(wp), allocatable :: carried(:)

    status = status_ok
    message = ''
    call MPI_Comm_rank(comm, s%rank)
    call MPI_Comm_size(comm, s%n_ranks)
    s%threads = max(omp_get_max_threads(), 1)
    call decompose_distributed(comm, deck%n_nodes, deck%element_ids, deck%connectivity, deck%element_part, s%dom)
    call halo_setup(s%dom, comm, s%halo)
    s%props = [(part_properties(deck, p), p = 1, deck%n_parts)]
    call nodal_state_setup(s%nodes, deck, s%dom)
    call element_state_setup(s%elements, s%dom, s%props)
    call run_control_setup(s%control, deck, s%dom)
    s%effects = effects
    s%part_effect = merge(effect_plastic_shells, effect_elastic_shells, &
                          material_is_plastic(deck%material_model(deck%part_material)))
    allocate (s%corner(6, 4 * s%dom%n_elements + s%dom%n_ghost_slots), source=0.0_wp)
    allocate (s%workspace(workspace_per_group, s%threads), source=0.0_wp)

    call mass_scaling_setup(scaling, deck, s%props)   ! the held elements (= the domain's, in order)
    call mass_scaling_totals(comm, deck%n_elements, deck%element_ids, deck%element_part, scaling)
    s%elements%step_scale = scaling%step_scale
    s%added_mass_part = scaling%added_part
    s%added_mass = scaling%added
    s%model_mass = scaling%model_mass
    s%mass_scaling_step = scaling%target
    s%scaled_elements = scaling%scaled
    call lumped_masses(s)
    s%nodes%mass = s%nodes%mass + deck%added_mass([(node_row(deck, s%dom%nodes(p)), p = 1, s%dom%n_nodes)])
    if (any(.not. (s%nodes%mass > 0.0_wp))) then
      status = status_bad_input
      message = 'a node has no mass (zero-area element?); check /elements/connectivity and the coordinates'
    end if
    if (status == status_ok .and. mass_scaling_message(scaling) /= '') then
      status = status_bad_input
      message = mass_scaling_message(scaling)
    end if
    if (scaling%dt_element_min == huge(1.0_wp)) s%dt_rigid_only = scaling%dt_rigid_min   ! rigid bodies alone
    call clock_setup(s%clock, min(scaling%dt_element_min, s%dt_rigid_only), deck%time_step_safety, deck%time_step, &
                     deck%end_time, too_large)
    ! a wall's spring k = scale m / dt0^2 (made with this first step) is stable below 2 dt0 / sqrt(scale):
    ! the step stays at half that, so a wall never sets it unless the mesh grows the step 1.4 times or more
    if (deck%n_rigid_walls > 0) s%control%dt_cap = s%clock%dt / sqrt(maxval(deck%rigid_wall_penalty_scale))
    if (status == status_ok) call check_step(s%clock, deck, status, message)
    call check_contact_overlap(deck, comm, status, message)   ! collective: every rank calls it
    call agree_on_status(comm, status, message)   ! one rank's verdict stops all of them
    if (status /= status_ok) return
    if (too_large .and. s%rank == 0) then
      write (0, '(a,es11.4,a,es11.4,a)') 'paradyn-engine: warning: the requested time step ', &
        deck%time_step, ' s is above the stable step ', s%clock%dt_stable, ' s; using the stable step'
    end if
    call make_nodal_effects(deck, s%dom, effects, s%clock%dt, s%nodes, comm, s%nodal_effects)   ! after the step: walls need it
    call pipeline_setup(s)

    s%has_contact = deck%n_contacts > 0
    if (s%has_contact) then   ! the contact's stability cap takes the mass moving with each node
      carried = s%nodes%mass
      do k = 1, size(s%nodal_effects)
        call s%nodal_effects(k)%effect%carried_mass(carried)
      end do
      call parallel_contact_setup(s%contact, contact, deck, s%dom, comm, carried, s%nodes%v, s%clock%dt, &
                                  s%control%contact_gather_all)
      s%contact%c%closing_limit = s%control%contact_closing_limit
    end if
    call eroded_contact_setup(s)
    if (s%has_contact) call contact_births_setup(s, deck)
    allocate (s%node_out(node_field_width, size(s%halo%owned_local)), s%v_free(3, s%nodes%n), s%w_free(3, s%nodes%n))
    allocate (s%element_out(element_field_width, s%dom%n_elements), s%tracked_out(6, deck%n_tracked))
    allocate (s%element_work(s%dom%n_elements))
    s%n_parts = deck%n_parts
    s%n_contacts = deck%n_contacts
    s%n_walls = deck%n_rigid_walls
    s%node_part = deck%node_part([(node_row(deck, s%dom%nodes(p)), p = 1, s%dom%n_nodes)])
  end subroutine solver_setup

  !> Refuses a run that cannot finish or would go wrong from the first step: more steps than
  !> max_steps (issue 17: the estimate is named), or mass damping so strong that it reverses the
  !> velocities every step (a dt >= 2, where the update's factor 1 - a dt / 2 turns negative).
  subroutine check_step(clock, deck, status, message)
    type(step_clock_t), intent(in) :: clock
    type(deck_t), intent(in) :: deck
    integer, intent(inout) :: status
    character(len=*), intent(inout) :: message
    real(wp) :: steps
    steps = deck%end_time / clock%dt
    if (steps > max_steps) then
      status = status_bad_input
      write (message, '(a,es10.3,a,es10.3,a,es9.2,a)') 'end_time / time step = ', steps, ' steps (dt = ', &
        clock%dt, ' s), more than the limit of ', max_steps, &
        '; shorten /control end_time, or check the mesh for a tiny element that sets the step'
    else if (deck%checkpoint_interval > 0.0_wp .and. deck%checkpoint_interval < clock%dt) then
      status = status_bad_input
      write (message, '(a,es10.3,a,es10.3,a)') '/control checkpoint_interval = ', deck%checkpoint_interval, &
        ' s is below the time step dt = ', clock%dt, ' s: a checkpoint every step or more often; '// &
        'give an interval of many steps (or 0 for none)'
    else if (deck%mass_damping * clock%dt >= 2.0_wp) then
      status = status_bad_input
      write (message, '(a,es10.3,a,es10.3,a)') '/control mass_damping x dt = ', deck%mass_damping * clock%dt, &
        ' (dt = ', clock%dt, ' s) must be below 2, or the damping reverses the velocities every step; '// &
        'use a smaller mass_damping (dynamic relaxation needs about twice the lowest natural frequency)'
    end if
  end subroutine check_step

  !> The time loop, from where the solver stands (the start, a pause, or a restored checkpoint)
  !> to the end time (s%finished), or until a pause: at the first step at or after pause_time, or
  !> when any rank got a stop signal (s%stop_requested). Returns status 0, or 3 with a message on a
  !> numerical failure; run holds the /run attributes of where it stopped.
  subroutine solver_run(s, rf, run, status, message, pause_time)
    type(solver_t), intent(inout) :: s
    type(results_file_t), intent(inout) :: rf
    type(run_record_t), intent(out) :: run
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    real(wp), intent(in) :: pause_time
    real(wp) :: t0
    integer(i8) :: call_cycle

    status = status_ok
    message = ''
    if (.not. s%started) call start_loop(s)
    call_cycle = s%clock%cycles   ! every call takes at least one step, whatever the pause time
    do
      call check_time_step_floor(s, status, message)   ! collective only when the floor is crossed
      if (status /= status_ok) exit
      if (pause_due(s, pause_time, call_cycle)) exit
      if (s%has_loads) call apply_loads(s)
      call output_and_velocities(s, rf, status, message)
      if (status /= status_ok) exit
      if (clock_finished(s%clock)) then
        s%finished = .true.
        exit
      end if
      t0 = wall_clock()
      call advance_positions(s%nodes, s%clock%dt, s%threads)
      s%timers%nodes = s%timers%nodes + wall_clock() - t0
      call clock_advance(s%clock)
      call contact_births_check(s, status, message)   ! a contact born now: the start's checks, now
      if (status /= status_ok) exit
      call forces_at_current_state(s, s%clock%dt_previous)
      call next_time_step(s)   ! dt(n+1/2) from the element steps the forces left
      call count_every_cycle_effects(s)
      call write_progress(s)
    end do
    run = run_record(s)
    if (s%finished) then
      if (s%has_contact) call contact_log_line(s%contact, s%rank)
      call write_phase_line(s)
    end if
  end subroutine solver_run

  !> The wall clock starts; a fresh run computes its first forces and its first step from them, a
  !> restored one comes with both.
  subroutine start_loop(s)
    type(solver_t), intent(inout) :: s
    call MPI_Barrier(s%halo%comm)
    s%wall_start = wall_clock()
    s%last_progress = s%wall_start
    s%halo%traffic = traffic_t()   ! the counts of /run are per cycle of this call, as wall_s
    if (s%has_contact) s%contact%traffic = traffic_t()
    s%clock%first_cycle = s%clock%cycles
    if (s%clock%cycles == 0) then
      call forces_at_current_state(s, 0.0_wp)
      call next_time_step(s)
      if (s%has_contact) then   ! the forces at the start are not a cycle of the pairs' counts either
        s%contact%c%pair_active_cycles = 0
        s%contact%c%pair_skipped_cycles = 0
      end if
    end if
    s%started = .true.
  end subroutine start_loop

  !> A pause is due at the first step at or after pause_time, or when any rank got a stop signal
  !> (checked collectively every few cycles); never at the first or the last step of a call.
  logical function pause_due(s, pause_time, call_cycle) result(due)
    type(solver_t), intent(inout) :: s
    real(wp), intent(in) :: pause_time
    integer(i8), intent(in) :: call_cycle   !< the cycle this call of solver_run started at
    logical :: mine
    due = .false.
    if (s%clock%cycles <= call_cycle .or. clock_finished(s%clock)) return
    due = s%clock%time >= pause_time - 1.0e-6_wp * s%clock%dt
    if (due .or. modulo(s%clock%cycles, int(signal_poll_cycles, i8)) /= 0) return
    mine = stop_signal_received()
    call MPI_Allreduce(mine, s%stop_requested, 1, MPI_LOGICAL, MPI_LOR, s%halo%comm)
    call count_allreduce(s%halo%traffic, 4_i8, s%n_ranks)
    due = s%stop_requested
  end function pause_due

  !> After a stop at the time step floor (and its checkpoint, which holds the state before this):
  !> the velocities of the step that would have come and one more history record, so that the
  !> history ends with the step that stopped the run and its element. Collective.
  subroutine record_at_stop(s, rf)
    type(solver_t), intent(inout) :: s
    type(results_file_t), intent(inout) :: rf
    integer :: status
    character(len=256) :: message
    if (s%has_loads) call apply_loads(s)
    call keep_velocities(s%nodes)
    call advance_velocities(s%nodes, half_step(s%clock), s%control%mass_damping, s%threads, s%damping_work)
    s%v_free = s%nodes%v
    s%w_free = s%nodes%w
    if (s%has_constraints) call apply_constraints(s)
    call write_record(s, rf, status, message)   ! the run stops anyway: its own verdict is not needed
  end subroutine record_at_stop

  !> The half-step velocities, and the history record and frame when due (they need the
  !> velocities on both sides of the whole step).
  subroutine output_and_velocities(s, rf, status, message)
    type(solver_t), intent(inout) :: s
    type(results_file_t), intent(inout) :: rf
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    logical :: frame_due, record_due
    real(wp) :: t0
    status = status_ok
    message = ''
    frame_due = output_due(s%clock, s%clock%frame_index, s%control%output_interval)
    record_due = output_due(s%clock, s%clock%record_index, s%control%history_interval)
    if (frame_due .or. record_due) call keep_velocities(s%nodes)
    t0 = wall_clock()
    call advance_velocities(s%nodes, half_step(s%clock), s%control%mass_damping, s%threads, s%damping_work)
    s%timers%nodes = s%timers%nodes + wall_clock() - t0
    if (record_due) then   ! what the constraints change is their reaction
      s%v_free = s%nodes%v
      s%w_free = s%nodes%w
    end if
    if (s%has_constraints) call apply_constraints(s)
    if (.not. (frame_due .or. record_due)) return
    t0 = wall_clock()
    if (record_due) then
      call write_record(s, rf, status, message)
      s%clock%record_index = next_output_index(s%clock, s%control%history_interval)
    end if
    if (frame_due .and. status == status_ok) then
      call write_frame(s, rf)
      s%clock%frame_index = next_output_index(s%clock, s%control%output_interval)
      if (results_failed(rf)) status = status_failure   ! the engine says what failed and stops
    end if
    s%timers%output = s%timers%output + wall_clock() - t0
  end subroutine output_and_velocities

end module explicit_solver
