!> The contact state of a run: its set-up from the deck (each definition's passes from its member
!> of the contact family), the start of a step (bucket sorts, which nodes to gather), and its
!> restore from a checkpoint. The stages of a step are in contact_stages, the sharing between
!> ranks in contact_exchange, and the protocol that strings them together in contact_parallel.
!>
!> Shells are two-sided and thick: the contact surface lies half a thickness off each
!> mid-surface, with edges and corners rounded by that half thickness, so a node meets the
!> faceted surface at its true distance (a node beyond a facet's edge is not measured against the
!> facet's extended plane, which on a faceted cylinder would make contact start early).
!>
!> A pair (node_to_segment_contact) gives two passes, each body slave to the other's segments: both every step
!> (passes = 2, the default) or one per step, alternating as in the paper (passes = 1). The
!> passes of a step run together, in the paper's two parallel stages (docs/theory.md, parallel
!> contact), so a step shares candidates and records once whatever the number of passes:
!>   1. global search (contact_global_search): each rank's slaves (local contact: those it owns;
!>      the replicated scheme: a cyclic share of all), inside a rank dealt to the threads; each
!>      slave near the master box gets its nearest master node, and the pairs (slave, nearest
!>      master) found are this rank's candidates;
!>   2. the replicated scheme shares the candidates between ranks; contact_candidates puts them in
!>      ascending slave order and gives each rank one contiguous block of equal size (within
!>      one); local contact keeps its own. contact_local_search finds the segment, the closest
!>      point and the penalty force of each candidate, threads sharing them.
!> Every candidate writes its own record (its force and the forces on the 4 master nodes); the
!> records are then summed in candidate order, which is pass order and slave order within a
!> pass, so the result does not depend on the number of threads. Between ranks
!> (contact_neighbours, contact_exchange) each rank gets the records that touch the nodes it
!> holds, by value, and sums them in the same order, so the result does not depend on the number
!> of ranks either. On one rank a sort chooses the nodes that can come into contact before the
!> next one (choose_gather_set). Only the nodes touched in the last two steps carry a force, so
!> only they are cleared, applied and summed into the energy. No MPI here.
module contact_interface
  use paradyn_kinds, only: wp, ip, i8
  use model_deck, only: deck_t
  use contact_buckets, only: bucket_grid_build, bucket_grid_drop
  use contact_pass, only: contact_pass_t
  use contact_kind, only: contact_kind_holder_t
  use contact_factory, only: contact_kind_from_name
  use contact_activity, only: extent_width, idle_cycles, max_idle_cycles, active_recheck_cycles
  use paradyn_schema, only: enum_name, enum_contact_kind
  implicit none
  private
  public :: contact_t, contact_setup, definitions_passes
  public :: contact_begin, contact_sort_due
  public :: contact_restore, contact_sort_pass
  public :: contact_activity_update, contact_all_idle, contact_count_activity
  public :: clock_seconds

  !> The wall clock the phases are timed with (the solver passes MPI_Wtime's wrapper).
  abstract interface
    function clock_seconds() result(seconds)
      import :: wp
      real(wp) :: seconds
    end function clock_seconds
  end interface


  type :: contact_t
    integer :: n_nodes = 0                     !< nodes of all parts in contact
    integer, allocatable :: global_node(:)     !< their global ids, ascending (not under local contact)
    ! the held slots (contact_slots): the contact nodes this rank holds, ascending (every one on
    ! one rank and in the replicated scheme, where slot(node) is each one's; under local contact a
    ! search in held_node finds it: slot_of), their local columns on this rank (0: a ghost) and
    ! whether this rank owns them; the per-node arrays below are indexed by slot
    integer, allocatable :: held_node(:), slot(:), column(:)
    logical, allocatable :: own(:)
    integer :: held_most = 0                   !< the most nodes held at once over the run (the log)
    real(wp), allocatable :: x(:, :), v(:, :)  !< gathered positions and velocities
    real(wp), allocatable :: mass(:)           !< lumped mass of each contact node
    real(wp) :: time_step = 0.0_wp             !< the solver's step, for the stability cap
    !> the soft constraint's step: the largest step of the run so far (LS-DYNA: the initial step,
    !> updated when the step grows), so that a step cut short does not stiffen the spring
    real(wp) :: soft_step = 0.0_wp
    !> the automatic step limit (/control contact_closing_limit): its fraction, and this cycle's
    !> least step over this rank's candidates near their segments (huge: none cuts the step; the
    !> step's choice resets it once used, so an idle cycle leaves it huge and a checkpoint never holds it)
    real(wp) :: closing_limit = 0.0_wp, near_step = huge(1.0_wp)
    real(wp) :: time = 0.0_wp                  !< the time of the step's forces (the passes' birth and death)
    real(wp), allocatable :: force(:, :), force_old(:, :)  !< contact force per contact node
    ! the contact nodes that got a record this step and last step, in the order of the sum (the
    ! same on every rank): only their forces are nonzero, so only they are cleared, applied and
    ! enter the energy; mark(j) == stamp flags the members of touched
    integer, allocatable :: touched(:), touched_old(:), mark(:)
    integer :: n_touched = 0, n_touched_old = 0, stamp = 0
    real(wp), allocatable :: x_at_sort(:, :)   !< positions at the last bucket sort
    ! contact_movement's members: their local columns, and their positions at the last sort in
    ! their order (so the per-step check reads one index and contiguous positions), as of sort
    ! number member_sort
    integer, allocatable :: member_at(:)
    real(wp), allocatable :: member_at_sort(:, :)
    integer(i8) :: member_sort = -1
    logical :: member_run = .false.            !< member_at is one ascending run of columns
    !> this step: the largest distance a contact node has moved since the last sort (0 at a sort,
    !> huge where not measured), for contact_stages' clearances
    real(wp) :: moved = huge(1.0_wp)
    ! the nodes whose positions the contact can read before the next sort (all of them with a
    ! fixed sort interval); the caller gathers only these between sorts once gather_subset is set
    logical, allocatable :: in_gather(:)
    logical :: gather_subset = .false.
    logical :: gather_all = .false.             !< never gather a subset (to check that it changes nothing)
    ! local contact (contact_neighbours): each rank searches the slaves it owns against the masters
    ! it holds (its domain's and the ghosts near its slaves)
    logical :: local = .false.
    type(contact_pass_t), allocatable :: passes(:)
    ! candidates of the step's passes: n_own found here, n_all shared by every rank (the caller
    ! fills all_pairs), n_candidates in pass order and, within a pass, slave order; pairs are
    ! (slave index, master index, pass)
    integer, allocatable :: nearest(:)          !< workspace, one per slave searched here (contact_search_room)
    integer, allocatable :: own_pairs(:, :), all_pairs(:, :), candidates(:, :)  !< (3, n)
    integer, allocatable :: pass_pairs(:, :)    !< (2, n) workspace: one pass's shared pairs
    integer :: n_own = 0, n_all = 0, n_candidates = 0
    integer :: first = 1, last = 0              !< this rank's block of the candidates
    ! counts over the run: sorts, passes run, candidates (all ranks), local searches on this rank
    integer(i8) :: n_sorts = 0, n_pass_steps = 0, candidates_total = 0, candidates_searched = 0
    ! per-candidate records, reused every step: room for every slave of every pass, or (local
    ! contact) for this rank's own slaves, grown as the records it receives need (contact_record_room)
    integer, allocatable :: record_nodes(:, :) !< (5, n) slave then the 4 master nodes, 0 = none
    real(wp), allocatable :: record_force(:, :, :)  !< (3, 5, n)
    real(wp), allocatable :: record_penetration(:)  !< (n)
    !> (n) the candidate's tie failed this step (tiebreak_contact; only in this rank's block)
    logical, allocatable :: record_failed(:)
    !> the ties of tiebreak definitions that have failed (tie_failures), the same on every rank:
    !> keys tie_key(definition, slave's contact-node id), ascending
    integer(i8), allocatable :: failed_ties(:)
    integer :: rank = 0, n_ranks = 1               !< this rank's share of the slaves
    integer(i8) :: last_sort = -huge(1_i8)
    integer :: sort_interval = 0
    real(wp) :: energy = 0.0_wp, max_penetration = 0.0_wp
    real(wp), allocatable :: definition_force(:, :)   !< (3, definitions): force on each one's first part this step
    ! the step's exact sums (exact_sum) of the energy's work and each definition's force, over this
    ! rank's terms; with local contact added over the ranks before they are rounded
    integer(i8), allocatable :: sums(:, :)           !< (exact_width, 1 + 3 definitions)
    real(wp) :: time_sort = 0, time_search = 0, time_force = 0
    ! activity (contact_activity): whether idle passes are skipped (not with gather_all, which
    ! takes no shortcut), the cycles of the next check and of the last, and per contact
    ! definition the cycles it ran its stages and the cycles it was skipped as idle
    logical :: check_activity = .true.
    integer(i8) :: next_check = -huge(1_i8), last_check = 0
    integer(i8), allocatable :: pair_active_cycles(:), pair_skipped_cycles(:)
    logical :: last_step_worked = .false.       !< the last step ran the search stages
    ! erosion (contact_erosion_marks): the global ids of the eroded elements of the contact parts
    ! and the contact-node ids of the nodes whose elements are all eroded, ascending, the same on
    ! every rank; those found since the last step, for the next step to apply
    integer, allocatable :: eroded_elements(:), dead_nodes(:), eroded_pending(:), dead_pending(:)
  end type contact_t

contains

  !> The contact state of the deck's pairs from the contact parts in the global layout (one rank
  !> and the replicated scheme, contact_global_rows; local contact: contact_local_setup): every contact
  !> node, numbered in global id order, and every definition's passes with all their lists.
  subroutine contact_setup(deck, c)
    type(deck_t), intent(in) :: deck
    type(contact_t), intent(out) :: c
    logical, allocatable :: in_contact(:)
    integer, allocatable :: contact_id(:)
    integer :: i, e
    allocate (in_contact(deck%n_nodes), source=.false.)
    do e = 1, deck%n_elements
      if (any(deck%contact_pairs == deck%element_part(e))) in_contact(deck%connectivity(:, e)) = .true.
    end do
    c%global_node = pack([(i, i = 1, deck%n_nodes)], in_contact)
    c%n_nodes = size(c%global_node)
    allocate (contact_id(deck%n_nodes), source=0)
    contact_id(c%global_node) = [(i, i = 1, c%n_nodes)]
    c%sort_interval = deck%contact_sort_interval
    allocate (c%eroded_elements(0), c%dead_nodes(0))
    call definitions_passes(deck, contact_id, c%n_nodes, c%passes)
    allocate (c%pair_active_cycles(deck%n_contacts), c%pair_skipped_cycles(deck%n_contacts), source=0_i8)
    allocate (c%definition_force(3, deck%n_contacts), source=0.0_wp)
  end subroutine contact_setup

  !> Each contact definition's passes, one after the other, from its member of the contact family
  !> (contact_id: the contact-node id of each global node, n_contact of them; empty lists for a
  !> deck without its mesh, whose passes local contact fills from each rank's rows).
  subroutine definitions_passes(deck, contact_id, n_contact, passes)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: contact_id(:), n_contact
    type(contact_pass_t), allocatable, intent(out) :: passes(:)
    type(contact_kind_holder_t), allocatable :: kinds(:)
    integer :: k, p, n_passes
    allocate (kinds(deck%n_contacts))
    n_passes = 0
    do k = 1, deck%n_contacts
      call contact_kind_from_name(enum_name(enum_contact_kind, deck%contact_kind(k)), kinds(k)%kind)
      n_passes = n_passes + kinds(k)%kind%pass_count()
    end do
    allocate (passes(n_passes))
    n_passes = 0
    do k = 1, deck%n_contacts
      p = kinds(k)%kind%pass_count()
      call kinds(k)%kind%make_passes(deck, k, contact_id, n_contact, passes(n_passes + 1:n_passes + p))
      n_passes = n_passes + p
    end do
  end subroutine definitions_passes

  !> Start a step: keep the last forces, redo the bucket sorts if sort (contact_sort_due; the
  !> positions of all contact nodes are then current). Only the nodes touched in the last two
  !> steps hold nonzero forces, so only they are copied and cleared. With sort interval 0, a sort
  !> also chooses the nodes to gather until the next sort (new_gather_set).
  subroutine contact_begin(c, cycle, sort, clock, new_gather_set)
    type(contact_t), intent(inout) :: c
    integer(i8), intent(in) :: cycle
    logical, intent(in) :: sort
    procedure(clock_seconds) :: clock
    logical, intent(out) :: new_gather_set
    integer :: i, j
    real(wp) :: t0
    do i = 1, c%n_touched_old
      c%force_old(:, c%touched_old(i)) = 0.0_wp
    end do
    do i = 1, c%n_touched
      j = c%touched(i)
      c%force_old(:, j) = c%force(:, j)
      c%force(:, j) = 0.0_wp
      c%touched_old(i) = j
    end do
    c%n_touched_old = c%n_touched
    c%n_touched = 0
    c%stamp = c%stamp + 1
    c%max_penetration = 0.0_wp
    c%definition_force = 0.0_wp
    t0 = clock()
    new_gather_set = .false.
    if (sort) call sort_passes(c, cycle, new_gather_set)
    c%time_sort = c%time_sort + clock() - t0
  end subroutine contact_begin

  !> The bucket sort of every pass at the current positions, and (automatic sorting) the nodes to
  !> gather until the next sort: new_gather_set says the caller must take the new set.
  subroutine sort_passes(c, cycle, new_gather_set)
    type(contact_t), intent(inout) :: c
    integer(i8), intent(in) :: cycle
    logical, intent(out) :: new_gather_set
    integer :: p
    c%x_at_sort = c%x
    do p = 1, size(c%passes)
      ! an idle pass sorts when it wakes, from these positions (the same grid as sorting now)
      c%passes(p)%stale = c%passes(p)%idle
      if (.not. c%passes(p)%idle) call contact_sort_pass(c, p)
    end do
    c%last_sort = cycle
    c%n_sorts = c%n_sorts + 1
    new_gather_set = c%sort_interval == 0 .and. .not. c%gather_all .and. .not. c%local
    if (new_gather_set) then
      call choose_gather_set(c)
      c%gather_subset = .true.
    end if
  end subroutine sort_passes

  !> The bucket grid of pass p at the positions of the last sort: of its masters (every one, or under
  !> local contact the masters this rank holds), in ascending order, so that a search on them finds
  !> the same nearest master with the same tie rule (the lower index) wherever it lies within reach.
  !> Local contact also chooses the slaves the global search visits until the next grid: its own
  !> slaves within near_box's margin of the grid's box plus how far a slave can move till then
  !> (each stays within a tenth of the smallest bucket of where it was at the last refresh, so
  !> within a fifth of where it is now; three tenths against round-off): the others would fail
  !> near_box, as choose_gather_set's slaves on one rank.
  subroutine contact_sort_pass(c, p)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: p
    integer :: j, k
    real(wp) :: lower(3), upper(3), margin
    associate (pass => c%passes(p))
    pass%x_sorted = c%x_at_sort(:, pass%master_at)
    call bucket_grid_build(int(size(pass%x_sorted, 2), ip), pass%x_sorted, pass%bucket_size, pass%grid)
    if (pass%any_dead_segment) call bucket_grid_drop(pass%grid, pass%master_dead)   ! eroded: no segment left
    pass%stale = .false.
    if (c%local) then
      margin = pass%bucket_size + pass%t_slave + pass%t_master + 0.3_wp * smallest_bucket(c)
      lower = pass%grid%lower - margin
      upper = pass%grid%upper + margin
      pass%n_near = 0
      do j = 1, size(pass%slaves)
        k = pass%slave_at(j)
        if (any(c%x(:, k) < lower) .or. any(c%x(:, k) > upper)) cycle
        pass%n_near = pass%n_near + 1
        pass%near_slaves(pass%n_near) = j
      end do
      if (size(pass%x_sorted, 2) == 0) pass%n_near = 0
    end if
    end associate
  end subroutine contact_sort_pass

  !> An activity check at this cycle: extents(:, 2 p - 1) and extents(:, 2 p) are the slave and
  !> master extents of pass p over all ranks (contact_activity). A pass that cannot touch for the
  !> next cycles falls idle, one that can wakes (its grid rebuilt from the positions of the last
  !> sort if one fell while it slept, which is the grid it would have now); the next check comes
  !> when the first idle pass may touch, after active_recheck_cycles at the latest while a pass is
  !> active, and never more than twice as far as the last one came (accelerations that grow, as
  !> under a ramped load, are seen at least once per doubling of the time since the start or the
  !> restart). new_gather_set: the caller takes the new set of nodes to gather.
  subroutine contact_activity_update(c, extents, cycle, dt, new_gather_set)
    type(contact_t), intent(inout) :: c
    real(wp), intent(in) :: extents(extent_width, 2 * size(c%passes)), dt
    integer(i8), intent(in) :: cycle
    logical, intent(out) :: new_gather_set
    integer :: p, n, next
    logical :: idle, changed
    changed = .false.
    next = max_idle_cycles
    do p = 1, size(c%passes)
      associate (pass => c%passes(p))
      ! a node touches a segment only within half the two thicknesses of it: their sum is margin enough
      n = idle_cycles(extents(:, 2 * p - 1), extents(:, 2 * p), pass%t_slave + pass%t_master, dt)
      idle = n > 0
      next = min(next, merge(n, active_recheck_cycles, idle))
      changed = changed .or. (idle .neqv. pass%idle)
      pass%idle = idle
      if (.not. idle .and. pass%stale .and. c%last_sort >= 0) call contact_sort_pass(c, p)
      end associate
    end do
    c%next_check = cycle + max(1_i8, min(int(next, i8), 2 * (cycle - c%last_check)))
    c%last_check = cycle
    new_gather_set = changed .and. c%gather_subset
    if (new_gather_set) then
      call choose_gather_set(c)
      ! the nodes that carry last step's forces enter this step's energy at their velocities
      c%in_gather(c%touched(1:c%n_touched)) = .true.
    end if
  end subroutine contact_activity_update

  !> No pass runs its stages.
  pure logical function contact_all_idle(c)
    type(contact_t), intent(in) :: c
    integer :: p
    contact_all_idle = .true.
    do p = 1, size(c%passes)
      if (.not. c%passes(p)%idle) contact_all_idle = .false.
    end do
  end function contact_all_idle

  !> One more cycle for each contact definition: active if one of its passes is.
  subroutine contact_count_activity(c)
    type(contact_t), intent(inout) :: c
    logical :: active(size(c%pair_active_cycles))
    integer :: p
    active = .false.
    do p = 1, size(c%passes)
      if (.not. c%passes(p)%idle) active(c%passes(p)%pair) = .true.
    end do
    where (active)
      c%pair_active_cycles = c%pair_active_cycles + 1
    elsewhere
      c%pair_skipped_cycles = c%pair_skipped_cycles + 1
    end where
  end subroutine contact_count_activity

  !> The contact state of a checkpoint at the top of a step, per node held (held_node's order: the
  !> checkpoint's rows of those nodes): the forces of the last step and the nodes they act on
  !> (touched_order(s) > 0), the energy, the deepest penetration, and the sort redone at the
  !> positions of the last sort, so the later sorts, gathers and sums fall as in the uninterrupted
  !> run.
  subroutine contact_restore(c, force, touched_order, x_at_sort, last_sort, energy, max_penetration, &
                             new_gather_set)
    type(contact_t), intent(inout) :: c
    real(wp), intent(in) :: force(:, :), x_at_sort(:, :), energy, max_penetration
    integer, intent(in) :: touched_order(:)
    integer(i8), intent(in) :: last_sort
    logical, intent(out) :: new_gather_set
    integer :: s
    c%x = x_at_sort
    call sort_passes(c, last_sort, new_gather_set)
    c%force = force
    c%force_old = 0.0_wp
    c%n_touched_old = 0
    c%n_touched = 0
    c%stamp = 1
    c%mark = 0
    do s = 1, size(c%held_node)
      if (touched_order(s) == 0) cycle
      c%n_touched = c%n_touched + 1
      c%touched(c%n_touched) = s
      c%mark(s) = c%stamp
    end do
    c%energy = energy
    c%max_penetration = max_penetration
  end subroutine contact_restore

  !> After a sort (interval 0), or when passes wake or fall idle: the nodes whose positions the
  !> active passes can read before the next sort (at the positions of the last sort). Until then
  !> no node moves more than a tenth of the smallest bucket (contact_sort_due), so a slave can
  !> pass near_box only if it lay within the margin plus that movement of the master box at the
  !> sort; its nearest master node lies within the search radius plus that
  !> movement of it; and the local search reads the nodes of the segments around that master.
  !> Twice the movement is allowed, against round-off. The near slaves are also the only ones
  !> the global search needs to visit.
  subroutine choose_gather_set(c)
    type(contact_t), intent(inout) :: c
    real(wp) :: reach, margin, lower(3), upper(3), slave_lower(3), slave_upper(3), x(3)
    integer :: p, j, k
    reach = 0.2_wp * smallest_bucket(c)
    c%in_gather = .false.
    do p = 1, size(c%passes)
      if (c%passes(p)%idle) cycle
      associate (pass => c%passes(p))
      margin = pass%bucket_size + pass%t_slave + pass%t_master
      lower = pass%grid%lower - (margin + reach)
      upper = pass%grid%upper + (margin + reach)
      slave_lower = huge(1.0_wp)
      slave_upper = -huge(1.0_wp)
      pass%n_near = 0
      do j = 1, size(pass%slaves)
        x = c%x_at_sort(:, pass%slave_at(j))
        if (pass%edges) x = 0.5_wp * (x + c%x_at_sort(:, pass%slave_other_at(j)))   ! an edge: its midpoint
        if (any(x < lower) .or. any(x > upper)) cycle
        pass%n_near = pass%n_near + 1
        pass%near_slaves(pass%n_near) = j
        c%in_gather(pass%slave_at(j)) = .true.
        if (pass%edges) c%in_gather(pass%slave_other_at(j)) = .true.
        slave_lower = min(slave_lower, x)
        slave_upper = max(slave_upper, x)
      end do
      slave_lower = slave_lower - (margin + reach)
      slave_upper = slave_upper + (margin + reach)
      do j = 1, size(pass%segments, 2)
        do k = 1, 4
          x = c%x_at_sort(:, pass%segment_at(k, j))
          if (all(x >= slave_lower .and. x <= slave_upper)) then
            c%in_gather(pass%segment_at(:, j)) = .true.
            exit
          end if
        end do
      end do
      end associate
    end do
  end subroutine choose_gather_set

  pure real(wp) function smallest_bucket(c) result(smallest)
    type(contact_t), intent(in) :: c
    integer :: p
    smallest = huge(1.0_wp)
    do p = 1, size(c%passes)
      smallest = min(smallest, c%passes(p)%bucket_size)
    end do
  end function smallest_bucket

  !> A sort is due at the set interval, or (interval 0) once any contact node has moved a tenth
  !> of the smallest bucket since the last sort: moved is the largest movement over all contact
  !> nodes (contact_movement on each rank's own nodes, the largest over the ranks).
  logical function contact_sort_due(c, cycle, moved) result(due)
    type(contact_t), intent(in) :: c
    integer(i8), intent(in) :: cycle
    real(wp), intent(in) :: moved
    if (c%last_sort < 0) then
      due = .true.
    else if (c%sort_interval > 0) then
      due = cycle - c%last_sort >= c%sort_interval
    else
      due = moved > 0.1_wp * smallest_bucket(c)
    end if
  end function contact_sort_due

end module contact_interface
