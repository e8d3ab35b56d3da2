!> The parallel contact protocol of one step, and its checkpoint state: everything the solver asks
!> of the contact goes through this module (set-up, the step, the forces on the nodes, the
!> checkpoint rows and their restore), around the pure stages of contact_interface and the MPI
!> sharing of contact_exchange.
!>
!> A step on several ranks (local contact, contact_neighbours): this domain's contact nodes and
!> the ghosts near its slaves are brought up to date (new ghosts at a sort), each rank searches
!> the slaves it owns, the records go to the ranks that hold their nodes, each rank sums the
!> records it has in pass and slave order, and the energy and the definitions' forces are exact
!> sums of every rank's terms (contact_reduction), the same on every rank. With
!> contact_gather = "all", the paper's replicated scheme: every contact node gathered on every
!> rank, the candidates shared and cut into equal blocks, every record on every rank (the
!> reference that takes no shortcut). One rank communicates nothing.
!>
!> Idle is cheap: at activity checks (contact_activity) every rank measures the extents of its own
!> nodes of each pass, one maximum reduction combines them, and a pass that cannot touch before
!> the next check runs no stage. When every pass is idle and no force is left from the last step,
!> the step measures only what the sort schedule needs (so the sorts fall as without the skip, and
!> the answer is bitwise the same) and skips the search stages and their sharing.
module contact_parallel
  use mpi_f08, only: MPI_Comm, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_MAX
  use paradyn_kinds, only: wp, i8
  use model_deck, only: deck_t
  use domain_decomposition, only: domain_t
  use phase_timers, only: phase_timers_t, wall_clock
  use traffic_counter, only: traffic_t, count_allgather, count_allreduce
  use contact_slots, only: contact_node_state, contact_pass_slots, slot_of
  use contact_motion, only: contact_movement
  use contact_interface, only: contact_t, contact_setup, contact_begin, contact_sort_due, &
                               contact_activity_update, contact_all_idle, contact_count_activity, &
                               contact_sort_pass
  use contact_room, only: contact_rooms
  use contact_activity, only: extent_width, extent_empty, side_extent
  use contact_stages, only: contact_global_search, contact_candidates, contact_local_search, contact_sum, &
                            contact_end, contact_finish
  use exact_sum, only: exact_width
  use paradyn_schema, only: contact_kind_is_edge_to_edge
  use contact_reduction, only: reduce_contact_sums
  use contact_local_setup, only: local_contact_setup
  use tie_failures, only: gather_tie_failures
  use contact_exchange, only: node_set_t, node_set_setup, allgather_node_set, node_subset_setup, &
                              node_set_masses, allgather_node_subset, record_share_t, record_share_setup, share_contact_records, &
                              candidate_share_t, candidate_share_setup, share_contact_candidates
  use contact_neighbours, only: neighbours_t, neighbours_setup, neighbours_refresh, neighbours_update
  use contact_record_routes, only: share_records_locally
  use contact_erosion_marks, only: contact_erode
  use contact_birth_gaps, only: contact_birth_overlaps
  implicit none
  private
  public :: parallel_contact_t, parallel_contact_setup, parallel_contact_step
  public :: contact_log_line
  public :: parallel_contact_worked, parallel_contact_idle_cycles, contact_travel_step
  public :: contact_is_local

  type :: parallel_contact_t
    type(contact_t) :: c                  !< the contact state, the same on every rank
    type(node_set_t) :: nodes             !< where each contact node lives, and its gathers
    type(record_share_t) :: records
    type(candidate_share_t) :: candidates
    type(MPI_Comm) :: comm
    integer, allocatable :: owned_local(:)    !< the local columns of the contact nodes this rank owns (nodes%owned_member)
    real(wp), allocatable :: extents(:, :)    !< (extent_width, 2 passes): the activity check's slave and master extents
    real(wp), allocatable :: v_before(:, :)   !< velocities (local columns) of own contact nodes, the cycle before a check
    integer(i8) :: v_before_cycle = -huge(1_i8)      !< the cycle they are from
    type(traffic_t) :: traffic                !< messages and bytes of the contact's sharing (traffic_counter)
    type(neighbours_t) :: nb                  !< local contact: ghosts and record routes (contact_neighbours)
    logical :: touched_anywhere = .false.     !< local contact: a force was left on some rank last step
  end type parallel_contact_t

contains

  !> Contact of the deck's pairs on this rank's domain (mass, v: the local nodal masses and
  !> velocities; dt: the solver's step, for the penalty's stability cap): under local contact from
  !> this rank's rows (rows: contact_local_setup), else from the contact parts in the global
  !> layout (contact: contact_global_rows, released once the passes are built; empty under local
  !> contact). gather_all: no shortcut, every contact node gathered, every pass run every step (to
  !> check that those change nothing).
  subroutine parallel_contact_setup(pc, contact, rows, dom, comm, mass, v, dt, gather_all)
    type(parallel_contact_t), intent(out) :: pc
    type(deck_t), intent(inout) :: contact
    type(deck_t), intent(in) :: rows
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: mass(:), v(:, :), dt
    logical, intent(in) :: gather_all
    real(wp), allocatable :: masses(:)
    integer, allocatable :: contact_of(:), held(:), columns(:)
    logical, allocatable :: owned(:)
    logical :: local
    integer :: k, j
    pc%comm = comm
    ! local contact on more than one rank, unless every node is gathered (the replicated reference)
    local = contact_is_local(dom%n_ranks, gather_all, rows%contact_kind)
    ! the nodes held: every contact node, or (local contact) this domain's until the first refresh,
    ! with their local columns (0: not in this domain) and the masses for the stability cap
    ! (local: this domain's, the ghosts' come with them)
    if (local) then
      call local_contact_setup(rows, dom, comm, pc%c, contact_of)
      held = pack(contact_of, contact_of > 0)
      columns = pack([(k, k = 1, dom%n_nodes)], contact_of > 0)
      masses = mass(columns)
      pc%nodes%owned_member = pack(contact_of, contact_of > 0 .and. dom%node_owned == 1)
    else
      call contact_setup(contact, pc%c)
      call node_set_setup(dom, comm, pc%c%global_node, .true., pc%nodes)
      call node_set_masses(comm, pc%nodes, .true., mass, masses)
      held = [(k, k = 1, pc%c%n_nodes)]
      columns = pc%nodes%local
    end if
    contact = deck_t()
    pc%c%local = local
    allocate (owned(size(held)), source=.false.)
    do k = 1, size(held)
      if (columns(k) > 0) owned(k) = dom%node_owned(columns(k)) == 1
    end do
    pc%owned_local = pack(columns, owned)
    call contact_node_state(pc%c, held, masses, columns, owned)
    call contact_pass_slots(pc%c)
    do k = 1, size(pc%c%passes)
      associate (pass => pc%c%passes(k))
      pass%slave_columns = owned_columns(pass%slave_at)
      if (pass%edges) pass%slave_columns = owned_columns([pass%slave_at, pass%slave_other_at])
      pass%master_columns = owned_columns([(slot_of(pc%c, pass%own_masters(j)), j = 1, size(pass%own_masters))])
      end associate
    end do
    pc%c%time_step = dt
    pc%c%soft_step = dt
    pc%c%rank = dom%rank
    pc%c%n_ranks = dom%n_ranks
    pc%c%gather_all = gather_all
    pc%c%check_activity = .not. gather_all
    allocate (pc%extents(extent_width, 2 * size(pc%c%passes)))
    allocate (pc%v_before(3, size(v, 2)), source=0.0_wp)
    allocate (pc%c%sums(exact_width, 1 + size(pc%c%definition_force)), source=0_i8)
    if (pc%c%local) call neighbours_setup(pc%nb, dom, comm, contact_of)
    call contact_rooms(pc%c)   ! local contact: for this rank's own slaves (contact_room)
    if (.not. allocated(pc%c%failed_ties)) allocate (pc%c%failed_ties(0))   ! (tie_failures; a restart's restore)
    call record_share_setup(merge(0, size(pc%c%record_nodes, 2), pc%c%local), dom%n_ranks, pc%records)
    call candidate_share_setup(dom%n_ranks, pc%candidates)
  contains
    !> The local columns of the nodes at these slots that this rank owns.
    function owned_columns(slots) result(cols)
      integer, intent(in) :: slots(:)
      integer, allocatable :: cols(:)
      integer :: i
      cols = pack([(pc%c%column(slots(i)), i = 1, size(slots))], [(pc%c%own(slots(i)), i = 1, size(slots))])
    end function owned_columns
  end subroutine parallel_contact_setup

  !> Whether the contact is local (each rank its own slaves and the ghosts near them): on more than
  !> one rank, unless every node is gathered (contact_gather = "all", the replicated scheme) or a
  !> definition (kinds: the deck's contact kinds) has edge passes, which run in the replicated
  !> scheme (edge_to_edge_contact: an edge's two nodes may lie in different domains).
  pure logical function contact_is_local(n_ranks, gather_all, kinds)
    integer, intent(in) :: n_ranks
    logical, intent(in) :: gather_all
    integer, intent(in) :: kinds(:)
    contact_is_local = n_ranks > 1 .and. .not. gather_all .and. .not. any(contact_kind_is_edge_to_edge(kinds))
  end function contact_is_local

  !> Contact forces at the positions x (local nodes) of this cycle. Communication time goes to
  !> timers%communication, the rest to timers%contact.
  subroutine parallel_contact_step(pc, x, v, cycle, dt_strain, timers)
    type(parallel_contact_t), intent(inout) :: pc
    real(wp), intent(in) :: x(:, :), v(:, :), dt_strain
    integer(i8), intent(in) :: cycle
    type(phase_timers_t), intent(inout) :: timers
    real(wp) :: t_start, comm_before, t0
    t_start = wall_clock()
    comm_before = timers%communication
    if (pc%c%check_activity) then
      if (cycle >= pc%c%next_check) call activity_check(pc, x, v, cycle, timers)
      if (cycle == pc%c%next_check - 1) call keep_velocities(pc, v, cycle)
    end if
    call contact_count_activity(pc%c)
    if (pc%c%local) then
      call local_positions(pc, x, v, cycle, timers)
    else
      call gather_positions(pc, x, v, cycle, timers)
      pc%touched_anywhere = pc%c%n_touched_old > 0
    end if
    call contact_erode(pc%c)   ! erosion since the last step, after the sort (the grids are rebuilt from its positions)
    call contact_birth_overlaps(pc%c)   ! a "gap" definition born now: its overlaps at these positions
    ! every pass idle and no force left from the last step: no stage has anything to do
    pc%c%last_step_worked = .not. (contact_all_idle(pc%c) .and. .not. pc%touched_anywhere)
    if (.not. pc%c%last_step_worked) then
      pc%c%n_candidates = 0
      timers%contact = timers%contact + wall_clock() - t_start - (timers%communication - comm_before)
      return
    end if
    call contact_global_search(pc%c, cycle, wall_clock)
    if (pc%c%n_ranks > 1 .and. .not. pc%c%local) then
      call timed_share_candidates(pc, timers)
    end if
    call contact_candidates(pc%c, cycle, wall_clock)
    call contact_local_search(pc%c, wall_clock)
    t0 = wall_clock()
    call gather_tie_failures(pc%comm, pc%c)   ! the ties that failed this step, on every rank
    timers%communication = timers%communication + wall_clock() - t0
    ! no candidate on any rank (every rank holds the same count): no record to share
    if (pc%c%local) then
      t0 = wall_clock()
      call share_records_locally(pc%nb, pc%c, pc%traffic)
      timers%communication = timers%communication + wall_clock() - t0
    else if (pc%c%n_ranks > 1 .and. pc%c%n_candidates > 0) then
      call timed_share_records(pc, timers)
    end if
    call contact_sum(pc%c, wall_clock)
    ! local contact: the terms of the energy are counted by the owners of the nodes, which read
    ! the velocities of those this step's records touched
    if (pc%c%local) call copy_domain_slots(pc, pc%c%touched(1:pc%c%n_touched), x, v)
    call contact_end(pc%c, cycle)
    if (pc%c%local) then
      t0 = wall_clock()
      call reduce_contact_sums(pc%comm, pc%c%n_ranks, pc%c%sums, pc%c%max_penetration, pc%traffic)
      timers%communication = timers%communication + wall_clock() - t0
    end if
    call contact_finish(pc%c, cycle, dt_strain)
    ! the sharing inside counts as communication, not twice
    timers%contact = timers%contact + wall_clock() - t_start - (timers%communication - comm_before)
  end subroutine parallel_contact_step

  !> The largest step in which a slave and a master of an active pass close by at most `fraction` of
  !> the pass's thinner contact thickness, their closing speed bounded by twice the speed of the
  !> pass's fastest node (v: local velocities; this rank's own nodes; huge when none moves): a bound
  !> from one node's speed makes the least over the ranks independent of the layout.
  real(wp) function contact_travel_step(pc, v, fraction) result(dt)
    type(parallel_contact_t), intent(in) :: pc
    real(wp), intent(in) :: v(:, :), fraction
    real(wp) :: closing, reach
    integer :: p
    dt = huge(1.0_wp)
    do p = 1, size(pc%c%passes)
      if (pc%c%passes(p)%idle) cycle
      associate (pass => pc%c%passes(p))
      closing = 2.0_wp * sqrt(max(fastest2_of(pass%slave_columns), fastest2_of(pass%master_columns)))
      reach = fraction * min(pass%t_slave, pass%t_master)
      if (closing > 0.0_wp) dt = min(dt, reach / closing)
      end associate
    end do
  contains
    real(wp) function fastest2_of(columns) result(f)
      integer, intent(in) :: columns(:)
      integer :: i, j
      f = 0.0_wp
      do i = 1, size(columns)
        j = columns(i)
        f = max(f, v(1, j)**2 + v(2, j)**2 + v(3, j)**2)
      end do
    end function fastest2_of
  end function contact_travel_step

  !> The velocities of this rank's own contact nodes the cycle before a check, for the
  !> accelerations the check bounds the motion with.
  subroutine keep_velocities(pc, v, cycle)
    type(parallel_contact_t), intent(inout) :: pc
    real(wp), intent(in) :: v(:, :)
    integer(i8), intent(in) :: cycle
    integer :: i, j
    do i = 1, size(pc%owned_local)
      j = pc%owned_local(i)
      pc%v_before(:, j) = v(:, j)
    end do
    pc%v_before_cycle = cycle
  end subroutine keep_velocities

  !> The activity check (contact_activity): the extents of each pass's slaves and masters over
  !> this rank's own nodes, their maxima over the ranks (exact in any order), and which passes
  !> run until the next check. Without the velocities of the cycle before (the first step, a
  !> restart), the passes stay as they are and the check comes again two cycles later.
  subroutine activity_check(pc, x, v, cycle, timers)
    type(parallel_contact_t), intent(inout) :: pc
    real(wp), intent(in) :: x(:, :), v(:, :)
    integer(i8), intent(in) :: cycle
    type(phase_timers_t), intent(inout) :: timers
    integer :: p
    real(wp) :: t0
    logical :: new_gather_set
    if (pc%v_before_cycle /= cycle - 1) then
      pc%c%next_check = cycle + 2
      pc%c%last_check = cycle
      return
    end if
    do p = 1, size(pc%c%passes)
      pc%extents(:, 2 * p - 1) = extent_empty()
      pc%extents(:, 2 * p) = extent_empty()
      call side_extent(pc%c%passes(p)%slave_columns, x, v, pc%v_before, pc%extents(:, 2 * p - 1))
      call side_extent(pc%c%passes(p)%master_columns, x, v, pc%v_before, pc%extents(:, 2 * p))
    end do
    if (pc%c%n_ranks > 1) then
      t0 = wall_clock()
      call MPI_Allreduce(MPI_IN_PLACE, pc%extents, size(pc%extents), MPI_DOUBLE_PRECISION, MPI_MAX, pc%comm)
      call count_allreduce(pc%traffic, int(8 * size(pc%extents), i8), pc%c%n_ranks)
      timers%communication = timers%communication + wall_clock() - t0
    end if
    ! every step has the solver's step (step_clock), also the first, whose strain step is 0
    call contact_activity_update(pc%c, pc%extents, cycle, pc%c%time_step, new_gather_set)
    if (new_gather_set) call node_subset_setup(pc%nodes, pc%c%in_gather)
  end subroutine activity_check

  !> The positions and velocities the step reads, and the bucket sort when one is due. With every
  !> pass idle, nothing left to sum and a sort schedule that needs no positions (a fixed interval,
  !> or the first sort), positions are gathered only for a sort.
  subroutine gather_positions(pc, x, v, cycle, timers)
    type(parallel_contact_t), intent(inout) :: pc
    real(wp), intent(in) :: x(:, :), v(:, :)
    integer(i8), intent(in) :: cycle
    type(phase_timers_t), intent(inout) :: timers
    real(wp) :: t0, moved, moved_here
    logical :: sort, new_gather_set, quiet
    sort = .false.
    moved = huge(1.0_wp)                  ! unknown (a fixed sort interval measures nothing)
    quiet = .not. pc%c%gather_subset .and. contact_all_idle(pc%c) .and. pc%c%n_touched == 0 &
            .and. (pc%c%sort_interval > 0 .or. pc%c%last_sort < 0)
    if (quiet) then
      sort = contact_sort_due(pc%c, cycle, 0.0_wp)
      if (sort) then
        t0 = wall_clock()
        call allgather_node_set(pc%comm, pc%nodes, x, v, pc%c%x, pc%c%v)
        timers%communication = timers%communication + wall_clock() - t0
        call count_gather(pc, pc%nodes%counts, 8)
      end if
    else if (pc%c%gather_subset) then
      call contact_movement(pc%c, moved_here, wall_clock, pc%nodes%owned_member, pc%owned_local, x)
      t0 = wall_clock()
      call allgather_node_subset(pc%comm, pc%nodes, x, v, pc%c%x, pc%c%v, moved_here, moved)
      timers%communication = timers%communication + wall_clock() - t0
      call count_gather(pc, pc%nodes%sub_counts, 8)
      sort = contact_sort_due(pc%c, cycle, moved)
    end if
    if (.not. quiet .and. (.not. pc%c%gather_subset .or. sort)) then
      t0 = wall_clock()
      call allgather_node_set(pc%comm, pc%nodes, x, v, pc%c%x, pc%c%v)
      timers%communication = timers%communication + wall_clock() - t0
      call count_gather(pc, pc%nodes%counts, 8)
    end if
    if (.not. quiet .and. .not. pc%c%gather_subset) then
      call contact_movement(pc%c, moved, wall_clock)
      sort = contact_sort_due(pc%c, cycle, moved)
    end if
    call contact_begin(pc%c, cycle, sort, wall_clock, new_gather_set)
    if (new_gather_set) call node_subset_setup(pc%nodes, pc%c%in_gather)
    ! how far any contact node has moved from the positions of the sort the step's grids are from
    pc%c%moved = huge(1.0_wp)
    if (sort) then
      pc%c%moved = 0.0_wp
    else if (pc%c%sort_interval == 0 .and. pc%c%last_sort >= 0 .and. .not. quiet) then
      pc%c%moved = moved
    end if
  end subroutine gather_positions

  !> Local contact: this domain's contact nodes from x and v, the largest movements since the last
  !> sort and the last refresh of the ghosts and whether any rank carries a force (one maximum
  !> reduction), then new ghosts (at a sort, after a restore, or once a node has moved a tenth of
  !> the smallest bucket since the last refresh: contact_neighbours) or the ghosts' new positions,
  !> and the bucket sort when one is due (a refresh between sorts regrids from the positions of
  !> the last sort, which is the same grid over the masters now held).
  subroutine local_positions(pc, x, v, cycle, timers)
    type(parallel_contact_t), intent(inout) :: pc
    real(wp), intent(in) :: x(:, :), v(:, :)
    integer(i8), intent(in) :: cycle
    type(phase_timers_t), intent(inout) :: timers
    real(wp) :: t0, values(3), smallest
    integer :: i, j, p
    logical :: sort, refresh, new_gather_set
    call contact_movement(pc%c, values(1), wall_clock, pc%nodes%owned_member, pc%owned_local, x)
    ! automatic sorting refreshes at every sort (after a restart from the slaves' places at the last
    ! sort), so the movement since the sort is the movement since the refresh
    values(2) = values(1)
    if (pc%c%sort_interval > 0) then
      values(2) = 0.0_wp
      do i = 1, size(pc%nb%owned_node)
        j = pc%owned_local(i)   ! (nb%owned_node is nodes%owned_member)
        values(2) = max(values(2), (x(1, j) - pc%nb%x_at_refresh(1, i))**2 + (x(2, j) - pc%nb%x_at_refresh(2, i))**2 &
                                   + (x(3, j) - pc%nb%x_at_refresh(3, i))**2)
      end do
      values(2) = sqrt(values(2))
    end if
    values(3) = merge(1.0_wp, 0.0_wp, pc%c%n_touched > 0)
    t0 = wall_clock()
    call MPI_Allreduce(MPI_IN_PLACE, values, 3, MPI_DOUBLE_PRECISION, MPI_MAX, pc%comm)
    call count_allreduce(pc%traffic, 24_i8, pc%c%n_ranks)
    timers%communication = timers%communication + wall_clock() - t0
    pc%touched_anywhere = values(3) > 0.0_wp
    sort = contact_sort_due(pc%c, cycle, values(1))
    smallest = minval([(pc%c%passes(p)%bucket_size, p = 1, size(pc%c%passes))])
    refresh = sort .or. pc%nb%refresh_pending .or. values(2) > 0.1_wp * smallest
    if (refresh) then   ! every contact node of this domain, for the boxes and the ghosts
      call copy_domain_slots(pc, [(i, i = 1, size(pc%c%held_node))], x, v)
    else                ! those the step reads: near slaves, own segments near them, last forces
      do p = 1, size(pc%c%passes)
        call copy_domain_slots(pc, pc%c%passes(p)%slave_at(pc%c%passes(p)%near_slaves(1:pc%c%passes(p)%n_near)), x, v)
      end do
      call copy_domain_slots(pc, pc%nb%own_near, x, v)
      call copy_domain_slots(pc, pc%c%touched(1:pc%c%n_touched), x, v)
    end if
    t0 = wall_clock()
    if (refresh) then
      call neighbours_refresh(pc%nb, pc%c, sort, pc%c%sort_interval == 0 .and. .not. sort, pc%traffic)
    else
      call neighbours_update(pc%nb, pc%c, x, v, pc%traffic)
    end if
    timers%communication = timers%communication + wall_clock() - t0
    call contact_begin(pc%c, cycle, sort, wall_clock, new_gather_set)
    if (refresh .and. .not. sort .and. pc%c%last_sort >= 0) then
      do p = 1, size(pc%c%passes)
        if (pc%c%passes(p)%idle) then
          pc%c%passes(p)%stale = .true.
        else
          call contact_sort_pass(pc%c, p)
        end if
      end do
    end if
    pc%c%moved = huge(1.0_wp)
    if (sort) then
      pc%c%moved = 0.0_wp
    else if (pc%c%sort_interval == 0 .and. pc%c%last_sort >= 0) then
      pc%c%moved = values(1)
    end if
  end subroutine local_positions

  !> c%x and c%v of the nodes at the given slots that lie in this domain, from x and v.
  subroutine copy_domain_slots(pc, slots, x, v)
    type(parallel_contact_t), intent(inout) :: pc
    integer, intent(in) :: slots(:)
    real(wp), intent(in) :: x(:, :), v(:, :)
    integer :: i, j, k
    do i = 1, size(slots)
      k = slots(i)
      j = pc%c%column(k)
      if (j == 0) cycle
      pc%c%x(:, k) = x(:, j)
      pc%c%v(:, k) = v(:, j)
    end do
  end subroutine copy_domain_slots

  subroutine timed_share_candidates(pc, timers)
    type(parallel_contact_t), intent(inout) :: pc
    type(phase_timers_t), intent(inout) :: timers
    real(wp) :: t0
    integer :: k
    t0 = wall_clock()
    call share_contact_candidates(pc%comm, pc%candidates, pc%c%n_own, pc%c%own_pairs, pc%c%n_all, pc%c%all_pairs)
    timers%communication = timers%communication + wall_clock() - t0
    call count_gather(pc, [(1, k = 1, pc%c%n_ranks)], 4)   ! the counts
    call count_gather(pc, pc%candidates%counts, 4)
  end subroutine timed_share_candidates

  subroutine timed_share_records(pc, timers)
    type(parallel_contact_t), intent(inout) :: pc
    type(phase_timers_t), intent(inout) :: timers
    real(wp) :: t0
    integer :: k
    t0 = wall_clock()
    call share_contact_records(pc%comm, pc%records, pc%c%n_candidates, pc%c%record_nodes, pc%c%record_force, &
                               pc%c%record_penetration)
    timers%communication = timers%communication + wall_clock() - t0
    call count_gather(pc, [(1, k = 1, pc%c%n_ranks)], 4)   ! the counts
    call count_gather(pc, pc%records%counts, 8)
  end subroutine timed_share_records

  !> Counts an allgather(v) whose per-rank counts are `counts` items of `item_bytes` each.
  subroutine count_gather(pc, counts, item_bytes)
    type(parallel_contact_t), intent(inout) :: pc
    integer, intent(in) :: counts(:), item_bytes
    call count_allgather(pc%traffic, int(item_bytes, i8) * counts(pc%c%rank + 1), &
                         int(item_bytes, i8) * sum(int(counts, i8)), pc%c%n_ranks)
  end subroutine count_gather

  !> One line per rank for the log: the sorts, the passes run, all ranks' candidates, the local
  !> searches of this rank (its equal blocks of the candidates), and the cycles the contact
  !> definitions were skipped as idle (summed over the definitions).
  subroutine contact_log_line(pc, rank)
    type(parallel_contact_t), intent(in) :: pc
    integer, intent(in) :: rank
    write (*, '(8(a,i0))') 'PARADYN-CONTACT rank=', rank, ' sorts=', pc%c%n_sorts, ' pass_steps=', &
      pc%c%n_pass_steps, ' candidates=', pc%c%candidates_total, ' local_searches=', pc%c%candidates_searched, &
      ' idle_cycles=', parallel_contact_idle_cycles(pc), ' held=', pc%c%held_most, ' contact_nodes=', pc%c%n_nodes
    flush (6)
  end subroutine contact_log_line

  !> Whether the last step ran the contact's search stages (false: every pair idle, skipped).
  pure logical function parallel_contact_worked(pc)
    type(parallel_contact_t), intent(in) :: pc
    parallel_contact_worked = pc%c%last_step_worked
  end function parallel_contact_worked

  !> The cycles the contact definitions were skipped as idle, summed over the definitions.
  pure integer(i8) function parallel_contact_idle_cycles(pc)
    type(parallel_contact_t), intent(in) :: pc
    parallel_contact_idle_cycles = sum(pc%c%pair_skipped_cycles)
  end function parallel_contact_idle_cycles


end module contact_parallel
