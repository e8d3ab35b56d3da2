!> Local contact search for shell segments (Hallquist, Goudreau & Benson 1985; Hallquist, LS-DYNA
!> Theory Manual; the paper's stages 2 and 3).
!>
!> A master segment is a four-node quadrilateral with the bilinear surface
!>   x(xi, eta) = sum_I N_I(xi, eta) x_I,  N_I = (1 + xi xi_I)(1 + eta eta_I) / 4,
!> nodes 1..4 at (xi, eta) = (-1,-1), (1,-1), (1,1), (-1,1). A triangle is a quadrilateral with
!> nodes 3 and 4 equal.
!>
!> Stage 2 (segment_candidates): among the master segments around the nearest master node, the
!> one whose closest point is nearest to the slave node. Stage 3 (closest_point_on_segment, in
!> segment_projection): the closest point in isoparametric coordinates. The penalty force
!> (contact_penalty's penalty_force) then acts on the contact surfaces of the shells, which lie half
!> a thickness off each mid-surface on both sides (shells are two-sided).
!>
!> Between the global search and stage 2, the candidate pairs (slave, nearest master node) found by
!> all ranks are put in ascending slave order (candidates_in_slave_order) and cut into one
!> contiguous block per rank (candidate_block), the paper's node-wise block decomposition.
!>
!> Pure: no MPI, no I/O, no module state.
module contact_search
  use paradyn_kinds, only: wp, ip, i8
  use segment_projection, only: closest_point_on_segment, segment_distance_bound
  use contact_penalty, only: edge_tolerance
  implicit none
  private
  public :: segment_candidates, node_segment_map
  public :: candidate_block, candidates_in_slave_order

contains

  !> Node-to-segment map in compressed-row form: the segments that contain node i are
  !> segment_list(segment_start(i) : segment_start(i + 1) - 1), ascending. A node repeated in a
  !> segment (triangle) is listed once; node numbers outside 1..n_nodes are skipped. n_entries is
  !> the length used of segment_list (at most 4 n_segments).
  pure subroutine node_segment_map(n_nodes, n_segments, segment_nodes, segment_start, segment_list, &
                                   n_entries)
    integer(ip), intent(in) :: n_nodes, n_segments
    integer(ip), intent(in) :: segment_nodes(4, n_segments)
    integer(ip), intent(out) :: segment_start(n_nodes + 1)
    integer(ip), intent(out) :: segment_list(4 * n_segments)
    integer(ip), intent(out) :: n_entries
    integer(ip) :: s, k, node, i
    segment_start = 0
    segment_list = 0
    do s = 1, n_segments
      do k = 1, 4
        node = segment_nodes(k, s)
        if (listed_node(segment_nodes(:, s), k, n_nodes)) segment_start(node) = segment_start(node) + 1
      end do
    end do
    ! segment_start(i) = end (exclusive) of node i, then filled backwards down to its start
    if (n_nodes > 0) segment_start(1) = segment_start(1) + 1
    do i = 2, n_nodes
      segment_start(i) = segment_start(i) + segment_start(i - 1)
    end do
    if (n_nodes > 0) then
      n_entries = segment_start(n_nodes) - 1
    else
      n_entries = 0
    end if
    do s = n_segments, 1, -1
      do k = 1, 4
        node = segment_nodes(k, s)
        if (listed_node(segment_nodes(:, s), k, n_nodes)) then
          segment_start(node) = segment_start(node) - 1
          segment_list(segment_start(node)) = s
        end if
      end do
    end do
    segment_start(n_nodes + 1) = n_entries + 1
  end subroutine node_segment_map

  !> Node k of a segment counts if it is a valid node not already among nodes 1..k-1.
  pure logical function listed_node(nodes, k, n_nodes)
    integer(ip), intent(in) :: nodes(4), k, n_nodes
    listed_node = nodes(k) >= 1 .and. nodes(k) <= n_nodes
    if (listed_node .and. k > 1) listed_node = .not. any(nodes(1:k - 1) == nodes(k))
  end function listed_node

  !> Stages 2 and 3 for one slave point p: of the master segments that contain the master node
  !> `node` (from node_segment_map), the one whose closest point is nearest to p (the lower
  !> segment number on ties), with that closest point and the normal there. segment = 0 when
  !> the node belongs to no segment. With skip_node, segments that contain that node do not count
  !> (a slave's own segments in a single-surface contact). The segments' nodes are columns of
  !> coords (the held slots of the contact state, contact_slots: the pass's segment_at), and
  !> skip_node is one too; node is a master's place in segment_start.
  !>
  !> The segments are projected in the order of their segment_distance_bound, and one whose bound
  !> already exceeds the nearest closest point found cannot be nearer: it is not projected. The
  !> answer is the same as projecting them all (only the order of the projections changes, and the
  !> choice does not depend on it). With reach: segment = 0 also when no segment can touch p by
  !> penalty_force's test with that reach (half the two thicknesses), that is when every bound
  !> exceeds the reach plus the offset the face test allows (edge_tolerance times the longer
  !> diagonal): the projections are then skipped.
  pure subroutine segment_candidates(p, node, n_nodes, coords, n_segments, segment_nodes, &
                                     segment_start, segment_list, segment, xi, eta, xc, normal, skip_node, reach, &
                                     clearance)
    real(wp), intent(in) :: p(3)
    integer(ip), intent(in) :: node, n_nodes, n_segments
    real(wp), intent(in) :: coords(3, *)
    integer(ip), intent(in) :: segment_nodes(4, n_segments)
    integer(ip), intent(in) :: segment_start(n_nodes + 1)
    integer(ip), intent(in) :: segment_list(*)
    integer(ip), intent(out) :: segment
    real(wp), intent(out) :: xi, eta, xc(3), normal(3)
    integer(ip), intent(in), optional :: skip_node
    real(wp), intent(in), optional :: reach
    !> with reach, where no segment can touch: how much farther than it could touch the nearest
    !> segment lies at least (the least of bound - (reach + offset)); else 0
    real(wp), intent(out), optional :: clearance
    integer, parameter :: most = 16              ! segments around a node that are ordered
    real(wp) :: s_xi, s_eta, s_xc(3), s_normal(3), d2, best_d2, xseg(3, 4), bound(most), b, diagonal, touch, gap
    integer(ip) :: order(most), j, s, k, n, i
    logical :: near, ordered

    segment = 0
    xi = 0.0_wp
    eta = 0.0_wp
    xc = 0.0_wp
    normal = 0.0_wp
    if (present(clearance)) clearance = 0.0_wp
    if (node < 1 .or. node > n_nodes) return
    best_d2 = huge(1.0_wp)
    gap = huge(1.0_wp)
    n = segment_start(node + 1) - segment_start(node)
    ordered = n <= most                          ! else (not expected of a shell mesh) all, in list order
    near = .not. (present(reach) .and. ordered)
    if (ordered) then
      n = 0
      do j = segment_start(node), segment_start(node + 1) - 1
        s = segment_list(j)
        if (present(skip_node)) then
          if (any(segment_nodes(:, s) == skip_node)) cycle
        end if
        do i = 1, 4
          xseg(:, i) = coords(:, segment_nodes(i, s))
        end do
        if (near) then
          b = segment_distance_bound(xseg, p)
        else
          diagonal = sqrt(max(sum((xseg(:, 3) - xseg(:, 1))**2), sum((xseg(:, 4) - xseg(:, 2))**2)))
          touch = reach + edge_tolerance * diagonal + 1.0e-10_wp * (reach + diagonal)
          b = segment_distance_bound(xseg, p, enough=touch)
          near = b <= touch
          gap = min(gap, b - touch)
        end if
        ! insert into the segments in ascending order of their bounds
        n = n + 1
        k = n
        do while (k > 1)
          if (.not. (bound(k - 1) > b)) exit
          bound(k) = bound(k - 1)
          order(k) = order(k - 1)
          k = k - 1
        end do
        bound(k) = b
        order(k) = s
      end do
    end if
    if (.not. near) then
      if (present(clearance) .and. gap < huge(1.0_wp)) clearance = gap
      return
    end if
    do k = 1, n
      if (ordered) then
        if (bound(k)**2 > best_d2) exit          ! this one and the rest cannot be nearer
        s = order(k)
      else
        s = segment_list(segment_start(node) + k - 1)
        if (present(skip_node)) then
          if (any(segment_nodes(:, s) == skip_node)) cycle
        end if
      end if
      do i = 1, 4
        xseg(:, i) = coords(:, segment_nodes(i, s))
      end do
      call closest_point_on_segment(xseg, p, s_xi, s_eta, s_xc, s_normal)
      d2 = sum((p - s_xc)**2)
      if (segment == 0 .or. d2 < best_d2 .or. (d2 == best_d2 .and. s < segment)) then
        best_d2 = d2
        segment = s
        xi = s_xi
        eta = s_eta
        xc = s_xc
        normal = s_normal
      end if
    end do
  end subroutine segment_candidates

  !> Block of the candidate list that rank (0-based) of n_ranks works on: candidates first..last
  !> (empty when last < first). The blocks are contiguous, in rank order, cover 1..n_candidates
  !> exactly once and their sizes differ by at most one (the paper's kave per processor).
  pure subroutine candidate_block(n_candidates, n_ranks, rank, first, last)
    integer(ip), intent(in) :: n_candidates, n_ranks, rank
    integer(ip), intent(out) :: first, last
    ! 64-bit products: n_candidates * n_ranks may exceed 2**31
    first = int(int(rank, i8) * n_candidates / n_ranks, ip) + 1
    last = int(int(rank + 1, i8) * n_candidates / n_ranks, ip)
  end subroutine candidate_block

  !> The candidate pairs (slave index, nearest master index) of all ranks, as they arrive rank
  !> after rank, in ascending slave order: candidates(:, 1:n_candidates). Each slave appears at
  !> most once in pairs; slaves are 1..n_slaves. nearest is workspace (the master of each slave,
  !> 0 for none): scattering and reading it back in slave order costs O(n_slaves), no sort.
  pure subroutine candidates_in_slave_order(n_slaves, n_pairs, pairs, nearest, n_candidates, candidates)
    integer(ip), intent(in) :: n_slaves, n_pairs
    integer(ip), intent(in) :: pairs(2, n_pairs)
    integer(ip), intent(out) :: nearest(n_slaves)
    integer(ip), intent(out) :: n_candidates
    integer(ip), intent(inout) :: candidates(:, :)
    integer(ip) :: j, k
    nearest = 0
    do k = 1, n_pairs
      nearest(pairs(1, k)) = pairs(2, k)
    end do
    n_candidates = 0
    do j = 1, n_slaves
      if (nearest(j) == 0) cycle
      n_candidates = n_candidates + 1
      candidates(1, n_candidates) = j
      candidates(2, n_candidates) = nearest(j)
    end do
  end subroutine candidates_in_slave_order

end module contact_search
