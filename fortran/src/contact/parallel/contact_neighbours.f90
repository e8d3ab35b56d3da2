!> Local contact between ranks (docs/theory.md, "Parallel contact and determinism"): each rank
!> searches the slaves it owns against the masters it holds, its domain's and the ghosts near its
!> slaves, and sends each record to the ranks whose domains hold one of its nodes. Three exchanges:
!> neighbours_refresh (at a sort, after a restart, or once a node has moved a tenth of the smallest
!> bucket since the last one: every rank's box of its own slaves per pass, one small allgather,
!> then the ghosts, point to point in a sparse exchange), neighbours_update (every other step: the
!> same ghosts from the same ranks) and the records' (contact_record_routes, every step: each
!> record by value to the holders of its five nodes; the energy and the definitions' forces are
!> exact sums that every rank takes part in, contact_parallel). Every rank orders the records it has by pass and slave,
!> the order of the serial sum, so each node's force is bitwise the serial one. Which ranks hold a
!> node of this domain comes from the halo (the neighbours its corners go to), and a ghost's
!> holders come with it. The contact state's per-node arrays hold this domain's contact nodes and
!> the ghosts, renumbered at each refresh (contact_slots); the passes hold this rank's slaves and
!> segments and the ghost segments, which travel with the ghosts (contact_ghost_segments); the
!> passes and the lists here still name nodes by contact-node index (docs/performance.md).
module contact_neighbours
  use mpi_f08
  use paradyn_kinds, only: wp, i8
  use domain_decomposition, only: domain_t, local_element
  use integer_sort, only: merge_sort_ascending, sorted_position, distinct_ascending
  use traffic_counter, only: traffic_t, count_messages, count_allgather
  use contact_sparse, only: sparse_exchange
  use contact_interface, only: contact_t
  use contact_slots, only: contact_hold, slot_of, contact_pass_slots, contact_pass_slots_moved
  use contact_ghost_segments, only: segment_row_width, segment_row, hold_ghost_segments
  implicit none
  private
  public :: neighbours_t, neighbours_setup, neighbours_refresh, neighbours_update, in_domain

  !> Lists of contact nodes per rank (CSR): node(start(i) : start(i + 1) - 1) go to or come from
  !> rank(i); at: where each lies here (sent: its local column; received: its slot)
  type :: rank_lists_t
    integer, allocatable :: rank(:), start(:), node(:), at(:)
  end type rank_lists_t

  type :: neighbours_t
    type(MPI_Comm) :: comm
    integer :: rank = 0, n_ranks = 1, round = 0
    integer, allocatable :: domain_node(:), domain_local(:)   !< contact nodes of this domain, their local columns
    integer, allocatable :: owned_node(:)                     !< contact nodes this rank owns, ascending
    real(wp), allocatable :: x_at_refresh(:, :)               !< their positions at the last refresh
    ! the ranks whose domains hold each contact node of this domain (domain_node's order) and each
    ! ghost (ghost_node: the ghosts not of this domain, ascending), ascending (CSR)
    integer, allocatable :: holder_start(:), holder(:)
    integer, allocatable :: ghost_node(:), ghost_holder_start(:), ghost_holder(:)
    type(rank_lists_t) :: send, recv                          !< the ghosts, from the last refresh
    integer, allocatable :: own_near(:)                       !< the slots of own segments' nodes near own slaves
    integer, allocatable :: mark(:), slot(:)                  !< workspace per held slot, per rank
    integer :: stamp = 0
    logical :: refresh_pending = .true.                       !< at the start and after a restore
    ! the ghost segments' rows of the last refresh: a refresh that brings the same keeps the
    ! passes' lists and moves their slots (rebuilding them is a search per entry)
    real(wp), allocatable :: segment_rows_before(:, :)
  end type neighbours_t

  !> node, position at the sort, position, velocity, mass, number of holders (the holders follow)
  integer, parameter :: ghost_width = 12
  integer, parameter :: update_tag = 710

contains

  !> contact_of(ln): the contact-node id of local node ln (0: not a contact node). No communication.
  subroutine neighbours_setup(nb, dom, comm, contact_of)
    type(neighbours_t), intent(out) :: nb
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: contact_of(:)
    integer :: k
    nb%comm = comm
    nb%rank = dom%rank
    nb%n_ranks = dom%n_ranks
    nb%domain_node = pack(contact_of, contact_of > 0)
    nb%domain_local = pack([(k, k = 1, dom%n_nodes)], contact_of > 0)
    nb%owned_node = pack(contact_of, contact_of > 0 .and. dom%node_owned == 1)
    allocate (nb%x_at_refresh(3, size(nb%owned_node)), source=0.0_wp)
    call domain_holders(nb, dom)
    allocate (nb%mark(0))
    allocate (nb%slot(0:nb%n_ranks - 1), source=0)
  end subroutine neighbours_setup

  !> The ranks whose domains hold each contact node of this domain: this rank and the neighbours
  !> that its corners at the node go to (halo_exchange sends every corner at a shared node to each
  !> other rank whose elements touch it), ascending.
  subroutine domain_holders(nb, dom)
    type(neighbours_t), intent(inout) :: nb
    type(domain_t), intent(in) :: dom
    integer, allocatable :: place(:), last(:), counts(:), fill(:)
    integer :: n, i, k, s, round
    n = size(nb%domain_node)
    allocate (place(dom%n_nodes), source=0)
    place(nb%domain_local) = [(i, i = 1, n)]
    allocate (counts(n), source=1)   ! this rank
    allocate (last(n), fill(n), nb%holder_start(n + 1))
    do round = 1, 2   ! count, then fill
      last = 0
      if (round == 2) then
        nb%holder_start(1) = 1
        do i = 1, n
          nb%holder_start(i + 1) = nb%holder_start(i) + counts(i)
        end do
        allocate (nb%holder(nb%holder_start(n + 1) - 1))
        fill = nb%holder_start(1:n)
        nb%holder(fill) = nb%rank
        fill = fill + 1
      end if
      do k = 1, dom%n_neighbours
        do s = dom%send_start(k), dom%send_start(k + 1) - 1   ! corner slot 4 (element - 1) + corner
          i = place(dom%connectivity(modulo(dom%send_slot(s) - 1, 4) + 1, (dom%send_slot(s) - 1) / 4 + 1))
          if (i == 0) cycle
          if (last(i) == k) cycle
          last(i) = k
          if (round == 1) then
            counts(i) = counts(i) + 1
          else
            nb%holder(fill(i)) = dom%neighbour(k)
            fill(i) = fill(i) + 1
          end if
        end do
      end do
    end do
    do i = 1, n
      call merge_sort_ascending(nb%holder(nb%holder_start(i):nb%holder_start(i + 1) - 1))
    end do
  end subroutine domain_holders

  !> New ghosts: every rank's box of its own slaves per pass goes to all; this rank sends each other
  !> rank the nodes of its own master segments that have a node within the search radius of the
  !> pass plus twice the movement allowed before the next refresh (a fifth of the smallest bucket)
  !> of that rank's box, measured at the positions of the last sort (at the current ones when a sort
  !> follows: sorting). A master within reach of a slave before the next refresh is then held, and
  !> so are the nodes of every segment around it. Collective.
  subroutine neighbours_refresh(nb, c, sorting, from_sort, traffic)
    type(neighbours_t), intent(inout) :: nb
    type(contact_t), intent(inout) :: c
    logical, intent(in) :: sorting
    !> the slaves' boxes at their places at the last sort (a restart under automatic sorting)
    logical, intent(in) :: from_sort
    type(traffic_t), intent(inout) :: traffic
    real(wp) :: boxes(6, size(c%passes)), all_boxes(6, size(c%passes), nb%n_ranks), smallest
    integer, allocatable :: list(:), start(:), dest(:), sources(:), rstart(:), at(:), segs(:, :), seg_start(:)
    real(wp), allocatable :: buffer(:), received(:)
    integer, allocatable :: slots(:)
    integer :: p, q, first, i, k, h, d, n_segs, s
    if (allocated(nb%own_near)) deallocate (nb%own_near)
    smallest = minval([(c%passes(p)%bucket_size, p = 1, size(c%passes))])
    do p = 1, size(c%passes)
      boxes(1:3, p) = huge(1.0_wp)
      boxes(4:6, p) = -huge(1.0_wp)
      do i = 1, size(c%passes(p)%slaves)   ! its own slaves alone
        k = c%passes(p)%slave_at(i)
        if (from_sort) then
          boxes(1:3, p) = min(boxes(1:3, p), c%x_at_sort(:, k))
          boxes(4:6, p) = max(boxes(4:6, p), c%x_at_sort(:, k))
        else
          boxes(1:3, p) = min(boxes(1:3, p), c%x(:, k))
          boxes(4:6, p) = max(boxes(4:6, p), c%x(:, k))
        end if
      end do
    end do
    call MPI_Allgather(boxes, size(boxes), MPI_DOUBLE_PRECISION, all_boxes, size(boxes), MPI_DOUBLE_PRECISION, &
                       nb%comm)
    call count_allgather(traffic, int(8 * size(boxes), i8), int(8 * size(all_boxes), i8), nb%n_ranks)
    allocate (list(0), start(1), dest(0), segs(2, 64), seg_start(1))
    start(1) = 1
    seg_start(1) = 1
    n_segs = 0
    allocate (nb%own_near(0))
    if (size(nb%mark) < size(c%held_node)) then   ! marks per slot (a stamp never 0)
      deallocate (nb%mark)
      allocate (nb%mark(size(c%held_node)), source=0)
    end if
    nb%stamp = nb%stamp + 1
    do p = 1, size(c%passes)
      call near_segments(nb, c, p, all_boxes(:, p, nb%rank + 1), smallest, sorting, nb%own_near)
    end do
    do q = 0, nb%n_ranks - 1
      if (q == nb%rank) cycle
      first = size(list) + 1
      nb%stamp = nb%stamp + 1
      do p = 1, size(c%passes)
        call near_segments(nb, c, p, all_boxes(:, p, q + 1), smallest, sorting, list, segs, n_segs)
      end do
      if (size(list) < first) cycle
      call merge_sort_ascending(list(first:))
      dest = [dest, q]
      start = [start, size(list) + 1]
      seg_start = [seg_start, n_segs + 1]
    end do
    nb%send%rank = dest
    nb%send%start = start
    nb%send%node = list
    nb%send%at = [(nb%domain_local(sorted_position(nb%domain_node, list(i))), i = 1, size(list))]
    ! each message: its number of ghost segments, their rows, then each ghost's row and its holders
    ! (list holds nodes of this domain: of its own segments)
    allocate (at(size(list) + 1))
    at(1) = 1
    do i = 1, size(list)
      h = sorted_position(nb%domain_node, list(i))
      at(i + 1) = at(i) + ghost_width + nb%holder_start(h + 1) - nb%holder_start(h)
    end do
    allocate (buffer(at(size(list) + 1) - 1 + size(dest) * 1 + segment_row_width * n_segs))
    k = 0
    do d = 1, size(dest)
      start(d) = k + 1
      buffer(k + 1) = real(seg_start(d + 1) - seg_start(d), wp)
      k = k + 1
      do i = seg_start(d), seg_start(d + 1) - 1
        buffer(k + 1:k + segment_row_width) = segment_row(c, segs(1, i), segs(2, i))
        k = k + segment_row_width
      end do
      do i = nb%send%start(d), nb%send%start(d + 1) - 1
        k = k + 1
        h = sorted_position(nb%domain_node, list(i))
        s = slot_of(c, list(i))
        buffer(k:k + at(i + 1) - at(i) - 1) = [real(list(i), wp), c%x_at_sort(:, s), c%x(:, s), c%v(:, s), c%mass(s), &
                                               real(nb%holder_start(h + 1) - nb%holder_start(h), wp), &
                                               real(nb%holder(nb%holder_start(h):nb%holder_start(h + 1) - 1), wp)]
        k = k + at(i + 1) - at(i) - 1
      end do
    end do
    start(size(dest) + 1) = k + 1
    call sparse_exchange(nb%comm, nb%n_ranks, nb%round, dest, start, buffer, sources, rstart, received, traffic)
    call take_ghosts(nb, c, sources, rstart, received)
    nb%own_near = [(slot_of(c, nb%own_near(i)), i = 1, size(nb%own_near))]   ! names till now, slots from here
    slots = [(slot_of(c, nb%owned_node(i)), i = 1, size(nb%owned_node))]
    nb%x_at_refresh = c%x(:, slots)
    if (from_sort) nb%x_at_refresh = c%x_at_sort(:, slots)
    nb%refresh_pending = .false.
  end subroutine neighbours_refresh

  !> The ghosts of a refresh (messages received(rstart(i) :) from sources(i), rows of neighbours_refresh):
  !> the held nodes are this domain's and these (renumbered: contact_hold); their positions,
  !> velocities and masses, the lists to update between refreshes (recv), and each ghost's holders.
  subroutine take_ghosts(nb, c, sources, rstart, received)
    type(neighbours_t), intent(inout) :: nb
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: sources(:), rstart(:)
    real(wp), intent(in) :: received(:)
    integer, allocatable :: nodes(:), first(:), held(:), to(:)
    logical :: kept
    real(wp), allocatable :: segment_rows(:, :)
    integer :: i, j, k, m, n, g, width, s, n_segs
    if (allocated(nb%ghost_holder)) deallocate (nb%recv%start, nb%ghost_holder_start, nb%ghost_holder)
    nb%recv%rank = sources
    allocate (nb%recv%start(size(sources) + 1))
    allocate (first(size(received) / ghost_width))   ! where each row starts (ghost_width or more long)
    n_segs = 0
    do i = 1, size(sources)
      n_segs = n_segs + nint(received(rstart(i)))
    end do
    allocate (segment_rows(segment_row_width, n_segs))
    n_segs = 0
    j = 0
    do i = 1, size(sources)
      nb%recv%start(i) = j + 1
      m = rstart(i)
      do k = 1, nint(received(m))   ! the ghost segments, then the ghosts
        n_segs = n_segs + 1
        segment_rows(:, n_segs) = received(m + 1 + segment_row_width * (k - 1):m + segment_row_width * k)
      end do
      m = m + 1 + segment_row_width * nint(received(m))
      do while (m < rstart(i + 1))
        j = j + 1
        first(j) = m
        m = m + ghost_width + nint(received(m + 11))
      end do
    end do
    nb%recv%start(size(sources) + 1) = j + 1
    first = first(1:j)
    nodes = nint(received(first))
    nb%recv%node = nodes
    nb%ghost_node = distinct_ascending(pack(nodes, [(.not. in_domain(nb, nodes(i)), i = 1, size(nodes))]))
    n = size(nb%ghost_node)
    held = [nb%domain_node, nb%ghost_node]
    call merge_sort_ascending(held)
    call contact_hold(c, held, to)
    kept = same_segments(nb, segment_rows)
    if (kept) call contact_pass_slots_moved(c, to, kept)
    if (.not. kept) then
      call hold_ghost_segments(c, segment_rows)
      call contact_pass_slots(c)
      nb%segment_rows_before = segment_rows
    end if
    nb%recv%at = [(slot_of(c, nodes(i)), i = 1, size(nodes))]
    allocate (nb%ghost_holder_start(n + 1), source=0)
    do j = 1, size(nodes)   ! a ghost from several ranks comes with the same holders from each
      k = nodes(j)
      if (in_domain(nb, k)) cycle
      m = first(j)
      s = nb%recv%at(j)
      c%x_at_sort(:, s) = received(m + 1:m + 3)
      c%x(:, s) = received(m + 4:m + 6)
      c%v(:, s) = received(m + 7:m + 9)
      c%mass(s) = received(m + 10)
      nb%ghost_holder_start(sorted_position(nb%ghost_node, k) + 1) = nint(received(m + 11))
    end do
    nb%ghost_holder_start(1) = 1
    do g = 1, n
      nb%ghost_holder_start(g + 1) = nb%ghost_holder_start(g + 1) + nb%ghost_holder_start(g)
    end do
    allocate (nb%ghost_holder(nb%ghost_holder_start(n + 1) - 1))
    do j = 1, size(nodes)
      k = nodes(j)
      if (in_domain(nb, k)) cycle
      m = first(j)
      g = sorted_position(nb%ghost_node, k)
      width = nint(received(m + 11))
      nb%ghost_holder(nb%ghost_holder_start(g):nb%ghost_holder_start(g + 1) - 1) = &
        nint(received(m + ghost_width:m + ghost_width + width - 1))
    end do
  end subroutine take_ghosts

  !> Whether a refresh brings the same ghost segments (rows, in the order they came) as the last:
  !> the passes' segments and masters are then those already built.
  pure logical function same_segments(nb, segment_rows) result(same)
    type(neighbours_t), intent(in) :: nb
    real(wp), intent(in) :: segment_rows(:, :)
    same = .false.
    if (.not. allocated(nb%segment_rows_before)) return
    if (any(shape(segment_rows) /= shape(nb%segment_rows_before))) return
    same = all(segment_rows == nb%segment_rows_before)
  end function same_segments

  !> Append to list the nodes (not yet marked) of this rank's segments of pass p with a node near
  !> box (lower and upper corner of a rank's own slaves of the pass), and (segs: the ghost
  !> segments for that rank, segs(:, 1:n_segs)) the pass and the place of each of those segments.
  subroutine near_segments(nb, c, p, box, smallest, sorting, list, segs, n_segs)
    type(neighbours_t), intent(inout) :: nb
    type(contact_t), intent(in) :: c
    integer, intent(in) :: p
    real(wp), intent(in) :: box(6), smallest
    logical, intent(in) :: sorting
    integer, allocatable, intent(inout) :: list(:)
    integer, allocatable, intent(inout), optional :: segs(:, :)
    integer, intent(inout), optional :: n_segs
    integer, allocatable :: grown(:, :)
    real(wp) :: reach, lower(3), upper(3), x(3)
    integer :: i, m, k
    if (any(box(1:3) > box(4:6))) return          ! no slave of the pass there
    associate (pass => c%passes(p))
    reach = pass%bucket_size + pass%t_slave + pass%t_master + 0.2_wp * smallest
    lower = box(1:3) - reach
    upper = box(4:6) + reach
    do i = 1, size(pass%own_element)
      do m = 1, 4
        k = pass%own_segment_at(m, i)
        if (sorting) then
          x = c%x(:, k)
        else
          x = c%x_at_sort(:, k)
        end if
        if (all(x >= lower .and. x <= upper)) exit
      end do
      if (m > 4) cycle
      if (present(segs)) then
        if (n_segs == size(segs, 2)) then
          allocate (grown(2, 2 * n_segs))
          grown(:, 1:n_segs) = segs(:, 1:n_segs)
          call move_alloc(grown, segs)
        end if
        n_segs = n_segs + 1
        segs(:, n_segs) = [p, i]
      end if
      do m = 1, 4
        k = pass%own_segment_at(m, i)
        if (nb%mark(k) == nb%stamp) cycle
        nb%mark(k) = nb%stamp
        list = [list, pass%own_segments(m, i)]
      end do
    end do
    end associate
  end subroutine near_segments

  !> The ghosts' positions and velocities from the ranks that sent them at the last refresh (this
  !> rank's are x and v at local columns send%at; a ghost that is also a node of this domain
  !> gets the same values as its own copy, and so becomes current here too).
  subroutine neighbours_update(nb, c, x, v, traffic)
    type(neighbours_t), intent(inout) :: nb
    type(contact_t), intent(inout) :: c
    real(wp), intent(in) :: x(:, :), v(:, :)
    type(traffic_t), intent(inout) :: traffic
    real(wp), allocatable :: out(:), in(:)
    type(MPI_Request), allocatable :: requests(:)
    integer :: i, j, k, n_send, n_recv, at
    n_send = size(nb%send%rank)
    n_recv = size(nb%recv%rank)
    allocate (out(6 * size(nb%send%node)), in(6 * size(nb%recv%node)), requests(n_send + n_recv))
    do j = 1, size(nb%send%node)
      k = nb%send%at(j)
      out(6 * j - 5:6 * j) = [x(:, k), v(:, k)]
    end do
    do i = 1, n_recv
      at = 6 * (nb%recv%start(i) - 1)
      call MPI_Irecv(in(at + 1:6 * (nb%recv%start(i + 1) - 1)), 6 * (nb%recv%start(i + 1) - nb%recv%start(i)), &
                     MPI_DOUBLE_PRECISION, nb%recv%rank(i), update_tag, nb%comm, requests(i))
    end do
    do i = 1, n_send
      at = 6 * (nb%send%start(i) - 1)
      call MPI_Isend(out(at + 1:6 * (nb%send%start(i + 1) - 1)), 6 * (nb%send%start(i + 1) - nb%send%start(i)), &
                     MPI_DOUBLE_PRECISION, nb%send%rank(i), update_tag, nb%comm, requests(n_recv + i))
    end do
    call MPI_Waitall(n_send + n_recv, requests, MPI_STATUSES_IGNORE)
    call count_messages(traffic, n_send, int(8 * size(out), i8), int(8 * size(in), i8))
    do j = 1, size(nb%recv%node)
      k = nb%recv%at(j)
      c%x(:, k) = in(6 * j - 5:6 * j - 3)
      c%v(:, k) = in(6 * j - 2:6 * j)
    end do
  end subroutine neighbours_update


  !> Whether contact node `node` is one of this domain's.
  pure logical function in_domain(nb, node)
    type(neighbours_t), intent(in) :: nb
    integer, intent(in) :: node
    integer :: h
    h = sorted_position(nb%domain_node, node)
    in_domain = .false.
    if (h <= size(nb%domain_node)) in_domain = nb%domain_node(h) == node
  end function in_domain

end module contact_neighbours
