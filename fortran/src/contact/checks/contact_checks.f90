!> The contact set-up's two checks on each rank's own rows (issue 19, item 5): initial
!> penetrations (issue 15: reported, and moved out where the definition asks) and parts whose
!> mid-surfaces cross at the start (issue 17: refused). Each rank tests what it holds (the slave
!> nodes of its elements, the sides of its elements) against the other part's elements near them,
!> its own and those near_elements brings from the other ranks, and the ranks agree on what one
!> rank holding the whole deck would report: the same count, the same deepest node (the lowest id
!> among the deepest), the same first crossing (the lowest element id, then its first side, then
!> the lowest element pierced). A node that several ranks hold is tested by each of them with the
!> same elements near it, so each moves it by the same push; a rank that holds it through another
!> part's element only gets the moved position through its home in the node directory
!> (block_owner), where it is also counted, once. Nothing here is sized by the global mesh. Tied
!> definitions (trait "tied") are not checked: their parts start within reach on purpose.
module contact_checks
  use mpi_f08
  use paradyn_kinds, only: wp
  use paradyn_schema, only: status_ok, status_bad_input, initial_penetration_move, contact_kind_is_self_contact, &
                           contact_kind_is_tied
  use model_deck, only: deck_t, node_row
  use integer_sort, only: distinct_ascending, sorted_position
  use domain_decomposition, only: block_owner
  use rank_exchange, only: exchange_int, exchange_real
  use deck_directory, only: block_range
  use near_elements, only: near_set_t, gather_near, box_of
  use initial_penetration, only: slave_penetrations
  use surface_overlap, only: first_crossing
  use contact_surfaces, only: capped_thickness, shortest_edge, scaled_thickness
  implicit none
  private
  public :: resolve_initial_penetrations, check_contact_overlap, held_thickness, part_rows, corners

contains

  !> Checks every contact definition, both ways, at the deck's positions; where a definition asks
  !> for it, the penetrating slave nodes get the moves (3, size(deck%node_ids): this rank's node
  !> rows) that put them onto the surface (then the check runs again on the moved positions:
  !> moving one side's nodes may leave the other's inside). Each definition with penetrations is
  !> reported on `unit` when speak (rank 0). The deck keeps its coordinates: the solver adds the
  !> moves to the start positions, so they show as initial displacements. Collective.
  !> With only: definition `only` alone, checked at its birth (contact_births: the deck's
  !> coordinates are then the positions at the birth, at time `born`, which the report names).
  subroutine resolve_initial_penetrations(deck, comm, speak, unit, moves, only, born)
    type(deck_t), intent(in) :: deck
    type(MPI_Comm), intent(in) :: comm
    logical, intent(in) :: speak
    integer, intent(in) :: unit
    real(wp), allocatable, intent(out) :: moves(:, :)
    integer, intent(in), optional :: only
    real(wp), intent(in), optional :: born
    real(wp), allocatable :: x(:, :)
    character(len=40) :: at
    integer :: k
    x = deck%coordinates
    at = ''
    if (present(born)) write (at, '(a,es10.3,a)') ' at its birth (t =', born, ' s)'
    do k = 1, deck%n_contacts
      if (present(only)) then
        if (k /= only) cycle
      else if (deck%contact_birth_time(k) > 0.0_wp) then
        cycle   ! born later: checked at its birth (contact_births), the parts may cross at the start
      end if
      if (contact_kind_is_tied(deck%contact_kind(k))) cycle   ! tied parts start within reach on purpose
      if (deck%contact_initial_penetration(k) == initial_penetration_move) then
        call check_definition(deck, comm, x, k, .true., speak, unit, 'moved onto the surface'//trim(at))
        call check_definition(deck, comm, x, k, .false., speak, unit, 'still inside after the move'//trim(at))
      else
        call check_definition(deck, comm, x, k, .false., speak, unit, 'kept as the initial gap'//trim(at))
      end if
    end do
    moves = x - deck%coordinates
  end subroutine resolve_initial_penetrations

  !> Both passes of definition k at the positions x (this rank's node rows): report the
  !> penetrating slave nodes; move them in x when asked.
  subroutine check_definition(deck, comm, x, k, move, speak, unit, what)
    type(deck_t), intent(in) :: deck
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(inout) :: x(:, :)
    integer, intent(in) :: k, unit
    logical, intent(in) :: move, speak
    character(len=*), intent(in) :: what
    integer, allocatable :: slaves(:), rows(:), at(:)
    real(wp), allocatable :: depth(:), push(:, :), slave_x(:, :)
    logical, allocatable :: moved(:)
    type(near_set_t) :: near
    integer :: side, slave_part, master_part, i, n_inside, node
    real(wp) :: reach, t_slave, t_master, deepest, where(3)
    do side = 1, 2
      slave_part = deck%contact_pairs(side, k)
      master_part = deck%contact_pairs(3 - side, k)
      ! a single-surface definition names its part twice: one pass
      if (side == 2 .and. contact_kind_is_self_contact(deck%contact_kind(k))) exit
      rows = part_rows(deck, slave_part)
      slaves = distinct_ascending(reshape(deck%connectivity(:, rows), [4 * size(rows)]))
      at = [(node_row(deck, slaves(i)), i = 1, size(slaves))]
      slave_x = x(:, at)
      t_slave = held_thickness(deck, comm, k, slave_part)
      t_master = held_thickness(deck, comm, k, master_part)
      reach = 0.5_wp * (t_slave + t_master)
      rows = part_rows(deck, master_part)
      call gather_near(comm, box_of(slave_x), reach, deck%element_ids(rows), deck%connectivity(:, rows), &
                       corners(deck, x, rows), slaves, slave_x, near)
      allocate (depth(size(slaves)), push(3, size(slaves)))
      call slave_penetrations(near%x, [(sorted_position(near%node_ids, slaves(i)), i = 1, size(slaves))], &
                              near%connectivity, t_slave, t_master, depth, push)
      call deepest_node(deck, comm, slaves, slave_x, depth, n_inside, deepest, node, where)
      if (n_inside > 0) then
        if (speak) write (unit, '(a,i0,a,i0,a,i0,a,i0,a,es10.3,a,f5.3,a,i0,a,3es11.3,a)') &
          'paradyn-engine: warning: initial penetration in /contact/pairs[', k - 1, ']: ', n_inside, &
          ' nodes of part ', slave_part - 1, ' inside the contact thickness of part ', master_part - 1, &
          ', deepest', deepest, ' m (', deepest / reach, ' of the reach (t_slave + t_master)/2) '// &
          'at node ', node - 1, ' near', where, '; '//what
        if (move) then
          allocate (moved(size(x, 2)), source=.false.)
          do i = 1, size(slaves)
            if (depth(i) > 0.0_wp) x(:, at(i)) = x(:, at(i)) + push(:, i)
            moved(at(i)) = depth(i) > 0.0_wp
          end do
          call share_moves(deck, comm, x, moved)   ! also to the ranks that hold a node by another part
          deallocate (moved)
        end if
      end if
      deallocate (depth, push)
    end do
  end subroutine check_definition

  !> Over the ranks: how many distinct slave nodes are inside (n_inside, each counted at its home),
  !> the deepest depth, its node (the lowest id among the deepest) and that node's position.
  subroutine deepest_node(deck, comm, slaves, slave_x, depth, n_inside, deepest, node, where)
    type(deck_t), intent(in) :: deck
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: slaves(:)
    real(wp), intent(in) :: slave_x(:, :), depth(:)
    integer, intent(out) :: n_inside, node
    real(wp), intent(out) :: deepest, where(3)
    integer, allocatable :: inside(:), counts(:), recv(:), recv_counts(:)
    real(wp) :: mine(2), best(2)
    integer :: n_ranks, i, mine_count, holder, rank
    call MPI_Comm_size(comm, n_ranks)
    call MPI_Comm_rank(comm, rank)
    inside = pack(slaves, depth > 0.0_wp)   ! ascending: grouped by home
    allocate (counts(n_ranks), source=0)
    do i = 1, size(inside)
      counts(block_owner(inside(i), deck%n_nodes, n_ranks) + 1) = counts(block_owner(inside(i), deck%n_nodes, &
                                                                                        n_ranks) + 1) + 1
    end do
    call exchange_int(comm, inside, counts, recv, recv_counts)
    mine_count = size(distinct_ascending(recv))
    call MPI_Allreduce(mine_count, n_inside, 1, MPI_INTEGER, MPI_SUM, comm)
    deepest = 0.0_wp
    node = 0
    where = 0.0_wp
    if (n_inside == 0) return
    mine = [-1.0_wp, 0.0_wp]
    if (size(inside) > 0) then   ! maxloc: the first, so the lowest id, among the deepest
      i = maxloc(depth, 1)
      mine = [depth(i), real(slaves(i), wp)]
    end if
    call MPI_Allreduce(mine, best, 1, MPI_2DOUBLE_PRECISION, MPI_MAXLOC, comm)   ! ties: the lower id
    deepest = best(1)
    node = nint(best(2))
    i = sorted_position(slaves, node)
    holder = n_ranks
    if (size(slaves) > 0) then
      if (slaves(i) == node) holder = rank
    end if
    call MPI_Allreduce(MPI_IN_PLACE, holder, 1, MPI_INTEGER, MPI_MIN, comm)
    if (holder == rank) where = slave_x(:, i)
    call MPI_Bcast(where, 3, MPI_DOUBLE_PRECISION, holder, comm)
  end subroutine deepest_node

  !> The moved positions to every rank that holds the node (a node of the slave part may be held by
  !> a rank through an element of another part only, and that rank moves nothing): each rank sends
  !> the node rows it moved (moved: per node row) to their homes, and each asks the homes for every
  !> node it holds and takes the new position of those moved. Copies: every holder ends with the
  !> mover's bits. Collective.
  subroutine share_moves(deck, comm, x, moved)
    type(deck_t), intent(in) :: deck
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(inout) :: x(:, :)
    logical, intent(in) :: moved(:)
    integer, allocatable :: ids(:), counts(:), recv(:), recv_counts(:)
    real(wp), allocatable :: send_x(:), recv_x(:), home_x(:, :), reply(:), answer(:)
    logical, allocatable :: home_moved(:)
    integer :: n_ranks, rank, first, n_home, i, n
    call MPI_Comm_size(comm, n_ranks)
    call MPI_Comm_rank(comm, rank)
    call block_range(deck%n_nodes, rank, n_ranks, first, n_home)
    allocate (home_x(3, n_home), home_moved(n_home))
    home_moved = .false.
    ids = pack(deck%node_ids, moved)   ! ascending: grouped by home
    send_x = reshape(x(:, pack([(i, i = 1, size(moved))], moved)), [3 * size(ids)])
    call exchange_int(comm, ids, homes(ids), recv, recv_counts)
    call exchange_real(comm, send_x, 3 * homes(ids), recv_x)
    do i = 1, size(recv)
      n = recv(i) - first + 1
      home_x(:, n) = recv_x(3 * i - 2:3 * i)   ! every holder that moved it sent the same bits
      home_moved(n) = .true.
    end do
    call exchange_int(comm, deck%node_ids, homes(deck%node_ids), recv, recv_counts)
    allocate (reply(4 * size(recv)))
    do i = 1, size(recv)
      n = recv(i) - first + 1
      reply(4 * i - 3:4 * i) = [merge(1.0_wp, 0.0_wp, home_moved(n)), home_x(:, n)]
    end do
    call exchange_real(comm, reply, 4 * recv_counts, answer)
    do i = 1, size(deck%node_ids)
      if (answer(4 * i - 3) > 0.0_wp) x(:, i) = answer(4 * i - 2:4 * i)
    end do
  contains
    !> How many of the ascending ids go to each home.
    function homes(list) result(c)
      integer, intent(in) :: list(:)
      integer :: c(n_ranks), j
      c = 0
      do j = 1, size(list)
        c(block_owner(list(j), deck%n_nodes, n_ranks) + 1) = c(block_owner(list(j), deck%n_nodes, n_ranks) + 1) + 1
      end do
    end function homes
  end subroutine share_moves

  !> Refuses a contact pair whose mid-surfaces cross at the start (surface_overlap): its nodes are
  !> past the surface they should meet, and contact would never engage (issue 17). Each rank tests
  !> the sides of its elements of one part against the other part's elements near them; the first
  !> crossing in element order over all ranks is the one reported, as one rank testing them all
  !> would. status: left as it is unless it is status_ok and a pair crosses. Collective.
  !> With only: definition `only` alone, checked at its birth at time `born` (contact_births).
  subroutine check_contact_overlap(deck, comm, status, message, only, born)
    type(deck_t), intent(in) :: deck
    type(MPI_Comm), intent(in) :: comm
    integer, intent(inout) :: status
    character(len=*), intent(inout) :: message
    integer, intent(in), optional :: only
    real(wp), intent(in), optional :: born
    character(len=40) :: at
    character(len=60) :: hint
    integer, allocatable :: a(:), b(:), a_nodes(:), local(:, :)
    real(wp), allocatable :: a_x(:, :)
    type(near_set_t) :: near
    integer :: j, k, side, element_a, element_b, part(2), rank, n_ranks, found, first_found, holder
    real(wp) :: point(3)
    call MPI_Comm_rank(comm, rank)
    call MPI_Comm_size(comm, n_ranks)
    at = 'at the start'
    hint = ''
    if (present(born)) then
      write (at, '(a,es10.3,a)') 'at its birth (t =', born, ' s)'
      hint = ' at that time, or give the contact a later birth_time'
    end if
    do k = 1, deck%n_contacts
      if (present(only)) then
        if (k /= only) cycle
      else if (deck%contact_birth_time(k) > 0.0_wp) then
        cycle   ! born later: checked at its birth (contact_births), the parts may cross at the start
      end if
      if (contact_kind_is_tied(deck%contact_kind(k))) cycle   ! tied parts may meet as they like
      do side = 1, 2   ! a small element of one part may poke through the middle of a large one of the other
        part = deck%contact_pairs(:, k)
        if (side == 2) part = part([2, 1])
        a = part_rows(deck, part(1))
        b = part_rows(deck, part(2))
        a_nodes = distinct_ascending(reshape(deck%connectivity(:, a), [4 * size(a)]))
        a_x = deck%coordinates(:, [(node_row(deck, a_nodes(j)), j = 1, size(a_nodes))])
        call gather_near(comm, box_of(a_x), 0.0_wp, deck%element_ids(b), deck%connectivity(:, b), &
                         corners(deck, deck%coordinates, b), a_nodes, a_x, near)
        local = reshape([(sorted_position(near%node_ids, deck%connectivity(mod(j - 1, 4) + 1, a((j - 1) / 4 + 1))), &
                          j = 1, 4 * size(a))], [4, size(a)])
        call first_crossing(near%x, local, near%connectivity, element_a, element_b, point)
        found = huge(1)
        if (element_a > 0) found = deck%element_ids(a(element_a))
        call MPI_Allreduce(found, first_found, 1, MPI_INTEGER, MPI_MIN, comm)
        if (first_found == huge(1)) cycle
        ! the rank holding the first crossing's element gives its point
        call MPI_Allreduce(merge(rank, n_ranks, found == first_found), holder, 1, MPI_INTEGER, MPI_MIN, comm)
        call MPI_Bcast(point, 3, MPI_DOUBLE_PRECISION, holder, comm)
        if (status /= status_ok) return
        status = status_bad_input
        write (message, '(a,i0,a,i0,a,3es11.3,a)') 'the parts of /contact/pairs[', k - 1, '] cross '//trim(at)// &
          ' (part ', part(1) - 1, ' passes through the other near', point, '); contact would never engage: move the '// &
          'parts apart so that their surfaces do not intersect'//trim(hint)
        return
      end do
    end do
  end subroutine check_contact_overlap

  !> The rows of this rank's elements of a part, ascending.
  pure function part_rows(deck, part) result(rows)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: part
    integer, allocatable :: rows(:)
    integer :: e
    rows = pack([(e, e = 1, size(deck%element_ids))], deck%element_part == part)
  end function part_rows

  !> The corner positions (3, 4, n) of the element rows `rows` at the node-row positions x.
  pure function corners(deck, x, rows) result(c)
    type(deck_t), intent(in) :: deck
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: rows(:)
    real(wp) :: c(3, 4, size(rows))
    integer :: e, j
    do e = 1, size(rows)
      do j = 1, 4
        c(:, j, e) = x(:, node_row(deck, deck%connectivity(j, rows(e))))
      end do
    end do
  end function corners

  !> contact_surfaces' contact_thickness over the ranks' rows: the scaled shell thickness, capped at
  !> self_thickness_cap times the part's shortest element edge (the least over the ranks, exact in
  !> any order) for a single-surface definition. Collective for a single-surface definition.
  real(wp) function held_thickness(deck, comm, definition, part) result(t)
    type(deck_t), intent(in) :: deck
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: definition, part
    integer :: e, k
    real(wp) :: shortest
    t = scaled_thickness(deck, definition, part)
    if (.not. contact_kind_is_self_contact(deck%contact_kind(definition))) return
    shortest = shortest_edge(deck%coordinates, &
                             reshape([((node_row(deck, deck%connectivity(k, e)), k = 1, 4), e = 1, size(deck%element_ids))], &
                                     [4, size(deck%element_ids)]), deck%element_part, part)
    call MPI_Allreduce(MPI_IN_PLACE, shortest, 1, MPI_DOUBLE_PRECISION, MPI_MIN, comm)
    t = capped_thickness(t, shortest)
  end function held_thickness

end module contact_checks
