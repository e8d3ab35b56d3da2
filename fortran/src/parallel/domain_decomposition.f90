!> Element domain decomposition and the bookkeeping every rank needs. Two ways to give elements
!> to ranks: the paper's contiguous blocks by element number (block_owner) and recursive
!> coordinate bisection of the element centroids (rcb_partition). For any owner array, decompose
!> builds one rank's elements and nodes in local numbering, which neighbour ranks share nodes,
!> which element corners go to and come from each of them, and the fixed-order assembly lists.
!> Pure computation from the global mesh: no MPI here (the engine builds its domain with
!> distributed_decomposition and bisects with distributed_rcb; these are their references).
module domain_decomposition
  use paradyn_kinds, only: wp, i8
  use element_groups, only: group_size
  ! the deck's /control partition codes: partition_blocks (the paper's contiguous blocks by element
  ! number) and partition_rcb (recursive coordinate bisection of the element centroids)
  use paradyn_schema, only: partition_blocks, partition_rcb
  use integer_sort, only: sort_ascending
  implicit none
  private
  public :: domain_t, block_owner, rcb_partition, element_centroids, partition_elements, decompose
  public :: local_node, local_element, build_groups
  public :: partition_blocks, partition_rcb


  type :: domain_t
    integer :: rank = 0, n_ranks = 1
    integer :: n_elements = 0                 !< local elements
    integer, allocatable :: elements(:)       !< global ids of local elements, ascending
    integer :: n_nodes = 0                    !< local nodes (touched by local elements)
    integer, allocatable :: nodes(:)          !< global ids of local nodes, ascending
    integer, allocatable :: connectivity(:, :) !< (4, n_elements), local node ids
    integer, allocatable :: node_owned(:)     !< 1 if this rank is the lowest rank touching the node
    integer :: n_ghost_slots = 0              !< corner forces received from neighbours
    integer, allocatable :: assembly_start(:), assembly_slot(:)   !< CSR, n_nodes + 1
    integer :: n_neighbours = 0
    integer, allocatable :: neighbour(:)      !< neighbour ranks, ascending
    integer, allocatable :: send_start(:), send_slot(:)   !< CSR over neighbours
    integer, allocatable :: recv_start(:), recv_slot(:)   !< CSR over neighbours
    integer :: n_groups = 0
    integer, allocatable :: group_first(:), group_count(:), group_part(:)
    !> the group's elements are triangles (third and fourth node the same: shell_c0_triangle), else
    !> quadrilaterals (shell_blt)
    logical, allocatable :: group_triangle(:)
  end type domain_t

  !> Which element corners and which ranks meet at each global node (CSR by node).
  type :: incidence_t
    integer, allocatable :: corner_start(:), corner(:)   !< incident corners, ascending by element
    integer, allocatable :: rank_start(:), ranks(:)      !< ranks touching the node, ascending
  end type incidence_t

contains

  !> Rank owning global element e of n_elements in contiguous blocks of near-equal size.
  pure integer function block_owner(e, n_elements, n_ranks) result(owner)
    integer, intent(in) :: e, n_elements, n_ranks
    owner = int((int(e - 1, 8) * n_ranks) / n_elements)
    ! guard the rounding at block edges: block r holds elements (r*ne)/np + 1 .. ((r+1)*ne)/np
    do while (owner > 0 .and. e <= (int(owner, 8) * n_elements) / n_ranks)
      owner = owner - 1
    end do
    do while (e > (int(owner + 1, 8) * n_elements) / n_ranks)
      owner = owner + 1
    end do
  end function block_owner

  !> Owner rank (0-based) of every element by the chosen method (partition_blocks or partition_rcb).
  !> coordinates: (3, n_nodes); connectivity: (4, n_elements) global 1-based node ids.
  pure subroutine partition_elements(method, coordinates, connectivity, n_ranks, owner)
    integer, intent(in) :: method, n_ranks
    real(wp), intent(in) :: coordinates(:, :)
    integer, intent(in) :: connectivity(:, :)
    integer, intent(out) :: owner(:)
    real(wp), allocatable :: centroids(:, :)
    integer :: e
    if (method == partition_rcb) then
      allocate (centroids(3, size(connectivity, 2)))
      call element_centroids(coordinates, connectivity, centroids)
      call rcb_partition(size(owner), centroids, n_ranks, owner)
    else
      do e = 1, size(owner)
        owner(e) = block_owner(e, size(owner), n_ranks)
      end do
    end if
  end subroutine partition_elements

  !> Centroid of every element: the mean of its four corner positions.
  pure subroutine element_centroids(coordinates, connectivity, centroids)
    real(wp), intent(in) :: coordinates(:, :)
    integer, intent(in) :: connectivity(:, :)
    real(wp), intent(out) :: centroids(:, :)
    integer :: e
    do e = 1, size(connectivity, 2)
      centroids(:, e) = 0.25_wp * (coordinates(:, connectivity(1, e)) + coordinates(:, connectivity(2, e)) &
                                   + coordinates(:, connectivity(3, e)) + coordinates(:, connectivity(4, e)))
    end do
  end subroutine element_centroids

  !> Recursive coordinate bisection: owner(e) in 0..n_ranks-1 for element centroids (3, n_elements).
  !> Each set of elements for q ranks is cut across the longest side of its bounding box (the
  !> lowest axis on a tie); the lower n q_low / q elements in (coordinate, element id) order go to
  !> the first q_low = q / 2 ranks. Part sizes differ by at most one for any n_ranks, and the
  !> strict (coordinate, id) order makes the answer the same on every rank and compiler.
  !> Cost O(n log n log p); work arrays are allocated (they scale with the mesh).
  pure subroutine rcb_partition(n_elements, centroids, n_ranks, owner)
    integer, intent(in) :: n_elements, n_ranks
    real(wp), intent(in) :: centroids(3, n_elements)
    integer, intent(out) :: owner(n_elements)
    integer, allocatable :: order(:), buffer(:)
    integer :: e
    allocate (order(n_elements), buffer(n_elements))
    order = [(e, e = 1, n_elements)]
    call bisect(centroids, 1, n_elements, 0, max(n_ranks, 1), order, buffer, owner)
  end subroutine rcb_partition

  !> Give the elements order(first:last) to ranks rank0 .. rank0 + q - 1 (one level of rcb_partition).
  pure recursive subroutine bisect(centroids, first, last, rank0, q, order, buffer, owner)
    real(wp), intent(in) :: centroids(:, :)
    integer, intent(in) :: first, last, rank0, q
    integer, intent(inout) :: order(:), buffer(:), owner(:)
    integer :: axis, k, q_low, n_low
    real(wp) :: extent(3)
    if (q == 1 .or. last < first) then
      owner(order(first:last)) = rank0
      return
    end if
    do k = 1, 3
      extent(k) = maxval(centroids(k, order(first:last))) - minval(centroids(k, order(first:last)))
    end do
    axis = 1
    do k = 2, 3
      if (extent(k) > extent(axis)) axis = k
    end do
    q_low = q / 2
    n_low = int((int(last - first + 1, i8) * q_low) / q)
    call sort_by_axis(order(first:last), buffer(first:last), centroids, axis)
    call bisect(centroids, first, first + n_low - 1, rank0, q_low, order, buffer, owner)
    call bisect(centroids, first + n_low, last, rank0 + q_low, q - q_low, order, buffer, owner)
  end subroutine bisect

  !> Bottom-up merge sort of element ids by (centroid along axis, id), a strict total order, so
  !> the result does not depend on the algorithm. work: scratch of the same size.
  pure subroutine sort_by_axis(ids, work, centroids, axis)
    integer, intent(inout) :: ids(:), work(:)
    real(wp), intent(in) :: centroids(:, :)
    integer, intent(in) :: axis
    integer :: n, width, lo
    logical :: in_ids
    n = size(ids)
    width = 1
    in_ids = .true.
    do while (width < n)
      do lo = 1, n, 2 * width
        if (in_ids) then
          call merge_runs(ids, work, lo, min(lo + width - 1, n), min(lo + 2 * width - 1, n), centroids, axis)
        else
          call merge_runs(work, ids, lo, min(lo + width - 1, n), min(lo + 2 * width - 1, n), centroids, axis)
        end if
      end do
      in_ids = .not. in_ids
      width = 2 * width
    end do
    if (.not. in_ids) ids = work
  end subroutine sort_by_axis

  !> Merge the sorted runs src(lo:mid) and src(mid+1:hi) into dst(lo:hi).
  pure subroutine merge_runs(src, dst, lo, mid, hi, centroids, axis)
    integer, intent(in) :: src(:), lo, mid, hi, axis
    integer, intent(inout) :: dst(:)
    real(wp), intent(in) :: centroids(:, :)
    integer :: i, j, k
    logical :: left
    i = lo
    j = mid + 1
    do k = lo, hi
      if (i > mid) then
        left = .false.
      else if (j > hi) then
        left = .true.
      else
        left = centroids(axis, src(i)) < centroids(axis, src(j)) .or. &
               (centroids(axis, src(i)) == centroids(axis, src(j)) .and. src(i) < src(j))
      end if
      if (left) then
        dst(k) = src(i)
        i = i + 1
      else
        dst(k) = src(j)
        j = j + 1
      end if
    end do
  end subroutine merge_runs

  !> Build the domain of one rank. connectivity: (4, n_elements) global 1-based node ids;
  !> element_part: part of each element (groups never mix parts); owner: rank of each element in
  !> 0..n_ranks-1, from any method (every rank must pass the same array).
  pure subroutine decompose(n_nodes, n_elements, connectivity, element_part, owner, n_ranks, rank, dom)
    integer, intent(in) :: n_nodes, n_elements, n_ranks, rank
    integer, intent(in) :: connectivity(4, n_elements), element_part(n_elements), owner(n_elements)
    type(domain_t), intent(out) :: dom
    type(incidence_t) :: inc
    integer, allocatable :: global_to_local(:), ghost_of(:)
    dom%rank = rank
    dom%n_ranks = n_ranks
    call build_incidence(n_nodes, n_elements, connectivity, owner, inc)
    call local_elements_and_nodes(n_nodes, n_elements, connectivity, owner, inc, dom, global_to_local)
    call neighbour_lists(n_elements, connectivity, owner, inc, dom, ghost_of)
    call assembly_lists(owner, inc, ghost_of, dom)
    call build_groups(dom, element_part(dom%elements))
  end subroutine decompose

  !> The incident corners of every node, ascending by element (corner id = 4 (e - 1) + c), and
  !> the ranks touching it (distinct owners of its incident elements, ascending). Allocatable
  !> rather than automatic: these scale with the global mesh and must not live on the stack.
  pure subroutine build_incidence(n_nodes, n_elements, connectivity, owner, inc)
    integer, intent(in) :: n_nodes, n_elements, connectivity(4, n_elements), owner(n_elements)
    type(incidence_t), intent(out) :: inc
    integer, allocatable :: fill(:)
    integer :: e, c, n, s, r, total
    allocate (inc%corner_start(n_nodes + 1), inc%corner(4 * n_elements), source=0)
    do e = 1, n_elements
      do c = 1, 4
        inc%corner_start(connectivity(c, e) + 1) = inc%corner_start(connectivity(c, e) + 1) + 1
      end do
    end do
    inc%corner_start(1) = 1
    do n = 1, n_nodes
      inc%corner_start(n + 1) = inc%corner_start(n + 1) + inc%corner_start(n)
    end do
    fill = inc%corner_start(1:n_nodes)
    do e = 1, n_elements
      do c = 1, 4
        n = connectivity(c, e)
        inc%corner(fill(n)) = 4 * (e - 1) + c
        fill(n) = fill(n) + 1
      end do
    end do
    allocate (inc%rank_start(n_nodes + 1), inc%ranks(4 * n_elements))
    inc%rank_start(1) = 1
    total = 0
    do n = 1, n_nodes
      do s = inc%corner_start(n), inc%corner_start(n + 1) - 1
        r = owner((inc%corner(s) - 1) / 4 + 1)
        if (.not. any(inc%ranks(inc%rank_start(n):total) == r)) then
          total = total + 1
          inc%ranks(total) = r
        end if
      end do
      call sort_ascending(inc%ranks(inc%rank_start(n):total))
      inc%rank_start(n + 1) = total + 1
    end do
  end subroutine build_incidence

  !> Whether rank r holds an element around global node n.
  pure logical function touches(inc, node, r)
    type(incidence_t), intent(in) :: inc
    integer, intent(in) :: node, r
    touches = any(inc%ranks(inc%rank_start(node):inc%rank_start(node + 1) - 1) == r)
  end function touches

  !> This rank's elements and the nodes they touch, in ascending global order; a node is owned by
  !> the lowest rank touching it.
  pure subroutine local_elements_and_nodes(n_nodes, n_elements, connectivity, owner, inc, dom, global_to_local)
    integer, intent(in) :: n_nodes, n_elements, connectivity(4, n_elements), owner(n_elements)
    type(incidence_t), intent(in) :: inc
    type(domain_t), intent(inout) :: dom
    integer, allocatable, intent(out) :: global_to_local(:)
    integer :: e, n, le
    dom%n_elements = count_equal(owner, dom%rank)
    allocate (dom%elements(dom%n_elements))
    dom%elements = pack([(e, e = 1, n_elements)], owner == dom%rank)
    allocate (global_to_local(n_nodes), source=0)
    dom%n_nodes = 0
    do n = 1, n_nodes
      if (touches(inc, n, dom%rank)) then
        dom%n_nodes = dom%n_nodes + 1
        global_to_local(n) = dom%n_nodes
      end if
    end do
    allocate (dom%nodes(dom%n_nodes), dom%node_owned(dom%n_nodes))
    do n = 1, n_nodes
      if (global_to_local(n) > 0) then
        dom%nodes(global_to_local(n)) = n
        dom%node_owned(global_to_local(n)) = merge(1, 0, inc%ranks(inc%rank_start(n)) == dom%rank)
      end if
    end do
    allocate (dom%connectivity(4, dom%n_elements))
    do le = 1, dom%n_elements
      dom%connectivity(:, le) = global_to_local(connectivity(:, dom%elements(le)))
    end do
  end subroutine local_elements_and_nodes

  !> Neighbours (every other rank that touches one of our nodes) and, per neighbour, the corners
  !> we send (ours on nodes it also holds, ascending element and corner) and the ghost slots we
  !> receive into (its corners on nodes we hold, in the order it sends them: its local elements
  !> are its owned elements in ascending global id, whatever the owner array). ghost_of(corner)
  !> is the slot of a received global corner.
  pure subroutine neighbour_lists(n_elements, connectivity, owner, inc, dom, ghost_of)
    integer, intent(in) :: n_elements, connectivity(4, n_elements), owner(n_elements)
    type(incidence_t), intent(in) :: inc
    type(domain_t), intent(inout) :: dom
    integer, allocatable, intent(out) :: ghost_of(:)
    integer :: e, c, r, k, le, count
    allocate (dom%neighbour(0))
    do r = 0, dom%n_ranks - 1
      if (r == dom%rank) cycle
      do le = 1, dom%n_nodes
        if (touches(inc, dom%nodes(le), r)) then
          dom%neighbour = [dom%neighbour, r]
          exit
        end if
      end do
    end do
    dom%n_neighbours = size(dom%neighbour)
    allocate (dom%send_start(dom%n_neighbours + 1), dom%recv_start(dom%n_neighbours + 1))
    allocate (dom%send_slot(0), dom%recv_slot(0))
    allocate (ghost_of(4 * n_elements), source=0)
    dom%send_start(1) = 1
    dom%recv_start(1) = 1
    count = 0
    do k = 1, dom%n_neighbours
      r = dom%neighbour(k)
      do le = 1, dom%n_elements
        do c = 1, 4
          if (touches(inc, connectivity(c, dom%elements(le)), r)) dom%send_slot = [dom%send_slot, 4 * (le - 1) + c]
        end do
      end do
      dom%send_start(k + 1) = size(dom%send_slot) + 1
      do e = 1, n_elements
        if (owner(e) /= r) cycle
        do c = 1, 4
          if (touches(inc, connectivity(c, e), dom%rank)) then
            count = count + 1
            ghost_of(4 * (e - 1) + c) = 4 * dom%n_elements + count
            dom%recv_slot = [dom%recv_slot, 4 * dom%n_elements + count]
          end if
        end do
      end do
      dom%recv_start(k + 1) = size(dom%recv_slot) + 1
    end do
    dom%n_ghost_slots = count
  end subroutine neighbour_lists

  !> Assembly lists: every incident corner of a local node, ascending global element order (the
  !> fixed order of the nodal sum, the same on every layout).
  pure subroutine assembly_lists(owner, inc, ghost_of, dom)
    integer, intent(in) :: owner(:), ghost_of(:)
    type(incidence_t), intent(in) :: inc
    type(domain_t), intent(inout) :: dom
    integer :: e, c, n, s, k, le
    allocate (dom%assembly_start(dom%n_nodes + 1))
    dom%assembly_start(1) = 1
    do le = 1, dom%n_nodes
      n = dom%nodes(le)
      dom%assembly_start(le + 1) = dom%assembly_start(le) + inc%corner_start(n + 1) - inc%corner_start(n)
    end do
    allocate (dom%assembly_slot(dom%assembly_start(dom%n_nodes + 1) - 1))
    k = 0
    do le = 1, dom%n_nodes
      n = dom%nodes(le)
      do s = inc%corner_start(n), inc%corner_start(n + 1) - 1
        k = k + 1
        e = (inc%corner(s) - 1) / 4 + 1
        c = inc%corner(s) - 4 * (e - 1)
        if (owner(e) == dom%rank) then
          dom%assembly_slot(k) = 4 * (local_element(dom, e) - 1) + c
        else
          dom%assembly_slot(k) = ghost_of(inc%corner(s))
        end if
      end do
    end do
  end subroutine assembly_lists

  !> Local id of a global element this rank owns (binary search: dom%elements ascends).
  pure integer function local_element(dom, e_global)
    type(domain_t), intent(in) :: dom
    integer, intent(in) :: e_global
    integer :: lo, hi, mid
    lo = 1
    hi = dom%n_elements
    do while (lo < hi)
      mid = (lo + hi) / 2
      if (dom%elements(mid) < e_global) then
        lo = mid + 1
      else
        hi = mid
      end if
    end do
    local_element = lo
  end function local_element

  !> Groups of at most group_size consecutive local elements of one part and one shape (local_part:
  !> the part of each local element; a triangle is an element whose third and fourth nodes are the
  !> same). The element order is kept: a group ends where the part or the shape changes, so a mesh
  !> of quadrilaterals only has the groups it had before triangles were read.
  pure subroutine build_groups(dom, local_part)
    type(domain_t), intent(inout) :: dom
    integer, intent(in) :: local_part(:)
    integer :: le, first, part, n
    logical :: triangle
    allocate (dom%group_first(0), dom%group_count(0), dom%group_part(0), dom%group_triangle(0))
    le = 1
    do while (le <= dom%n_elements)
      first = le
      part = local_part(le)
      triangle = dom%connectivity(3, le) == dom%connectivity(4, le)
      n = 0
      do while (le <= dom%n_elements .and. n < group_size)
        if (local_part(le) /= part) exit
        if ((dom%connectivity(3, le) == dom%connectivity(4, le)) .neqv. triangle) exit
        n = n + 1
        le = le + 1
      end do
      dom%group_first = [dom%group_first, first]
      dom%group_count = [dom%group_count, n]
      dom%group_part = [dom%group_part, part]
      dom%group_triangle = [dom%group_triangle, triangle]
    end do
    dom%n_groups = size(dom%group_first)
  end subroutine build_groups

  pure integer function count_equal(a, value)
    integer, intent(in) :: a(:), value
    count_equal = count(a == value)
  end function count_equal

  !> Local id of a global node, 0 if this rank does not hold it (binary search: dom%nodes ascends).
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

end module domain_decomposition
