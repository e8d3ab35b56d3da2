!> Local contact search and penalty forces for shell segments (Hallquist, Goudreau & Benson 1985;
!> Hallquist, LS-DYNA Theory Manual; the paper's stages 2 and 3).
!>
!> A master segment is a four-node quadrilateral with the bilinear surface
!>   x(xi, eta) = sum_I N_I(xi, eta) x_I,  N_I = (1 + xi xi_I)(1 + eta eta_I) / 4,
!> nodes 1..4 at (xi, eta) = (-1,-1), (1,-1), (1,1), (-1,1). A triangle is a quadrilateral with
!> nodes 3 and 4 equal.
!>
!> Stage 2 (segment_candidates): among the master segments around the nearest master node, the
!> one whose closest point is nearest to the slave node. Stage 3 (closest_point_on_segment, in
!> segment_projection): the closest point in isoparametric coordinates. The penalty force (penalty_force) then acts on
!> the contact surfaces of the shells, which lie half a thickness off each mid-surface on both
!> sides (shells are two-sided).
!>
!> Between the global search and stage 2, the candidate pairs (slave, nearest master node) found by
!> all ranks are put in ascending slave order (candidates_in_slave_order) and cut into one
!> contiguous block per rank (candidate_block), the paper's node-wise block decomposition.
!>
!> Pure: no MPI, no I/O, no module state.
module contact_search
  use paradyn_kinds, only: wp, ip, i8
  use vector_algebra, only: cross
  use segment_projection, only: closest_point_on_segment, segment_shape_functions, segment_distance_bound
  implicit none
  private
  public :: closest_point_on_segment, segment_candidates, node_segment_map
  public :: shell_penalty_stiffness, penalty_force, friction_coefficient, segment_shape_functions
  public :: default_penalty_scale, edge_tolerance
  public :: candidate_block, candidates_in_slave_order, segment_distance_bound

  !> LS-DYNA's default scale factor of the penalty stiffness.
  real(wp), parameter :: default_penalty_scale = 0.1_wp
  !> A slave point whose closest point on a segment is off the segment's normal by more than
  !> this fraction of the longer diagonal (it lies beyond an edge) is not in contact with that
  !> segment, unless rounded edges are asked for. The margin keeps a node that slides over the
  !> ridge between two faceted segments from slipping through the gap between their normals.
  real(wp), parameter :: edge_tolerance = 0.05_wp

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

  !> Penalty stiffness of a shell master segment, LS-DYNA's shell form k = scale K A / d_max:
  !> K = E / (3 (1 - 2 nu)) the bulk modulus, A the segment area (half the cross product of the
  !> diagonals, exact for a flat quadrilateral), d_max the longer diagonal. scale is usually
  !> default_penalty_scale (0.1).
  pure real(wp) function shell_penalty_stiffness(xseg, young, poisson, scale) result(k)
    real(wp), intent(in) :: xseg(3, 4), young, poisson, scale
    real(wp) :: d13(3), d24(3), bulk, area, diagonal
    d13 = xseg(:, 3) - xseg(:, 1)
    d24 = xseg(:, 4) - xseg(:, 2)
    bulk = young / (3.0_wp * (1.0_wp - 2.0_wp * poisson))
    area = 0.5_wp * norm2(cross(d13, d24))
    diagonal = max(norm2(d13), norm2(d24))
    k = 0.0_wp
    if (diagonal > 0.0_wp) k = scale * bulk * area / diagonal
  end function shell_penalty_stiffness

  !> Friction coefficient at slip speed v: mu = mu_d + (mu_s - mu_d) exp(-decay v) (LS-DYNA's
  !> exponential interpolation from the static to the dynamic coefficient).
  pure real(wp) function friction_coefficient(mu_static, mu_dynamic, decay, v) result(mu)
    real(wp), intent(in) :: mu_static, mu_dynamic, decay, v
    mu = mu_dynamic + (mu_static - mu_dynamic) * exp(-decay * v)
  end function friction_coefficient

  !> Penalty contact force between a slave node at p (shell thickness t_slave) and a master
  !> segment xseg (thickness t_master), both two-sided.
  !>
  !> With xc the closest point of the segment, n its unit normal there and d = (p - xc).n, the
  !> contact surfaces are half a thickness off the mid-surfaces, so the gap is
  !> g = |d| - (t_slave + t_master) / 2. If g < 0 the slave gets f = -k g sign(d) n (pushed out
  !> on the side it is on; d = 0 counts as the +n side) and master node I gets -f N_I(xi, eta),
  !> so the forces sum to zero and have no moment about xc. penetration = -g (0 when not in
  !> contact).
  !>
  !> Only points whose closest point lies on the segment count: the offset of p - xc from the
  !> normal line must be within edge_tolerance of the longer diagonal. With rounded_edges, a
  !> point beyond an edge or corner instead meets the edge rounded with radius
  !> (t_slave + t_master) / 2: g = |p - xc| - (t_slave + t_master) / 2 along (p - xc) / |p - xc|,
  !> continuous with the face value where the projection leaves the segment.
  !>
  !> Friction (optional, when v_slave, v_master and the coefficients are given): regularised
  !> Coulomb friction on the relative tangential velocity v_t = v_rel - (v_rel.e) e,
  !> v_rel = v_slave - sum_I N_I v_master_I, e the force direction:
  !>   f_t = -mu |f_n| v_t / max(|v_t|, v_slip),  mu = mu_d + (mu_s - mu_d) exp(-decay |v_t|).
  !> Above the slip velocity v_slip this is Coulomb friction at the cap mu |f_n| opposing the
  !> slip; below it the force falls linearly to zero with the slip speed (a viscous
  !> regularisation of stick). We chose this velocity form over LS-DYNA's elastic trial force
  !> (k times the tangential slip increment, returned to the cap) because it needs no history
  !> per contact pair; the price is that a body at rest on a slope creeps at a speed of order
  !> v_slip. v_slip = 0 gives the pure sign form. The friction force is shared out like the
  !> normal force (slave node; master nodes by N_I), so it is also equal and opposite; the slave
  !> node sits a distance d off xc along the normal, so the friction pair leaves a couple
  !> d x f_t that is not applied to the shell rotations (as in usual node-to-segment contact).
  pure subroutine penalty_force(p, t_slave, xseg, t_master, k, f_slave, f_master, penetration, &
                                in_contact, v_slave, v_master, mu_static, mu_dynamic, decay, &
                                v_slip, rounded_edges, closest)
    real(wp), intent(in) :: p(3), t_slave, xseg(3, 4), t_master, k
    real(wp), intent(out) :: f_slave(3), f_master(3, 4), penetration
    logical, intent(out) :: in_contact
    real(wp), intent(in), optional :: v_slave(3), v_master(3, 4)
    real(wp), intent(in), optional :: mu_static, mu_dynamic, decay, v_slip
    logical, intent(in), optional :: rounded_edges
    !> the closest point of p on the segment already found: xi, eta, xc(3), normal(3)
    real(wp), intent(in), optional :: closest(8)
    real(wp) :: xi, eta, xc(3), normal(3), dvec(3), d, offset(3), reach, gap, direction(3), dist
    real(wp) :: diagonal, shape(4), v_rel(3), v_t(3), speed, mu, fn, regular
    logical :: rounded, on_edge
    integer :: i

    f_slave = 0.0_wp
    f_master = 0.0_wp
    penetration = 0.0_wp
    in_contact = .false.
    rounded = .false.
    if (present(rounded_edges)) rounded = rounded_edges

    if (present(closest)) then
      xi = closest(1)
      eta = closest(2)
      xc = closest(3:5)
      normal = closest(6:8)
    else
      call closest_point_on_segment(xseg, p, xi, eta, xc, normal)
    end if
    dvec = p - xc
    d = dot_product(dvec, normal)
    offset = dvec - d * normal
    reach = 0.5_wp * (t_slave + t_master)
    diagonal = max(norm2(xseg(:, 3) - xseg(:, 1)), norm2(xseg(:, 4) - xseg(:, 2)))
    if (.not. (diagonal > 0.0_wp)) return          ! collapsed segment: no normal, no contact
    on_edge = abs(xi) >= 1.0_wp .or. abs(eta) >= 1.0_wp
    dist = norm2(dvec)

    if (rounded .and. on_edge .and. dist > 0.0_wp) then
      gap = dist - reach
      direction = dvec / dist
    else if (norm2(offset) <= edge_tolerance * diagonal) then
      gap = abs(d) - reach
      if (d >= 0.0_wp) then
        direction = normal
      else
        direction = -normal
      end if
    else
      return
    end if
    if (.not. (gap < 0.0_wp)) return

    in_contact = .true.
    penetration = -gap
    fn = -k * gap
    f_slave = fn * direction
    shape = segment_shape_functions(xi, eta)

    if (present(v_slave) .and. present(v_master) .and. present(mu_static) .and. &
        present(mu_dynamic)) then
      v_rel = v_slave - matmul(v_master, shape)
      v_t = v_rel - dot_product(v_rel, direction) * direction
      speed = norm2(v_t)
      if (speed > 0.0_wp) then
        mu = mu_dynamic
        if (present(decay)) mu = friction_coefficient(mu_static, mu_dynamic, decay, speed)
        regular = 0.0_wp
        if (present(v_slip)) regular = v_slip
        f_slave = f_slave - mu * abs(fn) * v_t / max(speed, regular)
      end if
    end if

    do i = 1, 4
      f_master(:, i) = -shape(i) * f_slave
    end do
  end subroutine penalty_force

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
