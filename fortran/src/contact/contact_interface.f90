!> Contact between pairs of parts: set-up from the deck and the work of one step, around the pure
!> kernels of contact_buckets (global search) and contact_search (local search, penalty force).
!>
!> Shells are two-sided and thick: the contact surface lies half a thickness off each
!> mid-surface, with edges and corners rounded by that half thickness, so a node meets the
!> faceted surface at its true distance (a node beyond a facet's edge is not measured against the
!> facet's extended plane, which on a faceted cylinder would make contact start early).
!>
!> Each pair gives two passes, each body slave to the other's segments: both every step
!> (passes = 2, the default) or one per step, alternating as in the paper (passes = 1). The
!> passes of a step run together, in the paper's two parallel stages (docs/theory.md, parallel
!> contact), so a step shares candidates and records once whatever the number of passes:
!>   1. global search (contact_global_search): the slaves are dealt node-wise cyclically to the
!>      ranks and, inside a rank, to the threads; each slave near the master box gets its nearest
!>      master node, and the pairs (slave, nearest master) found are this rank's candidates;
!>   2. the caller shares the candidates between ranks; contact_candidates puts them in
!>      ascending slave order and gives each rank one contiguous block of equal size (within
!>      one), and contact_local_search finds the segment, the closest point and the penalty force
!>      of each candidate of the block, threads sharing the block.
!> Every candidate writes its own record (its force and the forces on the 4 master nodes); the
!> records are then summed in candidate order, which is pass order and slave order within a
!> pass, so the result does not depend on the number of threads. The contact nodes' positions are gathered on every rank
!> (halo_exchange): all of them at a sort, and between sorts only those that can come into
!> contact before the next one (choose_gather_set). The records are shared by value and every
!> rank sums all of them, so the result does not depend on the number of ranks either. Only the
!> nodes touched in the last two steps carry a force, so only they are cleared, applied and
!> summed into the energy. No MPI here.
module contact_interface
  use paradyn_kinds, only: wp, ip, i8
  use model_deck, only: deck_t
  use contact_buckets, only: bucket_grid_t, bucket_grid_build, nearest_master_node
  use contact_search, only: segment_candidates, penalty_force, candidate_block, candidates_in_slave_order
  use contact_pass, only: contact_pass_t
  use contact_kind, only: contact_kind_holder_t
  use contact_factory, only: contact_kind_from_name
  implicit none
  private
  public :: contact_t, contact_setup
  public :: contact_begin, contact_global_search, contact_candidates
  public :: contact_local_search, contact_sum, contact_end, contact_sort_due, contact_movement
  public :: contact_restore
  public :: clock_seconds

  !> The wall clock the phases are timed with (the solver passes MPI_Wtime's wrapper).
  abstract interface
    function clock_seconds() result(seconds)
      import :: wp
      real(wp) :: seconds
    end function clock_seconds
  end interface

  !> Below this slip speed friction falls linearly to zero (a viscous regularisation of stick
  !> that needs no history per contact; a body at rest on a slope creeps at most this fast).
  real(wp), parameter :: stick_speed = 1.0e-3_wp  ! m/s
  !> The penalty spring of a contact never exceeds this fraction of m / dt^2, m the lightest node
  !> of the slave and its segment: the contact frequency then stays below 0.63 / dt, so the
  !> contact cannot make the central-difference step unstable however stiff the penalty or light
  !> the node (docs/theory.md; LS-DYNA's soft-constraint stiffness has the same m / dt^2 form).
  real(wp), parameter :: stable_spring_fraction = 0.25_wp
  !> The kind of every contact definition of a deck of version 1 (the schema's only kind so far)
  character(len=*), parameter :: contact_kind_name = 'node_to_segment'


  type :: contact_t
    integer :: n_nodes = 0                     !< nodes of all parts in contact
    integer, allocatable :: global_node(:)     !< their global ids, ascending
    real(wp), allocatable :: x(:, :), v(:, :)  !< gathered positions and velocities
    real(wp), allocatable :: mass(:)           !< lumped mass of each contact node
    real(wp) :: time_step = 0.0_wp             !< the solver's step, for the stability cap
    real(wp), allocatable :: force(:, :), force_old(:, :)  !< contact force per contact node
    ! the contact nodes that got a record this step and last step, in the order of the sum (the
    ! same on every rank): only their forces are nonzero, so only they are cleared, applied and
    ! enter the energy; mark(j) == stamp flags the members of touched
    integer, allocatable :: touched(:), touched_old(:), mark(:)
    integer :: n_touched = 0, n_touched_old = 0, stamp = 0
    real(wp), allocatable :: x_at_sort(:, :)   !< positions at the last bucket sort
    ! the nodes whose positions the contact can read before the next sort (all of them with a
    ! fixed sort interval); the caller gathers only these between sorts once gather_subset is set
    logical, allocatable :: in_gather(:)
    logical :: gather_subset = .false.
    logical :: gather_all = .false.             !< never gather a subset (to check that it changes nothing)
    type(contact_pass_t), allocatable :: passes(:)
    ! candidates of the step's passes: n_own found here, n_all shared by every rank (the caller
    ! fills all_pairs), n_candidates in pass order and, within a pass, slave order; pairs are
    ! (slave index, master index, pass)
    integer, allocatable :: nearest(:)          !< workspace, one per slave of all passes
    integer, allocatable :: own_pairs(:, :), all_pairs(:, :), candidates(:, :)  !< (3, n)
    integer, allocatable :: pass_pairs(:, :)    !< (2, n) workspace: one pass's shared pairs
    integer :: n_own = 0, n_all = 0, n_candidates = 0
    integer :: first = 1, last = 0              !< this rank's block of the candidates
    ! counts over the run: sorts, passes run, candidates (all ranks), local searches on this rank
    integer(i8) :: n_sorts = 0, n_pass_steps = 0, candidates_total = 0, candidates_searched = 0
    ! per-candidate records, reused every step
    integer, allocatable :: record_nodes(:, :) !< (5, n) slave then the 4 master nodes, 0 = none
    real(wp), allocatable :: record_force(:, :, :)  !< (3, 5, n)
    real(wp), allocatable :: record_penetration(:)  !< (n)
    integer :: rank = 0, n_ranks = 1               !< this rank's share of the slaves
    integer :: last_sort = -huge(1), sort_interval = 0
    real(wp) :: energy = 0.0_wp, max_penetration = 0.0_wp
    real(wp) :: time_sort = 0, time_search = 0, time_force = 0
  end type contact_t

contains

  subroutine contact_setup(deck, c)
    type(deck_t), intent(in) :: deck
    type(contact_t), intent(out) :: c
    logical, allocatable :: in_contact(:)
    integer, allocatable :: contact_id(:)
    integer :: i, k, p, n_max, e, n_passes
    type(contact_kind_holder_t), allocatable :: kinds(:)
    allocate (in_contact(deck%n_nodes), source=.false.)
    do e = 1, deck%n_elements
      if (any(deck%contact_pairs == deck%element_part(e))) in_contact(deck%connectivity(:, e)) = .true.
    end do
    c%global_node = pack([(i, i = 1, deck%n_nodes)], in_contact)
    c%n_nodes = size(c%global_node)
    allocate (contact_id(deck%n_nodes), source=0)
    contact_id(c%global_node) = [(i, i = 1, c%n_nodes)]
    allocate (c%x(3, c%n_nodes), c%v(3, c%n_nodes), c%force(3, c%n_nodes), c%force_old(3, c%n_nodes), &
              c%x_at_sort(3, c%n_nodes), source=0.0_wp)
    c%sort_interval = deck%contact_sort_interval
    ! each definition's passes, one after the other, from its member of the contact family
    allocate (kinds(deck%n_contacts))
    n_passes = 0
    do k = 1, deck%n_contacts
      call contact_kind_from_name(contact_kind_name, kinds(k)%kind)
      n_passes = n_passes + kinds(k)%kind%pass_count()
    end do
    allocate (c%passes(n_passes))
    n_passes = 0
    do k = 1, deck%n_contacts
      p = kinds(k)%kind%pass_count()
      call kinds(k)%kind%make_passes(deck, k, contact_id, c%n_nodes, c%passes(n_passes + 1:n_passes + p))
      n_passes = n_passes + p
    end do
    n_max = 1 + sum([(size(c%passes(p)%slaves), p = 1, n_passes)])   ! slaves of all passes together
    allocate (c%record_nodes(5, n_max), source=0)
    allocate (c%record_force(3, 5, n_max), c%record_penetration(n_max), source=0.0_wp)
    allocate (c%nearest(n_max), c%own_pairs(3, n_max), c%all_pairs(3, n_max), c%candidates(3, n_max), &
              c%pass_pairs(2, n_max), source=0)
    allocate (c%touched(c%n_nodes), c%touched_old(c%n_nodes), c%mark(c%n_nodes), source=0)
    allocate (c%in_gather(c%n_nodes), source=.true.)
  end subroutine contact_setup

  !> Start a step: keep the last forces, redo the bucket sorts if sort (contact_sort_due; the
  !> positions of all contact nodes are then current). Only the nodes touched in the last two
  !> steps hold nonzero forces, so only they are copied and cleared. With sort interval 0, a sort
  !> also chooses the nodes to gather until the next sort (new_gather_set).
  subroutine contact_begin(c, cycle, sort, clock, new_gather_set)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: cycle
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
    t0 = clock()
    new_gather_set = .false.
    if (sort) call sort_passes(c, cycle, new_gather_set)
    c%time_sort = c%time_sort + clock() - t0
  end subroutine contact_begin

  !> The bucket sort of every pass at the current positions, and (automatic sorting) the nodes to
  !> gather until the next sort: new_gather_set says the caller must take the new set.
  subroutine sort_passes(c, cycle, new_gather_set)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: cycle
    logical, intent(out) :: new_gather_set
    integer :: p
    do p = 1, size(c%passes)
      c%passes(p)%x_sorted = c%x(:, c%passes(p)%masters)
      call bucket_grid_build(int(size(c%passes(p)%masters), ip), c%passes(p)%x_sorted, &
                             c%passes(p)%bucket_size, c%passes(p)%grid)
    end do
    c%x_at_sort = c%x
    c%last_sort = cycle
    c%n_sorts = c%n_sorts + 1
    new_gather_set = c%sort_interval == 0 .and. .not. c%gather_all
    if (new_gather_set) then
      call choose_gather_set(c)
      c%gather_subset = .true.
    end if
  end subroutine sort_passes

  !> The contact state of a checkpoint at the top of a step: the forces of the last step and the
  !> nodes they act on in the order of the sum (touched_order(j) = k > 0 for the k-th touched
  !> node), the energy, the deepest penetration, and the sort redone at the positions of the last
  !> sort, so the later sorts, gathers and sums fall as in the uninterrupted run.
  subroutine contact_restore(c, force, touched_order, x_at_sort, last_sort, energy, max_penetration, &
                             new_gather_set)
    type(contact_t), intent(inout) :: c
    real(wp), intent(in) :: force(:, :), x_at_sort(:, :), energy, max_penetration
    integer, intent(in) :: touched_order(:), last_sort
    logical, intent(out) :: new_gather_set
    integer :: j
    c%x = x_at_sort
    call sort_passes(c, last_sort, new_gather_set)
    c%force = force
    c%force_old = 0.0_wp
    c%n_touched_old = 0
    c%n_touched = count(touched_order > 0)
    c%stamp = 1
    c%mark = 0
    do j = 1, c%n_nodes
      if (touched_order(j) == 0) cycle
      c%touched(touched_order(j)) = j
      c%mark(j) = c%stamp
    end do
    c%energy = energy
    c%max_penetration = max_penetration
  end subroutine contact_restore

  !> After a sort (interval 0): the nodes whose positions the contact can read before the next
  !> sort. Until then no node moves more than a tenth of the smallest bucket (contact_sort_due),
  !> so a slave can pass near_box only if it lay within the margin plus that movement of the
  !> master box at the sort; its nearest master node lies within the search radius plus that
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
      associate (pass => c%passes(p))
      margin = pass%bucket_size + pass%t_slave + pass%t_master
      lower = pass%grid%lower - (margin + reach)
      upper = pass%grid%upper + (margin + reach)
      slave_lower = huge(1.0_wp)
      slave_upper = -huge(1.0_wp)
      pass%n_near = 0
      do j = 1, size(pass%slaves)
        x = c%x(:, pass%slaves(j))
        if (any(x < lower) .or. any(x > upper)) cycle
        pass%n_near = pass%n_near + 1
        pass%near_slaves(pass%n_near) = j
        c%in_gather(pass%slaves(j)) = .true.
        slave_lower = min(slave_lower, x)
        slave_upper = max(slave_upper, x)
      end do
      slave_lower = slave_lower - (margin + reach)
      slave_upper = slave_upper + (margin + reach)
      do j = 1, size(pass%segments, 2)
        do k = 1, 4
          x = c%x(:, pass%segments(k, j))
          if (all(x >= slave_lower .and. x <= slave_upper)) then
            c%in_gather(pass%segments(:, j)) = .true.
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

  !> Pass p runs this cycle: always, or every other cycle with the paper's swap.
  pure logical function contact_pass_active(c, p, cycle)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: p, cycle
    contact_pass_active = c%passes(p)%every_cycle .or. modulo(cycle + c%passes(p)%swap_index, 2) == 1
  end function contact_pass_active

  !> Add the records of the step (complete on this rank: the caller has shared them between
  !> ranks) to the contact forces, in candidate order (pass, then slave), the same for any layout.
  subroutine contact_sum(c, clock)
    type(contact_t), intent(inout) :: c
    procedure(clock_seconds) :: clock
    integer :: j, k, node
    real(wp) :: t0
    t0 = clock()
    do j = 1, c%n_candidates
      if (c%record_nodes(1, j) == 0) cycle
      c%max_penetration = max(c%max_penetration, c%record_penetration(j))
      do k = 1, 5
        node = c%record_nodes(k, j)
        if (c%mark(node) /= c%stamp) then
          c%mark(node) = c%stamp
          c%n_touched = c%n_touched + 1
          c%touched(c%n_touched) = node
        end if
        c%force(:, node) = c%force(:, node) + c%record_force(:, k, j)
      end do
    end do
    c%time_force = c%time_force + clock() - t0
  end subroutine contact_sum

  !> End a step: the contact energy advances by minus the work of the mean contact force over
  !> the last step dt (the velocities are those of that step). Only nodes touched in this step
  !> or the last have a force; they are summed in the order of the lists, which is the same on
  !> every rank and for any number of threads.
  subroutine contact_end(c, cycle, dt)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: cycle
    real(wp), intent(in) :: dt
    integer :: i, j
    real(wp) :: work
    if (cycle == 0) return
    work = 0.0_wp
    do i = 1, c%n_touched
      j = c%touched(i)
      work = work + dot_product(c%v(:, j), c%force_old(:, j) + c%force(:, j))
    end do
    do i = 1, c%n_touched_old
      j = c%touched_old(i)
      if (c%mark(j) == c%stamp) cycle   ! in both lists: counted above
      work = work + dot_product(c%v(:, j), c%force_old(:, j))
    end do
    c%energy = c%energy - 0.5_wp * dt * work
  end subroutine contact_end

  !> A sort is due at the set interval, or (interval 0) once any contact node has moved a tenth
  !> of the smallest bucket since the last sort: moved is the largest movement over all contact
  !> nodes (contact_movement on each rank's own nodes, the largest over the ranks).
  logical function contact_sort_due(c, cycle, moved) result(due)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: cycle
    real(wp), intent(in) :: moved
    if (c%last_sort < 0) then
      due = .true.
    else if (c%sort_interval > 0) then
      due = cycle - c%last_sort >= c%sort_interval
    else
      due = moved > 0.1_wp * smallest_bucket(c)
    end if
  end function contact_sort_due

  !> The largest distance that contact nodes have moved since the last sort: the given nodes
  !> (members, at columns local(members) of x), or without them every contact node at c%x. A
  !> maximum is exact in any order, so the threads and ranks may share it; squared distances
  !> and one square root at the end (norm2's scaling against overflow costs more than the rest).
  subroutine contact_movement(c, moved, clock, members, local, x)
    type(contact_t), intent(inout) :: c
    real(wp), intent(out) :: moved
    procedure(clock_seconds) :: clock
    integer, intent(in), optional :: members(:), local(:)
    real(wp), intent(in), optional :: x(:, :)
    real(wp) :: t0
    integer :: i, j, k
    t0 = clock()
    moved = 0.0_wp
    if (present(members) .and. present(local) .and. present(x)) then
      !$omp parallel do schedule(static) private(j, k) reduction(max:moved)
      do i = 1, size(members)
        k = members(i)
        j = local(k)
        moved = max(moved, (x(1, j) - c%x_at_sort(1, k))**2 + (x(2, j) - c%x_at_sort(2, k))**2 &
                           + (x(3, j) - c%x_at_sort(3, k))**2)
      end do
      !$omp end parallel do
    else if (c%sort_interval == 0 .and. c%last_sort >= 0) then   ! else contact_sort_due does not ask
      !$omp parallel do schedule(static) reduction(max:moved)
      do k = 1, c%n_nodes
        moved = max(moved, (c%x(1, k) - c%x_at_sort(1, k))**2 + (c%x(2, k) - c%x_at_sort(2, k))**2 &
                           + (c%x(3, k) - c%x_at_sort(3, k))**2)
      end do
      !$omp end parallel do
    end if
    moved = sqrt(moved)
    c%time_sort = c%time_sort + clock() - t0
  end subroutine contact_movement

  !> Stage 1, the global search, for every pass active this cycle: this rank's share of the
  !> slaves that can be near (near_slaves; all slaves with a fixed sort interval), dealt
  !> node-wise cyclically to the ranks (the k-th to rank mod(k - 1, n_ranks)) and, one at a time,
  !> to the threads (schedule(static, 1)), as in the paper; the passes' shares run as one loop. A
  !> slave near the master box gets its nearest master node; the pairs (place in near_slaves,
  !> nearest master, pass) found are own_pairs(:, 1:n_own), by pass and ascending within one.
  subroutine contact_global_search(c, cycle, clock)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: cycle
    procedure(clock_seconds) :: clock
    integer :: i, j, p, found, total, n_mine(size(c%passes)), offset(size(c%passes) + 1)
    real(wp) :: x(3), t0
    t0 = clock()
    offset(1) = 0
    do p = 1, size(c%passes)
      n_mine(p) = 0
      if (contact_pass_active(c, p, cycle)) &
        n_mine(p) = max(0, (c%passes(p)%n_near - c%rank + c%n_ranks - 1) / c%n_ranks)
      offset(p + 1) = offset(p) + n_mine(p)
    end do
    total = offset(size(offset))
    ! cleared first, so the threads write only the few slaves near the box (writes to
    ! neighbouring slaves from different threads would fight over their cache line)
    c%nearest(1:total) = 0
    !$omp parallel do schedule(static, 1) default(shared) private(i, j, p, x, found)
    do i = 1, total
      p = pass_of(offset, i)
      associate (pass => c%passes(p))
      j = pass%near_slaves(c%rank + 1 + (i - offset(p) - 1) * c%n_ranks)
      x = c%x(:, pass%slaves(j))
      if (near_box(x, pass)) then
        found = nearest_master_node(pass%grid, pass%x_sorted, x, &
                                    max_distance=pass%bucket_size + pass%t_slave + pass%t_master)
        if (found > 0) c%nearest(i) = found
      end if
      end associate
    end do
    !$omp end parallel do
    c%n_own = 0
    do p = 1, size(c%passes)
      do i = offset(p) + 1, offset(p + 1)
        if (c%nearest(i) == 0) cycle
        c%n_own = c%n_own + 1
        c%own_pairs(:, c%n_own) = [c%rank + 1 + (i - offset(p) - 1) * c%n_ranks, c%nearest(i), p]
      end do
    end do
    c%time_search = c%time_search + clock() - t0
  end subroutine contact_global_search

  !> The pass whose share of the global search holds entry i (offset: where each pass starts).
  pure integer function pass_of(offset, i) result(p)
    integer, intent(in) :: offset(:), i
    p = 1
    do while (i > offset(p + 1))
      p = p + 1
    end do
  end function pass_of

  !> The candidates of the step's passes, pass after pass and in ascending slave order within a
  !> pass, and this rank's block of them. With one rank they are own_pairs; with more, the
  !> caller has gathered every rank's pairs in all_pairs(:, 1:n_all) (halo_exchange's
  !> share_contact_candidates). The pairs name a slave by its place in near_slaves, which is
  !> ascending, so ordering costs O(n_near) per pass, not O(n_slaves).
  subroutine contact_candidates(c, cycle, clock)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: cycle
    procedure(clock_seconds) :: clock
    real(wp) :: t0
    integer :: k, p, n_pass, n_found, first
    t0 = clock()
    if (c%n_ranks == 1) then
      c%n_candidates = c%n_own
      c%candidates(:, 1:c%n_own) = c%own_pairs(:, 1:c%n_own)
    else
      c%n_candidates = 0
      do p = 1, size(c%passes)
        if (.not. contact_pass_active(c, p, cycle)) cycle
        n_pass = 0
        do k = 1, c%n_all
          if (c%all_pairs(3, k) /= p) cycle
          n_pass = n_pass + 1
          c%pass_pairs(:, n_pass) = c%all_pairs(1:2, k)
        end do
        first = c%n_candidates + 1
        call candidates_in_slave_order(int(c%passes(p)%n_near, ip), int(n_pass, ip), c%pass_pairs, &
                                       c%nearest, n_found, c%candidates(1:2, first:))
        c%candidates(3, first:first + n_found - 1) = p
        c%n_candidates = c%n_candidates + n_found
      end do
    end if
    do k = 1, c%n_candidates
      c%candidates(1, k) = c%passes(c%candidates(3, k))%near_slaves(c%candidates(1, k))
    end do
    call candidate_block(int(c%n_candidates, ip), int(c%n_ranks, ip), int(c%rank, ip), c%first, c%last)
    do p = 1, size(c%passes)
      if (contact_pass_active(c, p, cycle)) c%n_pass_steps = c%n_pass_steps + 1
    end do
    c%candidates_total = c%candidates_total + c%n_candidates
    c%candidates_searched = c%candidates_searched + max(0, c%last - c%first + 1)
    c%time_search = c%time_search + clock() - t0
  end subroutine contact_candidates

  !> Stage 2 on this rank's block of the candidates: the master segment around the nearest
  !> master node, the closest point on it and the penalty force. The candidates of the block
  !> cost about the same, and schedule(static, 1) deals them cyclically to the threads (measured
  !> against static and dynamic chunks: docs/performance.md). Every candidate outside the block
  !> gets an empty record, to be filled by the sharing of records between ranks.
  subroutine contact_local_search(c, clock)
    type(contact_t), intent(inout) :: c
    procedure(clock_seconds) :: clock
    integer :: k, node, segment
    real(wp) :: x(3), xi, eta, xc(3), normal(3), xseg(3, 4), vseg(3, 4), f_slave(3), f_master(3, 4)
    real(wp) :: penetration, t0, stiffness
    logical :: touching
    t0 = clock()
    c%record_nodes(1, 1:c%first - 1) = 0
    c%record_nodes(1, c%last + 1:c%n_candidates) = 0
    !$omp parallel do schedule(static, 1) default(shared) &
    !$omp private(k, node, segment, x, xi, eta, xc, normal, xseg, vseg, f_slave, f_master, &
    !$omp penetration, touching, stiffness)
    do k = c%first, c%last
      c%record_nodes(:, k) = 0
      associate (pass => c%passes(c%candidates(3, k)))
      node = pass%slaves(c%candidates(1, k))
      x = c%x(:, node)
      call segment_candidates(x, int(pass%masters(c%candidates(2, k)), ip), int(c%n_nodes, ip), c%x, &
                              int(size(pass%segments, 2), ip), pass%segments, pass%segment_start, &
                              pass%segment_list, segment, xi, eta, xc, normal)
      if (segment > 0) then
        xseg = c%x(:, pass%segments(:, segment))
        vseg = c%v(:, pass%segments(:, segment))
        stiffness = min(pass%stiffness(segment), stable_spring_fraction / c%time_step**2 &
                        * min(c%mass(node), minval(c%mass(pass%segments(:, segment)))))
        call penalty_force(x, pass%t_slave, xseg, pass%t_master, stiffness, f_slave, &
                           f_master, penetration, touching, v_slave=c%v(:, node), v_master=vseg, &
                           mu_static=pass%mu_static, mu_dynamic=pass%mu_dynamic, decay=pass%decay, &
                           v_slip=stick_speed, rounded_edges=.true.)
        if (touching) then
          c%record_penetration(k) = penetration
          c%record_nodes(1, k) = node
          c%record_nodes(2:5, k) = pass%segments(:, segment)
          c%record_force(:, 1, k) = f_slave
          c%record_force(:, 2:5, k) = f_master
        end if
      end if
      end associate
    end do
    !$omp end parallel do
    c%time_force = c%time_force + clock() - t0
  end subroutine contact_local_search

  !> Cheap rejection: a slave farther than a bucket from the master nodes' sorted bounding box
  !> cannot touch (an idle pair costs one box test per slave).
  pure logical function near_box(p, pass)
    real(wp), intent(in) :: p(3)
    type(contact_pass_t), intent(in) :: pass
    real(wp) :: margin
    margin = pass%bucket_size + pass%t_slave + pass%t_master
    near_box = all(p >= pass%grid%lower - margin .and. p <= pass%grid%upper + margin)
  end function near_box

end module contact_interface
