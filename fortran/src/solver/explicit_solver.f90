!> The explicit solver: set-up, the time loop and its phases, and the run record.
!>
!> Lifecycle: solver_setup (decompose, allocate everything, masses, time step) -> solver_run
!> (the time loop; nothing is allocated inside it) -> the run record for the results file.
!> Each step: element forces by groups on OpenMP threads -> corner exchange with neighbour ranks
!> -> fixed-order nodal sum -> central-difference update. Effects that the deck does not declare
!> (point loads, damping, plasticity) are not called.
module explicit_solver
  use mpi_f08
  use omp_lib, only: omp_get_max_threads, omp_get_thread_num
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t, part_properties
  use shell_blt, only: shell_properties_t, blt_internal_forces, blt_lumped_mass, &
                       blt_stable_time_step, blt_element_results, stress_components, back_stress_points, &
                       hourglass_components, material_j2_plastic
  use work_queues, only: work_queues_t, queues_start, queues_take
  use element_groups, only: group_size
  use domain_decomposition, only: domain_t, decompose, partition_elements
  use halo_exchange, only: halo_t, halo_setup, exchange_corners, sum_to_root, node_set_t, node_set_setup, &
                           allgather_node_set, node_subset_setup, allgather_node_subset, &
                           record_share_t, record_share_setup, share_contact_records, &
                           candidate_share_t, candidate_share_setup, share_contact_candidates
  use contact_interface, only: contact_t, contact_setup, contact_begin, &
                               contact_global_search, contact_candidates, contact_local_search, &
                               contact_sum, contact_end, contact_sort_due, contact_movement
  use nodal_assembly, only: gather_group, scatter_corners, assemble_nodes
  use time_integration, only: update_velocities, update_positions, point_load_forces, kinetic_energy
  use stop_signals, only: stop_signal_received
  use results_writer, only: results_file_t, results_write_frame, results_write_history, run_record_t
  implicit none
  private
  public :: solver_t, solver_setup, solver_run, solver_effects

  integer, parameter :: workspace_per_group = group_size * (3 * 4 * 3 + 6 * 4)

  type :: solver_t
    type(domain_t) :: dom
    type(halo_t) :: halo
    type(shell_properties_t), allocatable :: props(:)
    type(contact_t) :: contact
    type(node_set_t) :: contact_nodes
    type(record_share_t) :: contact_share
    type(candidate_share_t) :: candidate_share
    logical :: has_contact = .false.
    integer :: rank = 0, n_ranks = 1, threads = 1
    ! nodal state, local numbering
    real(wp), allocatable :: x0(:, :), x(:, :), v(:, :), w(:, :), v_old(:, :), w_old(:, :)
    real(wp), allocatable :: mass(:), inertia(:), weight(:)
    integer, allocatable :: fixed(:, :)
    real(wp), allocatable :: f_int(:, :), f_ext(:, :), f_ext_old(:, :), corner(:, :)
    ! element state in pools, one contiguous block per group
    real(wp), allocatable :: stress(:), back(:), eps_p(:), hourglass(:)
    integer, allocatable :: stress_at(:), back_at(:), eps_p_at(:), hourglass_at(:)
    real(wp), allocatable :: e_internal(:), e_hourglass(:)
    real(wp), allocatable :: workspace(:, :)
    type(work_queues_t) :: group_queues   !< the threads' shares of the element groups
    ! loads and tracked nodes in local numbering (0 where this rank does not hold the node)
    integer, allocatable :: load_node(:)
    ! output buffers: this rank's owned nodes and its elements
    real(wp), allocatable :: node_out_a(:, :), node_out_b(:, :), element_out(:, :)
    real(wp), allocatable :: tracked_out(:, :)   !< (6, n_tracked): this rank's share, summed to rank 0
    real(wp) :: dt = 0, dt_stable = 0, time = 0, external_work = 0, damping_work = 0
    integer :: cycles = 0, inverted = 0
    ! where the time loop stands between calls of solver_run (a pause for a checkpoint, a restart)
    integer :: n_steps = 0, frame_index = 0, record_index = 0, first_cycle = 0
    logical :: started = .false., finished = .false., stop_requested = .false.
    real(wp) :: phase(5) = 0   !< wall seconds: elements, contact, communication, output, other
    real(wp) :: wall_start = 0, last_progress = 0
  end type solver_t

contains

  !> Effects this deck switches on, in the order the engine runs them.
  function solver_effects(deck) result(list)
    type(deck_t), intent(in) :: deck
    character(len=:), allocatable :: list
    list = 'shell_elements,time_integration'
    if (any(deck%material_model(deck%part_material) == material_j2_plastic)) list = list//',plasticity'
    if (any(deck%fixed /= 0)) list = list//',fixed_boundaries'
    if (deck%n_loads > 0) list = list//',point_loads'
    if (deck%n_contacts > 0) list = list//',contact'
    if (deck%mass_damping > 0) list = list//',mass_damping'
  end function solver_effects

  subroutine solver_setup(s, deck, comm, status, message)
    type(solver_t), intent(inout) :: s
    type(deck_t), intent(in) :: deck
    type(MPI_Comm), intent(in) :: comm
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer :: g, p, n, nip, first, nl, ne, l, j
    integer, allocatable :: owner(:)
    character(len=8) :: gather_mode
    real(wp), allocatable :: dt_element(:), node_mass(:), node_inertia(:), xg(:, :, :)
    real(wp) :: dt_local

    status = 0
    message = ''
    call MPI_Comm_rank(comm, s%rank)
    call MPI_Comm_size(comm, s%n_ranks)
    s%threads = omp_get_max_threads()
    ! every rank computes the same owner array from the global deck
    allocate (owner(deck%n_elements))
    call partition_elements(deck%partition, deck%coordinates, deck%connectivity, s%n_ranks, owner)
    call decompose(deck%n_nodes, deck%n_elements, deck%connectivity, deck%element_part, owner, &
                   s%n_ranks, s%rank, s%dom)
    call halo_setup(s%dom, comm, s%halo)
    nl = s%dom%n_nodes
    ne = s%dom%n_elements
    allocate (s%props(deck%n_parts))
    do p = 1, deck%n_parts
      s%props(p) = part_properties(deck, p)
    end do

    s%x0 = deck%coordinates(:, s%dom%nodes)
    s%x = s%x0
    s%v = deck%velocity(:, s%dom%nodes)
    s%w = deck%angular_velocity(:, s%dom%nodes)
    s%v_old = s%v
    s%w_old = s%w
    s%fixed = deck%fixed(:, s%dom%nodes)
    s%weight = real(s%dom%node_owned, wp)
    where (s%fixed(1:3, :) /= 0) s%v = 0.0_wp
    where (s%fixed(4:6, :) /= 0) s%w = 0.0_wp
    allocate (s%f_int(6, nl), s%f_ext(6, nl), s%f_ext_old(6, nl), source=0.0_wp)
    allocate (s%corner(6, 4 * ne + s%dom%n_ghost_slots), source=0.0_wp)
    allocate (s%e_internal(ne), s%e_hourglass(ne), source=0.0_wp)
    s%threads = max(s%threads, 1)
    allocate (s%workspace(workspace_per_group, s%threads), source=0.0_wp)

    ! element state pools
    allocate (s%stress_at(s%dom%n_groups + 1), s%back_at(s%dom%n_groups + 1))
    allocate (s%eps_p_at(s%dom%n_groups + 1), s%hourglass_at(s%dom%n_groups + 1))
    s%stress_at(1) = 1
    s%back_at(1) = 1
    s%eps_p_at(1) = 1
    s%hourglass_at(1) = 1
    do g = 1, s%dom%n_groups
      n = s%dom%group_count(g)
      nip = s%props(s%dom%group_part(g))%integration_points
      s%stress_at(g + 1) = s%stress_at(g) + n * stress_components * nip
      s%back_at(g + 1) = s%back_at(g) + n * 3 * back_stress_points(s%props(s%dom%group_part(g)))
      s%eps_p_at(g + 1) = s%eps_p_at(g) + n * nip
      s%hourglass_at(g + 1) = s%hourglass_at(g) + n * hourglass_components
    end do
    allocate (s%stress(s%stress_at(s%dom%n_groups + 1) - 1), source=0.0_wp)
    allocate (s%back(s%back_at(s%dom%n_groups + 1) - 1), source=0.0_wp)
    allocate (s%eps_p(s%eps_p_at(s%dom%n_groups + 1) - 1), source=0.0_wp)
    allocate (s%hourglass(s%hourglass_at(s%dom%n_groups + 1) - 1), source=0.0_wp)

    ! lumped mass through the same corner exchange and fixed-order sum as the forces
    dt_local = huge(1.0_wp)
    allocate (dt_element(group_size), node_mass(group_size), node_inertia(group_size))
    allocate (xg(group_size, 3, 4))
    do g = 1, s%dom%n_groups
      n = s%dom%group_count(g)
      first = s%dom%group_first(g)
      p = s%dom%group_part(g)
      call gather_group(n, first, s%dom%connectivity, s%x, xg)
      call blt_lumped_mass(n, xg, s%props(p)%thickness, s%props(p)%density, node_mass, node_inertia)
      call blt_stable_time_step(n, xg, s%props(p), dt_element)
      dt_local = min(dt_local, minval(dt_element(1:n)))
      do j = 1, n
        s%corner(1:3, 4 * (first + j - 2) + 1:4 * (first + j - 1)) = node_mass(j)
        s%corner(4:6, 4 * (first + j - 2) + 1:4 * (first + j - 1)) = node_inertia(j)
      end do
    end do
    call exchange_corners(s%dom, s%halo, s%corner)
    call assemble_nodes(nl, s%dom%assembly_start, s%dom%assembly_slot, s%corner, s%f_int)
    s%mass = s%f_int(1, :)
    s%inertia = s%f_int(4, :)
    s%f_int = 0.0_wp
    if (any(.not. (s%mass > 0.0_wp))) then
      status = 2
      message = 'a node has no mass (zero-area element?); check /elements/connectivity and the coordinates'
    end if
    call MPI_Allreduce(dt_local, s%dt_stable, 1, MPI_DOUBLE_PRECISION, MPI_MIN, comm)
    s%dt_stable = deck%time_step_safety * s%dt_stable
    s%dt = s%dt_stable
    if (deck%time_step > 0.0_wp) then
      if (deck%time_step <= s%dt_stable) then
        s%dt = deck%time_step
      else if (s%rank == 0) then
        write (0, '(a,es11.4,a,es11.4,a)') 'paradyn-engine: warning: the requested time step ', &
          deck%time_step, ' s is above the stable step ', s%dt_stable, ' s; using the stable step'
      end if
    end if

    ! whole steps of equal size that end exactly at end_time (never above the chosen step)
    s%dt = deck%end_time / max(1, ceiling(deck%end_time / s%dt - 1.0e-9_wp))
    s%has_contact = deck%n_contacts > 0
    if (s%has_contact) then
      call contact_setup(deck, s%contact)
      call node_set_setup(s%dom, s%halo, s%contact%global_node, s%contact_nodes)
      ! the lumped masses of the contact nodes, for the penalty's stability cap
      call allgather_node_set(s%halo, s%contact_nodes, spread(s%mass, 1, 3), s%v, s%contact%x, s%contact%v)
      s%contact%mass = s%contact%x(1, :)
      s%contact%time_step = s%dt
      s%contact%rank = s%rank
      s%contact%n_ranks = s%n_ranks
      call get_environment_variable('PARADYN_CONTACT_GATHER', gather_mode)
      s%contact%gather_all = gather_mode == 'all'
      call record_share_setup(size(s%contact%record_nodes, 2), s%n_ranks, s%contact_share)
      call candidate_share_setup(s%n_ranks, s%candidate_share)
    end if
    allocate (s%load_node(deck%n_loads))
    do l = 1, deck%n_loads
      s%load_node(l) = local_node(s%dom, deck%load_node(l))
    end do
    allocate (s%node_out_a(3, size(s%halo%owned_local)), s%node_out_b(3, size(s%halo%owned_local)))
    allocate (s%element_out(5, ne), s%tracked_out(6, deck%n_tracked))
  end subroutine solver_setup

  !> Local id of a global node, 0 if this rank does not hold it.
  pure integer function local_node(dom, global) result(local)
    type(domain_t), intent(in) :: dom
    integer, intent(in) :: global
    integer :: lo, hi, mid
    local = 0
    lo = 1
    hi = dom%n_nodes
    do while (lo <= hi)
      mid = (lo + hi) / 2
      if (dom%nodes(mid) == global) then
        local = mid
        return
      else if (dom%nodes(mid) < global) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function local_node

  !> Element forces of every group for the step that ends at the current positions. The threads
  !> start on their own ranges of groups and then steal (work_queues); a group's forces go to its
  !> own corners, so the thread that computes it does not matter.
  subroutine element_forces(s, dt_strain)
    type(solver_t), intent(inout) :: s
    real(wp), intent(in) :: dt_strain
    integer :: g, n, first, p, tid, emptied, inverted, ox, ov, ow, of
    inverted = 0
    ox = 1
    ov = ox + 12 * group_size
    ow = ov + 12 * group_size
    of = ow + 12 * group_size
    call queues_start(s%group_queues, s%dom%n_groups, s%threads)
    !$omp parallel private(g, n, first, p, tid, emptied) reduction(+:inverted)
    tid = omp_get_thread_num() + 1
    emptied = 0
    do
      g = queues_take(s%group_queues, tid, emptied)
      if (g == 0) exit
      n = s%dom%group_count(g)
      first = s%dom%group_first(g)
      p = s%dom%group_part(g)
      call gather_group(n, first, s%dom%connectivity, s%x, s%workspace(ox, tid))
      call gather_group(n, first, s%dom%connectivity, s%v, s%workspace(ov, tid))
      call gather_group(n, first, s%dom%connectivity, s%w, s%workspace(ow, tid))
      call blt_internal_forces(n, s%workspace(ox, tid), s%workspace(ov, tid), s%workspace(ow, tid), &
                               s%props(p), dt_strain, s%stress(s%stress_at(g)), s%back(s%back_at(g):), &
                               s%eps_p(s%eps_p_at(g)), s%hourglass(s%hourglass_at(g)), &
                               s%workspace(of, tid), s%e_internal(first), s%e_hourglass(first), inverted)
      call scatter_corners(n, first, s%workspace(of, tid), s%corner)
    end do
    !$omp end parallel
    s%inverted = s%inverted + inverted
  end subroutine element_forces

  function wall_clock() result(seconds)
    real(wp) :: seconds
    seconds = MPI_Wtime()
  end function wall_clock

  !> True on every rank when any rank has received a stop signal (stop_signals).
  logical function any_rank_stopped(comm)
    type(MPI_Comm), intent(in) :: comm
    logical :: mine
    mine = stop_signal_received()
    call MPI_Allreduce(mine, any_rank_stopped, 1, MPI_LOGICAL, MPI_LOR, comm)
  end function any_rank_stopped

  !> The busiest rank's element and contact time over the mean of all ranks (1 = balanced).
  real(wp) function load_imbalance(comm, busy, n_ranks)
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: busy
    integer, intent(in) :: n_ranks
    real(wp) :: most, total
    call MPI_Allreduce(busy, most, 1, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
    call MPI_Allreduce(busy, total, 1, MPI_DOUBLE_PRECISION, MPI_SUM, comm)
    load_imbalance = most / max(total / n_ranks, tiny(1.0_wp))
  end function load_imbalance

  !> The /run attributes are written collectively and must agree: every rank takes rank 0's timings.
  subroutine share_root_timings(comm, run)
    type(MPI_Comm), intent(in) :: comm
    type(run_record_t), intent(inout) :: run
    real(wp) :: t(10)
    t = [run%wall_s, run%element_cycles_per_s, run%phase_elements_s, run%phase_contact_s, &
         run%phase_communication_s, run%phase_output_s, run%phase_other_s, run%phase_contact_sort_s, &
         run%phase_contact_search_s, run%phase_contact_force_s]
    call MPI_Bcast(t, size(t), MPI_DOUBLE_PRECISION, 0, comm)
    run%wall_s = t(1)
    run%element_cycles_per_s = t(2)
    run%phase_elements_s = t(3)
    run%phase_contact_s = t(4)
    run%phase_communication_s = t(5)
    run%phase_output_s = t(6)
    run%phase_other_s = t(7)
    run%phase_contact_sort_s = t(8)
    run%phase_contact_search_s = t(9)
    run%phase_contact_force_s = t(10)
  end subroutine share_root_timings

  !> Central-difference velocity update, nodes split into one contiguous range per thread.
  subroutine advance_velocities(s, h, damping)
    type(solver_t), intent(inout) :: s
    real(wp), intent(in) :: h, damping
    integer :: chunk, j0, j1
    real(wp) :: work
    chunk = max(1, (s%dom%n_nodes + s%threads - 1) / s%threads)
    work = 0.0_wp
    !$omp parallel do schedule(static) private(j1) reduction(+:work)
    do j0 = 1, s%dom%n_nodes, chunk
      j1 = min(j0 + chunk - 1, s%dom%n_nodes)
      call update_velocities(j1 - j0 + 1, h, damping, s%mass(j0:j1), s%inertia(j0:j1), s%fixed(:, j0:j1), &
                             s%f_int(:, j0:j1), s%f_ext(:, j0:j1), s%weight(j0:j1), s%v(:, j0:j1), &
                             s%w(:, j0:j1), work)
    end do
    !$omp end parallel do
    s%damping_work = s%damping_work + work
  end subroutine advance_velocities

  subroutine advance_positions(s)
    type(solver_t), intent(inout) :: s
    integer :: chunk, j0, j1
    chunk = max(1, (s%dom%n_nodes + s%threads - 1) / s%threads)
    !$omp parallel do schedule(static) private(j1)
    do j0 = 1, s%dom%n_nodes, chunk
      j1 = min(j0 + chunk - 1, s%dom%n_nodes)
      call update_positions(j1 - j0 + 1, s%dt, s%v(:, j0:j1), s%x(:, j0:j1))
    end do
    !$omp end parallel do
  end subroutine advance_positions

  !> Contact forces act on the nodes like external forces: subtract them from the internal ones.
  !> Only the nodes touched this step have a force (subtracting a zero would change nothing).
  subroutine apply_contact_forces(s)
    type(solver_t), intent(inout) :: s
    integer :: i, k, j
    do i = 1, s%contact%n_touched
      k = s%contact%touched(i)
      j = s%contact_nodes%local(k)
      if (j > 0) s%f_int(1:3, j) = s%f_int(1:3, j) - s%contact%force(:, k)
    end do
  end subroutine apply_contact_forces

  !> Fixed-order nodal sum of the corner forces, nodes split into one contiguous range per thread.
  !> (Static: stealing node blocks here, as the element groups do, moved the forces between the
  !> cores' caches and cost more in the node update than it saved: docs/performance.md.)
  subroutine assemble_forces(s)
    type(solver_t), intent(inout) :: s
    integer :: chunk, j0, nj, nl
    nl = s%dom%n_nodes
    chunk = max(1, (nl + s%threads - 1) / s%threads)
    !$omp parallel do schedule(static) private(j0, nj)
    do j0 = 1, nl, chunk
      nj = min(chunk, nl - j0 + 1)
      call assemble_nodes(nj, s%dom%assembly_start(j0:j0 + nj), s%dom%assembly_slot, s%corner, &
                          s%f_int(:, j0:j0 + nj - 1))
    end do
    !$omp end parallel do
  end subroutine assemble_forces

  !> The time loop, from where the solver stands (the start, a pause, or a restored checkpoint)
  !> to the end time (s%finished), or until a pause: at the first step at or after pause_time, or
  !> when any rank got a stop signal (s%stop_requested). Returns status 0, or 3 with a message on a
  !> numerical failure.
  subroutine solver_run(s, deck, rf, run, status, message, pause_time)
    type(solver_t), intent(inout) :: s
    type(deck_t), intent(in) :: deck
    type(results_file_t), intent(inout) :: rf
    type(run_record_t), intent(out) :: run
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    real(wp), intent(in) :: pause_time
    integer, parameter :: signal_poll_cycles = 16   ! a collective check every few cycles costs nothing
    real(wp) :: t_phase, h
    real(wp) :: phase(5)   ! this call's copy of s%phase, which the contained procedures add to
    logical :: frame_due, record_due

    status = 0
    message = ''
    phase = s%phase
    if (.not. s%started) then
      s%n_steps = max(1, nint(deck%end_time / s%dt))
      call MPI_Barrier(s%halo%comm)
      s%wall_start = MPI_Wtime()
      s%last_progress = s%wall_start
      s%first_cycle = s%cycles
      ! a fresh run computes its first forces; a restored one comes with them
      if (s%cycles == 0) call forces_at_current_state(0.0_wp)
      s%started = .true.
    end if

    do
      if (s%cycles > s%first_cycle .and. s%cycles < s%n_steps) then
        if (s%time >= pause_time - 1.0e-6_wp * s%dt) exit
        if (modulo(s%cycles, signal_poll_cycles) == 0) then
          s%stop_requested = any_rank_stopped(s%halo%comm)
          if (s%stop_requested) exit
        end if
      end if
      if (deck%n_loads > 0) call apply_loads()
      frame_due = is_due(s%frame_index, deck%output_interval)
      record_due = is_due(s%record_index, deck%history_interval)
      if (frame_due .or. record_due) then
        s%v_old = s%v
        s%w_old = s%w
      end if
      h = merge(0.5_wp * s%dt, s%dt, s%cycles == 0)
      t_phase = MPI_Wtime()
      call advance_velocities(s, h, deck%mass_damping)
      phase(5) = phase(5) + MPI_Wtime() - t_phase
      if (frame_due .or. record_due) then
        t_phase = MPI_Wtime()
        if (record_due) then
          call write_record(status, message)
          s%record_index = next_index(deck%history_interval)
        end if
        if (frame_due .and. status == 0) then
          call write_frame()
          s%frame_index = next_index(deck%output_interval)
        end if
        phase(4) = phase(4) + MPI_Wtime() - t_phase
        if (status /= 0) exit
      end if
      if (s%cycles >= s%n_steps) then
        s%finished = .true.
        exit
      end if
      call advance_positions(s)
      s%time = merge(deck%end_time, s%time + s%dt, s%cycles + 1 == s%n_steps)
      s%cycles = s%cycles + 1
      call forces_at_current_state(s%dt)
      if (s%rank == 0 .and. MPI_Wtime() - s%last_progress >= deck%progress_interval) then
        s%last_progress = MPI_Wtime()
        write (*, '(a,i0,a,es13.6,a,es11.4,a,es11.4,a,f0.3)') 'PARADYN-PROGRESS cycle=', s%cycles, &
          ' time=', s%time, ' dt=', s%dt, ' end_time=', deck%end_time, ' wall_s=', s%last_progress - s%wall_start
        flush (6)
      end if
    end do

    s%phase = phase
    run%cycles = s%cycles
    run%ranks = s%n_ranks
    run%threads = s%threads
    run%elements = deck%n_elements
    run%nodes = deck%n_nodes
    run%dt_s = s%dt
    run%dt_stable_s = s%dt_stable
    run%wall_s = MPI_Wtime() - s%wall_start
    run%element_cycles_per_s = real(deck%n_elements, wp) * (s%cycles - s%first_cycle) / max(run%wall_s, 1.0e-12_wp)
    run%phase_elements_s = s%phase(1)
    run%phase_contact_s = s%phase(2)
    run%phase_contact_sort_s = s%contact%time_sort
    run%phase_contact_search_s = s%contact%time_search
    run%phase_contact_force_s = s%contact%time_force
    run%phase_communication_s = s%phase(3)
    run%phase_output_s = s%phase(4)
    run%phase_other_s = max(run%wall_s - sum(s%phase(1:4)), 0.0_wp)
    run%load_imbalance = load_imbalance(s%halo%comm, s%phase(1) + s%phase(2), s%n_ranks)
    if (s%finished) then
      ! one line per rank for the log: the load balance behind the communication phase
      write (*, '(a,i0,5(a,f0.4))') 'PARADYN-PHASES rank=', s%rank, ' elements_s=', s%phase(1), &
        ' contact_s=', s%phase(2), ' communication_s=', s%phase(3), ' output_s=', s%phase(4), &
        ' nodes_s=', s%phase(5)
      flush (6)
    end if
    call share_root_timings(s%halo%comm, run)

  contains

    !> Output number k is due at the first step at or after k * interval, and at the last step.
    logical function is_due(k, interval)
      integer, intent(in) :: k
      real(wp), intent(in) :: interval
      is_due = s%time >= k * interval - 1.0e-6_wp * s%dt .or. s%cycles == s%n_steps
    end function is_due

    !> Index of the first output time after the current step.
    integer function next_index(interval)
      real(wp), intent(in) :: interval
      next_index = floor((s%time + 1.0e-6_wp * s%dt) / interval) + 1
    end function next_index

    subroutine forces_at_current_state(dt_strain)
      real(wp), intent(in) :: dt_strain
      real(wp) :: t0, comm_before
      t0 = MPI_Wtime()
      call element_forces(s, dt_strain)
      phase(1) = phase(1) + MPI_Wtime() - t0
      t0 = MPI_Wtime()
      call exchange_corners(s%dom, s%halo, s%corner)
      phase(3) = phase(3) + MPI_Wtime() - t0
      t0 = MPI_Wtime()
      call assemble_forces(s)
      phase(1) = phase(1) + MPI_Wtime() - t0
      if (s%has_contact) then
        t0 = MPI_Wtime()
        comm_before = phase(3)
        call contact_step(dt_strain)
        call apply_contact_forces(s)
        ! the sharing of contact records inside counts as communication, not twice
        phase(2) = phase(2) + MPI_Wtime() - t0 - (phase(3) - comm_before)
      end if
    end subroutine forces_at_current_state

    !> Contact forces at the current positions. The contact nodes' positions are gathered on every
    !> rank: all of them when a sort is due, else only those that can be in contact before the
    !> next sort (with each rank's largest movement, which tells whether a sort is due). Then per
    !> pass: each rank searches its cyclic share of the slaves for candidates, the candidates are
    !> shared, each rank locally searches its equal block of them, the records are shared, and
    !> every rank sums all of them in slave order. One rank communicates nothing.
    subroutine contact_step(dt_strain)
      real(wp), intent(in) :: dt_strain
      real(wp) :: t0, moved, moved_here
      logical :: sort, new_gather_set
      if (s%contact%gather_subset) then
        call contact_movement(s%contact, moved_here, wall_clock, s%contact_nodes%owned_member, &
                              s%contact_nodes%local, s%x)
        t0 = MPI_Wtime()
        call allgather_node_subset(s%halo, s%contact_nodes, s%x, s%v, s%contact%x, s%contact%v, moved_here, &
                                   moved)
        phase(3) = phase(3) + MPI_Wtime() - t0
        sort = contact_sort_due(s%contact, s%cycles, moved)
      end if
      if (.not. s%contact%gather_subset .or. sort) then
        t0 = MPI_Wtime()
        call allgather_node_set(s%halo, s%contact_nodes, s%x, s%v, s%contact%x, s%contact%v)
        phase(3) = phase(3) + MPI_Wtime() - t0
      end if
      if (.not. s%contact%gather_subset) then
        call contact_movement(s%contact, moved, wall_clock)
        sort = contact_sort_due(s%contact, s%cycles, moved)
      end if
      call contact_begin(s%contact, s%cycles, sort, wall_clock, new_gather_set)
      if (new_gather_set) call node_subset_setup(s%contact_nodes, s%contact%in_gather)
      ! every pair has a pass active in every cycle, so the stages run every step
      call contact_global_search(s%contact, s%cycles, wall_clock)
      if (s%n_ranks > 1) then
        t0 = MPI_Wtime()
        call share_contact_candidates(s%halo, s%candidate_share, s%contact%n_own, s%contact%own_pairs, &
                                      s%contact%n_all, s%contact%all_pairs)
        phase(3) = phase(3) + MPI_Wtime() - t0
      end if
      call contact_candidates(s%contact, s%cycles, wall_clock)
      call contact_local_search(s%contact, wall_clock)
      if (s%n_ranks > 1) then
        t0 = MPI_Wtime()
        call share_contact_records(s%halo, s%contact_share, s%contact%n_candidates, &
                                   s%contact%record_nodes, s%contact%record_force, &
                                   s%contact%record_penetration)
        phase(3) = phase(3) + MPI_Wtime() - t0
      end if
      call contact_sum(s%contact, wall_clock)
      call contact_end(s%contact, s%cycles, dt_strain)
      if (s%cycles == s%n_steps) then
        ! one line per rank for the log: the local searches of each rank (equal blocks), the sorts
        write (*, '(5(a,i0))') 'PARADYN-CONTACT rank=', s%rank, ' sorts=', s%contact%n_sorts, ' pass_steps=', &
          s%contact%n_pass_steps, ' candidates=', s%contact%candidates_total, ' local_searches=', &
          s%contact%candidates_searched
        flush (6)
      end if
    end subroutine contact_step

    !> Loads at the current time and their work since the last step (trapezoidal rule).
    subroutine apply_loads()
      integer :: j
      s%f_ext_old = s%f_ext
      call point_load_forces(deck%n_loads, s%load_node, deck%load_dof, deck%load_value, &
                             deck%load_ramp_time, s%time, s%f_ext)
      if (s%cycles == 0) return
      do j = 1, s%dom%n_nodes
        s%external_work = s%external_work + s%weight(j) * 0.5_wp * s%dt * ( &
          dot_product(s%v(:, j), s%f_ext_old(1:3, j) + s%f_ext(1:3, j)) + &
          dot_product(s%w(:, j), s%f_ext_old(4:6, j) + s%f_ext(4:6, j)))
      end do
    end subroutine apply_loads

    !> Energies and tracked nodes at the current time. Each tracked node is reported by its
    !> owner alone, so the sum over ranks is that owner's value.
    subroutine write_record(status, message)
      integer, intent(out) :: status
      character(len=*), intent(out) :: message
      real(wp) :: sums(8 + 6 * deck%n_tracked)
      integer :: bad, bad_total, k, j
      sums(1) = kinetic_energy(s%dom%n_nodes, s%mass, s%inertia, s%v_old, s%w_old, s%v, s%w, s%weight)
      sums(2) = sum(s%e_internal)
      sums(3) = sum(s%e_hourglass)
      ! every rank computes the same contact, so rank 0 alone reports it
      sums(4) = merge(s%contact%energy, 0.0_wp, s%rank == 0)
      sums(5) = s%external_work - s%damping_work
      sums(6) = merge(s%contact%max_penetration, 0.0_wp, s%rank == 0)
      sums(7) = real(s%inverted, wp)
      sums(8) = merge(1.0_wp, 0.0_wp, any(s%v /= s%v) .or. any(s%f_int /= s%f_int))
      s%tracked_out = 0.0_wp
      do k = 1, deck%n_tracked
        j = local_node(s%dom, deck%tracked_nodes(k))
        if (j == 0) cycle
        if (s%dom%node_owned(j) == 0) cycle
        s%tracked_out(1:3, k) = s%x(:, j) - s%x0(:, j)
        s%tracked_out(4:6, k) = 0.5_wp * (s%v(:, j) + s%v_old(:, j))
      end do
      sums(9:) = reshape(s%tracked_out, [6 * deck%n_tracked])
      call sum_to_root(s%halo, sums)
      s%tracked_out = reshape(sums(9:), [6, deck%n_tracked])
      call results_write_history(rf, s%time, sums(1:6), s%tracked_out(1:3, :), s%tracked_out(4:6, :))
      status = 0
      message = ''
      bad = 0
      if (s%rank == 0) then
        if (sums(7) > 0.0_wp) bad = 1
        if (sums(8) > 0.0_wp .or. sums(1) /= sums(1)) bad = 2
      end if
      call MPI_Allreduce(bad, bad_total, 1, MPI_INTEGER, MPI_MAX, s%halo%comm)
      if (bad_total == 1) then
        status = 3
        write (message, '(a,i0,a,es12.5,a)') 'an element turned inside out (zero or negative area) by cycle ', &
          s%cycles, ', time ', s%time, ' s; reduce the time step or the loading, or refine the mesh'
      else if (bad_total == 2) then
        status = 3
        write (message, '(a,i0,a,es12.5,a)') 'the solution became NaN by cycle ', s%cycles, ', time ', &
          s%time, ' s; the run is unstable (time step too large or a bad material constant)'
      end if
    end subroutine write_record

    !> Every rank writes its owned nodes and its elements into the frame (collective).
    subroutine write_frame()
      integer :: g, n, first, nip, k, j
      real(wp) :: membrane(group_size, 3), von_mises(group_size), plastic(group_size)
      ! threads share the frame's arithmetic; the writes that follow are collective, one call
      !$omp parallel do schedule(static) private(n, first, nip, membrane, von_mises, plastic)
      do g = 1, s%dom%n_groups
        n = s%dom%group_count(g)
        first = s%dom%group_first(g)
        nip = s%props(s%dom%group_part(g))%integration_points
        call blt_element_results(n, nip, s%stress(s%stress_at(g)), s%eps_p(s%eps_p_at(g)), &
                                 membrane(1:n, :), von_mises(1:n), plastic(1:n))
        s%element_out(1:3, first:first + n - 1) = transpose(membrane(1:n, :))
        s%element_out(4, first:first + n - 1) = von_mises(1:n)
        s%element_out(5, first:first + n - 1) = plastic(1:n)
      end do
      !$omp end parallel do
      !$omp parallel do schedule(static) private(j)
      do k = 1, size(s%halo%owned_local)
        j = s%halo%owned_local(k)
        s%node_out_a(:, k) = s%x(:, j) - s%x0(:, j)
        s%node_out_b(:, k) = 0.5_wp * (s%v(:, j) + s%v_old(:, j))
      end do
      !$omp end parallel do
      call results_write_frame(rf, s%time, s%node_out_a, s%node_out_b, s%element_out(1:3, :), &
                               s%element_out(4, :), s%element_out(5, :))
    end subroutine write_frame

  end subroutine solver_run

end module explicit_solver
