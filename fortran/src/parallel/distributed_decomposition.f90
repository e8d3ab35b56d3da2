!> The domain of one rank built from its own elements only (issue 19, item 5): no array here is
!> sized by the global mesh. A distributed directory finds who shares each node: node n has a
!> home rank by id range (block_owner(n, n_nodes, n_ranks), no mesh needed); every rank sends the
!> corners of its elements to the homes of their nodes (one MPI_Alltoallv), each home sorts the
!> incident corners of its nodes by corner id and sends every node's list back to each rank that
!> touches it (a second MPI_Alltoallv). From those lists each rank derives exactly the domain_t of
!> domain_decomposition's decompose (same local numbering, neighbours, send and receive order,
!> ghost slots and assembly order), so the results are bitwise those of the global path.
!> Memory per rank: its elements, its nodes and their incident corners, plus arrays of n_ranks
!> counts. A corner is 4 (e - 1) + c for global element e and corner c.
module distributed_decomposition
  use mpi_f08
  use domain_decomposition, only: domain_t, block_owner, local_node, local_element, build_groups
  use integer_sort, only: merge_sort_ascending, sort_ascending, sorted_position, distinct_ascending
  use rank_exchange, only: exchange_int, offsets
  implicit none
  private
  public :: decompose_distributed

  !> The incident corners of this rank's nodes (CSR by local node, ascending corner id) and the
  !> rank owning each corner's element; the ranks touching each node (CSR, ascending, distinct).
  type :: node_incidence_t
    integer, allocatable :: start(:), corner(:), owner(:)
    integer, allocatable :: rank_start(:), ranks(:)
  end type node_incidence_t

contains

  !> Build this rank's domain. n_nodes: the global node count (the directory's id ranges);
  !> elements: this rank's global element ids, ascending; connectivity (4, size(elements)): their
  !> global node ids; local_part: their parts. Collective over comm.
  subroutine decompose_distributed(comm, n_nodes, elements, connectivity, local_part, dom)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_nodes, elements(:), connectivity(:, :), local_part(:)
    type(domain_t), intent(out) :: dom
    type(node_incidence_t) :: inc
    integer, allocatable :: ghost_corner(:)
    call MPI_Comm_rank(comm, dom%rank)
    call MPI_Comm_size(comm, dom%n_ranks)
    dom%n_elements = size(elements)
    dom%elements = elements
    call local_nodes(connectivity, dom)
    call node_incidence(comm, n_nodes, connectivity, dom, inc)
    call neighbour_lists(inc, dom, ghost_corner)
    call assembly_lists(inc, ghost_corner, dom)
    call build_groups(dom, local_part)
  end subroutine decompose_distributed

  !> The distinct nodes of this rank's elements, ascending, and the local connectivity.
  pure subroutine local_nodes(connectivity, dom)
    integer, intent(in) :: connectivity(:, :)
    type(domain_t), intent(inout) :: dom
    integer :: k, le
    dom%nodes = distinct_ascending(reshape(connectivity, [4 * dom%n_elements]))
    dom%n_nodes = size(dom%nodes)
    allocate (dom%connectivity(4, dom%n_elements))
    do le = 1, dom%n_elements
      do k = 1, 4
        dom%connectivity(k, le) = local_node(dom, connectivity(k, le))
      end do
    end do
  end subroutine local_nodes

  !> The directory's two exchanges: corners to the homes of their nodes, and every node's sorted
  !> incident corners back to the ranks touching it.
  subroutine node_incidence(comm, n_nodes, connectivity, dom, inc)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_nodes, connectivity(:, :)
    type(domain_t), intent(in) :: dom
    type(node_incidence_t), intent(out) :: inc
    integer, allocatable :: send(:), counts(:), recv(:), recv_counts(:), source(:)
    integer, allocatable :: fill(:)
    integer :: le, c, r, k, p
    p = dom%n_ranks
    ! to the homes: (node, corner) pairs, grouped by home rank
    allocate (counts(p), fill(p), source=0)
    do le = 1, dom%n_elements
      do c = 1, 4
        r = block_owner(connectivity(c, le), n_nodes, p)
        counts(r + 1) = counts(r + 1) + 2
      end do
    end do
    call offsets(counts, fill)
    allocate (send(sum(counts)))
    do le = 1, dom%n_elements
      do c = 1, 4
        r = block_owner(connectivity(c, le), n_nodes, p) + 1
        send(fill(r) + 1:fill(r) + 2) = [connectivity(c, le), 4 * (dom%elements(le) - 1) + c]
        fill(r) = fill(r) + 2
      end do
    end do
    call exchange_int(comm, send, counts, recv, recv_counts)
    allocate (source(size(recv) / 2))
    k = 0
    do r = 1, p
      source(k + 1:k + recv_counts(r) / 2) = r - 1
      k = k + recv_counts(r) / 2
    end do
    call answer_from_home(dom, n_nodes, recv, source, send, counts)
    call exchange_int(comm, send, counts, recv, recv_counts)
    call unpack_incidence(recv, dom, inc)
  end subroutine node_incidence

  !> At the home of nodes first..last: the received (node, corner) pairs from rank source(k), sorted
  !> into each node's corners ascending; then the message for each rank touching a node: the node
  !> id, its corner count m, and m (corner, owner rank) pairs. send and counts: the outgoing lists.
  pure subroutine answer_from_home(dom, n_nodes, pairs, source, send, counts)
    type(domain_t), intent(in) :: dom
    integer, intent(in) :: n_nodes, pairs(:), source(:)
    integer, allocatable, intent(out) :: send(:)
    integer, intent(out) :: counts(:)
    integer, allocatable :: start(:), corner(:), owner(:), fill(:), at(:)
    integer :: first, last, k, n, s, m, r, j
    first = int((int(dom%rank, 8) * n_nodes) / dom%n_ranks) + 1
    last = int((int(dom%rank + 1, 8) * n_nodes) / dom%n_ranks)
    allocate (start(last - first + 2), source=0)
    do k = 1, size(source)
      n = pairs(2 * k - 1) - first + 1
      start(n + 1) = start(n + 1) + 1
    end do
    start(1) = 1
    do n = 1, last - first + 1
      start(n + 1) = start(n + 1) + start(n)
    end do
    allocate (corner(size(source)), owner(size(source)))
    fill = start(1:last - first + 1)
    do k = 1, size(source)
      n = pairs(2 * k - 1) - first + 1
      corner(fill(n)) = pairs(2 * k)
      owner(fill(n)) = source(k)
      fill(n) = fill(n) + 1
    end do
    do n = 1, last - first + 1
      call sort_pairs(corner(start(n):start(n + 1) - 1), owner(start(n):start(n + 1) - 1))
    end do
    ! each rank touching node n gets 2 + 2 m integers
    counts = 0
    do n = 1, last - first + 1
      m = start(n + 1) - start(n)
      do s = start(n), start(n + 1) - 1
        if (first_of_rank(owner(start(n):s))) counts(owner(s) + 1) = counts(owner(s) + 1) + 2 + 2 * m
      end do
    end do
    allocate (at(dom%n_ranks))
    call offsets(counts, at)
    allocate (send(sum(counts)))
    do n = 1, last - first + 1
      m = start(n + 1) - start(n)
      do s = start(n), start(n + 1) - 1
        if (.not. first_of_rank(owner(start(n):s))) cycle
        r = owner(s) + 1
        send(at(r) + 1:at(r) + 2) = [n + first - 1, m]
        do j = 0, m - 1
          send(at(r) + 3 + 2 * j:at(r) + 4 + 2 * j) = [corner(start(n) + j), owner(start(n) + j)]
        end do
        at(r) = at(r) + 2 + 2 * m
      end do
    end do
  end subroutine answer_from_home

  !> Whether the last entry of owners is the first occurrence of its value in the list.
  pure logical function first_of_rank(owners)
    integer, intent(in) :: owners(:)
    first_of_rank = .not. any(owners(1:size(owners) - 1) == owners(size(owners)))
  end function first_of_rank

  !> Sort the (corner, owner) pairs of one node by corner id (insertion: a node has few corners).
  pure subroutine sort_pairs(corner, owner)
    integer, intent(inout) :: corner(:), owner(:)
    integer :: i, j, key, value
    do i = 2, size(corner)
      key = corner(i)
      value = owner(i)
      j = i - 1
      do while (j >= 1)
        if (corner(j) <= key) exit
        corner(j + 1) = corner(j)
        owner(j + 1) = owner(j)
        j = j - 1
      end do
      corner(j + 1) = key
      owner(j + 1) = value
    end do
  end subroutine sort_pairs

  !> The answers of the homes, into CSR by local node (each local node gets exactly one answer).
  pure subroutine unpack_incidence(recv, dom, inc)
    integer, intent(in) :: recv(:)
    type(domain_t), intent(in) :: dom
    type(node_incidence_t), intent(inout) :: inc
    integer, allocatable :: place(:), size_of(:)
    integer :: k, ln, m, total, s, t
    allocate (place(dom%n_nodes), size_of(dom%n_nodes), source=0)
    k = 0
    do while (k < size(recv))
      ln = local_node(dom, recv(k + 1))
      place(ln) = k + 3
      size_of(ln) = recv(k + 2)
      k = k + 2 + 2 * recv(k + 2)
    end do
    allocate (inc%start(dom%n_nodes + 1), inc%rank_start(dom%n_nodes + 1))
    inc%start(1) = 1
    do ln = 1, dom%n_nodes
      inc%start(ln + 1) = inc%start(ln) + size_of(ln)
    end do
    total = inc%start(dom%n_nodes + 1) - 1
    allocate (inc%corner(total), inc%owner(total), inc%ranks(total))
    inc%rank_start(1) = 1
    t = 0
    do ln = 1, dom%n_nodes
      do m = 0, size_of(ln) - 1
        s = inc%start(ln) + m
        inc%corner(s) = recv(place(ln) + 2 * m)
        inc%owner(s) = recv(place(ln) + 2 * m + 1)
        if (.not. any(inc%ranks(inc%rank_start(ln):t) == inc%owner(s))) then
          t = t + 1
          inc%ranks(t) = inc%owner(s)
        end if
      end do
      call sort_ascending(inc%ranks(inc%rank_start(ln):t))
      inc%rank_start(ln + 1) = t + 1
    end do
  end subroutine unpack_incidence

  !> Whether rank r holds an element around local node ln.
  pure logical function touches(inc, ln, r)
    type(node_incidence_t), intent(in) :: inc
    integer, intent(in) :: ln, r
    touches = any(inc%ranks(inc%rank_start(ln):inc%rank_start(ln + 1) - 1) == r)
  end function touches

  !> Owned nodes (this rank the lowest touching them), neighbours (ascending), the corners sent to
  !> each (ours on nodes it touches, ascending local element and corner) and the ghost slots
  !> received from each (its corners on our nodes, ascending corner id, as it sends them).
  !> ghost_corner(k): the corner id of ghost slot 4 n_elements + k.
  pure subroutine neighbour_lists(inc, dom, ghost_corner)
    type(node_incidence_t), intent(in) :: inc
    type(domain_t), intent(inout) :: dom
    integer, allocatable, intent(out) :: ghost_corner(:)
    logical, allocatable :: is_neighbour(:)
    integer :: ln, le, c, k, r, s, n
    allocate (dom%node_owned(dom%n_nodes), source=0)
    allocate (is_neighbour(0:dom%n_ranks - 1), source=.false.)
    do ln = 1, dom%n_nodes
      if (inc%ranks(inc%rank_start(ln)) == dom%rank) dom%node_owned(ln) = 1
      is_neighbour(inc%ranks(inc%rank_start(ln):inc%rank_start(ln + 1) - 1)) = .true.
    end do
    is_neighbour(dom%rank) = .false.
    dom%neighbour = pack([(r, r = 0, dom%n_ranks - 1)], is_neighbour)
    dom%n_neighbours = size(dom%neighbour)
    allocate (dom%send_start(dom%n_neighbours + 1), dom%recv_start(dom%n_neighbours + 1))
    dom%send_start(1) = 1
    dom%recv_start(1) = 1
    do k = 1, dom%n_neighbours   ! counts first
      n = 0
      do le = 1, dom%n_elements
        do c = 1, 4
          if (touches(inc, dom%connectivity(c, le), dom%neighbour(k))) n = n + 1
        end do
      end do
      dom%send_start(k + 1) = dom%send_start(k) + n
      dom%recv_start(k + 1) = dom%recv_start(k) + count(inc%owner == dom%neighbour(k))
    end do
    allocate (dom%send_slot(dom%send_start(dom%n_neighbours + 1) - 1))
    allocate (dom%recv_slot(dom%recv_start(dom%n_neighbours + 1) - 1))
    allocate (ghost_corner(size(dom%recv_slot)))
    do k = 1, dom%n_neighbours
      n = dom%send_start(k) - 1
      do le = 1, dom%n_elements
        do c = 1, 4
          if (.not. touches(inc, dom%connectivity(c, le), dom%neighbour(k))) cycle
          n = n + 1
          dom%send_slot(n) = 4 * (le - 1) + c
        end do
      end do
      n = dom%recv_start(k) - 1
      do s = 1, size(inc%owner)
        if (inc%owner(s) /= dom%neighbour(k)) cycle
        n = n + 1
        ghost_corner(n) = inc%corner(s)
      end do
      call merge_sort_ascending(ghost_corner(dom%recv_start(k):n))
    end do
    dom%n_ghost_slots = size(ghost_corner)
    dom%recv_slot = [(4 * dom%n_elements + k, k = 1, dom%n_ghost_slots)]
  end subroutine neighbour_lists

  !> Every incident corner of each local node, ascending corner id (= ascending global element):
  !> a local corner or the ghost slot of a neighbour's.
  pure subroutine assembly_lists(inc, ghost_corner, dom)
    type(node_incidence_t), intent(in) :: inc
    integer, intent(in) :: ghost_corner(:)
    type(domain_t), intent(inout) :: dom
    integer :: s, e, c, k
    dom%assembly_start = inc%start
    allocate (dom%assembly_slot(size(inc%corner)))
    do s = 1, size(inc%corner)
      e = (inc%corner(s) - 1) / 4 + 1
      c = inc%corner(s) - 4 * (e - 1)
      if (inc%owner(s) == dom%rank) then
        dom%assembly_slot(s) = 4 * (local_element(dom, e) - 1) + c
      else
        k = findloc(dom%neighbour, inc%owner(s), dim=1)
        dom%assembly_slot(s) = 4 * dom%n_elements + dom%recv_start(k) - 1 + &
                               sorted_position(ghost_corner(dom%recv_start(k):dom%recv_start(k + 1) - 1), inc%corner(s))
      end if
    end do
  end subroutine assembly_lists

end module distributed_decomposition
