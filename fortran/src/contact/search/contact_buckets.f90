!> Global contact search: three-dimensional bucket sort of the master nodes (Benson & Hallquist
!> 1990; the paper's Table 1) and the nearest master node of a slave point.
!>
!> The bounding box of the master nodes is cut into nb(1) x nb(2) x nb(3) equal buckets whose
!> edges are at least the requested bucket size (the caller derives it from the segment size).
!> The total number of buckets is capped at the number of nodes, so memory stays O(n) whatever
!> the size. A counting sort puts the nodes of each bucket together in compressed-row form:
!> the nodes of bucket b are bucket_nodes(bucket_start(b) : bucket_start(b + 1) - 1), in
!> ascending order. Buckets are numbered b = ix + nb(1) (iy - 1) + nb(1) nb(2) (iz - 1).
!>
!> The query looks at the bucket of the point and its 26 neighbours, then at wider rings of
!> buckets until no unvisited bucket can hold a closer node, so the answer always equals brute
!> force (ties go to the lower master index). The query is exact for the coordinates the grid
!> was built from; if nodes have moved since, rebuild (the build is O(n) and reuses its arrays).
!>
!> Pure: no MPI, no I/O, no module state. Arrays are allocated only by bucket_grid_build.
module contact_buckets
  use paradyn_kinds, only: wp, ip
  implicit none
  private
  public :: bucket_grid_t, bucket_grid_build, nearest_master_node, nearest_master_nodes
  public :: bucket_of_point, masters_within, nearest_in_list, bucket_grid_drop

  !> Buckets over the bounding box of the master nodes, in compressed-row form.
  type :: bucket_grid_t
    integer(ip) :: n_nodes = 0                  !< master nodes sorted
    integer(ip) :: n_buckets(3) = 1             !< buckets along x, y, z
    real(wp) :: lower(3) = 0.0_wp               !< lower corner of the bounding box
    real(wp) :: upper(3) = 0.0_wp               !< upper corner of the bounding box
    real(wp) :: width(3) = 0.0_wp               !< bucket edge along each axis (0 on a flat axis)
    real(wp) :: inverse_width(3) = 0.0_wp       !< 1 / width (0 on a flat axis)
    real(wp) :: tolerance = 0.0_wp              !< round-off allowance of the search bound
    integer :: builds = 0                       !< times built: a list of its nodes is stale once it grows
    integer(ip), allocatable :: bucket_start(:) !< (product(n_buckets) + 1)
    integer(ip), allocatable :: bucket_nodes(:) !< (n_nodes), master indices grouped by bucket
    integer(ip), allocatable :: node_bucket(:)  !< (n_nodes), bucket of each master node
  end type bucket_grid_t

contains

  !> Sort n master nodes coords(:, 1:n) into buckets of edge at least bucket_size. A size that
  !> is not positive selects about one node per bucket: edge = (V / n)^(1/k) with V the product
  !> of the k nonzero extents of the box (so a flat sheet of nodes gets square buckets). The grid's
  !> arrays are reallocated only when their sizes change, so rebuilding the grid every step for the
  !> same master set allocates nothing after the first build.
  pure subroutine bucket_grid_build(n, coords, bucket_size, grid)
    integer(ip), intent(in) :: n
    real(wp), intent(in) :: coords(3, n), bucket_size
    type(bucket_grid_t), intent(inout) :: grid
    real(wp) :: extent(3), h, cap, count_real(3), volume
    integer(ip) :: a, i, b, n_total, iter

    grid%n_nodes = n
    grid%builds = grid%builds + 1
    if (n > 0) then
      grid%lower = minval(coords, dim=2)
      grid%upper = maxval(coords, dim=2)
    else
      grid%lower = 0.0_wp
      grid%upper = 0.0_wp
    end if
    extent = grid%upper - grid%lower

    ! bucket edge: the requested size, but never so small that there are more buckets than
    ! nodes (grow the edge by a factor 5/4 until the cap holds; at most ~ 3 log(n) / log(1.25)
    ! passes because the start already bounds each axis by n)
    cap = real(max(n, 1_ip), wp)
    h = bucket_size
    if (.not. (h > 0.0_wp) .and. any(extent > 0.0_wp)) then
      volume = product(extent, mask=extent > 0.0_wp)
      h = (volume / cap)**(1.0_wp / real(count(extent > 0.0_wp), wp))
    end if
    h = max(h, maxval(extent) / cap, tiny(1.0_wp))
    do iter = 1, 1000
      count_real = max(1.0_wp, real(floor(extent / h), wp))
      if (product(count_real) <= cap) exit
      h = 1.25_wp * h
    end do
    do a = 1, 3
      grid%n_buckets(a) = int(count_real(a), ip)
      if (extent(a) > 0.0_wp) then
        grid%width(a) = extent(a) / real(grid%n_buckets(a), wp)
        grid%inverse_width(a) = real(grid%n_buckets(a), wp) / extent(a)
      else
        grid%width(a) = 0.0_wp
        grid%inverse_width(a) = 0.0_wp
      end if
    end do
    grid%tolerance = 64.0_wp * epsilon(1.0_wp) * (maxval(abs(grid%lower)) + maxval(abs(grid%upper)) &
                                                   + maxval(extent))
    n_total = product(grid%n_buckets)

    call ensure_size(grid%bucket_start, n_total + 1)
    call ensure_size(grid%bucket_nodes, n)
    call ensure_size(grid%node_bucket, n)

    ! counting sort: bucket_start(b) first holds the end (exclusive) of bucket b, then filling
    ! from the last node backwards decrements it to the start and leaves each bucket ascending
    grid%bucket_start = 0
    do i = 1, n
      b = bucket_of_point(grid, coords(:, i))
      grid%node_bucket(i) = b
      grid%bucket_start(b) = grid%bucket_start(b) + 1
    end do
    grid%bucket_start(1) = grid%bucket_start(1) + 1
    do b = 2, n_total
      grid%bucket_start(b) = grid%bucket_start(b) + grid%bucket_start(b - 1)
    end do
    do i = n, 1, -1
      b = grid%node_bucket(i)
      grid%bucket_start(b) = grid%bucket_start(b) - 1
      grid%bucket_nodes(grid%bucket_start(b)) = i
    end do
    grid%bucket_start(n_total + 1) = n + 1
  end subroutine bucket_grid_build

  !> Leave the nodes with dropped(i) out of the grid's buckets (the box and the buckets stay those of
  !> the build, over every node): no query finds them. The others keep their ascending order.
  pure subroutine bucket_grid_drop(grid, dropped)
    type(bucket_grid_t), intent(inout) :: grid
    logical, intent(in) :: dropped(:)
    integer(ip) :: b, k, n, first
    n = 0
    do b = 1, size(grid%bucket_start) - 1
      first = grid%bucket_start(b)
      grid%bucket_start(b) = n + 1
      do k = first, grid%bucket_start(b + 1) - 1
        if (dropped(grid%bucket_nodes(k))) cycle
        n = n + 1
        grid%bucket_nodes(n) = grid%bucket_nodes(k)
      end do
    end do
    grid%bucket_start(size(grid%bucket_start)) = n + 1
  end subroutine bucket_grid_drop

  pure subroutine ensure_size(array, n)
    integer(ip), allocatable, intent(inout) :: array(:)
    integer(ip), intent(in) :: n
    if (allocated(array)) then
      if (size(array) == n) return
      deallocate(array)
    end if
    allocate(array(n))
  end subroutine ensure_size

  !> Bucket index of one axis, clamped into the grid (points outside the box fall into the
  !> boundary buckets).
  pure integer(ip) function axis_index(grid, a, x) result(ib)
    type(bucket_grid_t), intent(in) :: grid
    integer(ip), intent(in) :: a
    real(wp), intent(in) :: x
    real(wp) :: s
    s = (x - grid%lower(a)) * grid%inverse_width(a)
    if (.not. (s >= 1.0_wp)) then          ! also catches NaN
      ib = 1
    else if (s >= real(grid%n_buckets(a), wp)) then
      ib = grid%n_buckets(a)
    else
      ib = int(s, ip) + 1
    end if
  end function axis_index

  !> Bucket number of a point (clamped into the grid); the paper's nbxyz.
  pure integer(ip) function bucket_of_point(grid, x) result(b)
    type(bucket_grid_t), intent(in) :: grid
    real(wp), intent(in) :: x(3)
    b = axis_index(grid, 1, x(1)) + grid%n_buckets(1) * (axis_index(grid, 2, x(2)) - 1 &
        + grid%n_buckets(2) * (axis_index(grid, 3, x(3)) - 1))
  end function bucket_of_point

  !> Index (1..n_nodes) of the master node nearest to point, the lower index on ties; 0 when
  !> the grid is empty. coords must be the coordinates the grid was built from.
  !>
  !> With max_distance, only nodes within that distance count (0 when there is none), and the
  !> search stops at that radius: the cost of a query far from every master node is then
  !> bounded by (max_distance / bucket edge)^3 buckets instead of growing to the whole grid.
  !> With excluded, the master indices listed there never count (a slave's own node and its
  !> neighbours in a single-surface contact).
  pure integer(ip) function nearest_master_node(grid, coords, point, max_distance, excluded) result(best)
    type(bucket_grid_t), intent(in) :: grid
    real(wp), intent(in) :: coords(:, :)
    real(wp), intent(in) :: point(3)
    real(wp), intent(in), optional :: max_distance
    integer, intent(in), optional :: excluded(:)
    integer(ip) :: c(3), lo(3), hi(3), r, ix, iy, iz, a, b, j, node, step_x
    real(wp) :: best_d2, d2, box_d2(3), bound2, slab, rest, limit2
    logical :: any_slab

    best = 0
    best_d2 = huge(1.0_wp)
    limit2 = huge(1.0_wp)
    if (present(max_distance)) limit2 = max_distance**2
    if (grid%n_nodes <= 0) return
    do a = 1, 3
      c(a) = axis_index(grid, a, point(a))
      ! squared distance from the point to the box along each axis (0 inside)
      box_d2(a) = max(0.0_wp, grid%lower(a) - point(a), point(a) - grid%upper(a))**2
    end do

    r = 0
    do
      ! visit the buckets at Chebyshev distance exactly r from bucket c
      lo = max(c - r, 1_ip)
      hi = min(c + r, grid%n_buckets)
      do iz = lo(3), hi(3)
        do iy = lo(2), hi(2)
          if (abs(iz - c(3)) == r .or. abs(iy - c(2)) == r) then
            step_x = 1                          ! a face of the ring: the whole row
          else
            step_x = max(2 * r, 1_ip)           ! inside: only the two ends of the row
          end if
          do ix = c(1) - r, c(1) + r, step_x
            if (ix < 1 .or. ix > grid%n_buckets(1)) cycle
            b = ix + grid%n_buckets(1) * (iy - 1 + grid%n_buckets(2) * (iz - 1))
            do j = grid%bucket_start(b), grid%bucket_start(b + 1) - 1
              node = grid%bucket_nodes(j)
              d2 = sum((coords(:, node) - point)**2)
              if (best == 0 .or. d2 < best_d2 .or. (d2 == best_d2 .and. node < best)) then
                if (present(excluded)) then
                  if (any(excluded == node)) cycle
                end if
                best_d2 = d2
                best = node
              end if
            end do
          end do
        end do
      end do

      ! every unvisited bucket lies in a slab beyond the ring along some axis (and inside the
      ! box along the others): a lower bound on the distance of any node not yet seen
      any_slab = .false.
      bound2 = huge(1.0_wp)
      do a = 1, 3
        rest = sum(box_d2) - box_d2(a)
        if (c(a) + r + 1 <= grid%n_buckets(a)) then
          any_slab = .true.
          slab = max(0.0_wp, grid%lower(a) + real(c(a) + r, wp) * grid%width(a) - point(a) - grid%tolerance)
          bound2 = min(bound2, slab**2 + rest)
        end if
        if (c(a) - r - 1 >= 1) then
          any_slab = .true.
          slab = max(0.0_wp, point(a) - grid%lower(a) - real(c(a) - r - 1, wp) * grid%width(a) - grid%tolerance)
          bound2 = min(bound2, slab**2 + rest)
        end if
      end do
      if (.not. any_slab) exit
      if (best > 0 .and. bound2 > best_d2) exit
      if (bound2 > limit2) exit
      r = r + 1
    end do
    if (best > 0 .and. best_d2 > limit2) best = 0
  end function nearest_master_node

  !> nearest_master_node for m points.
  pure subroutine nearest_master_nodes(grid, coords, m, points, nearest, max_distance)
    type(bucket_grid_t), intent(in) :: grid
    real(wp), intent(in) :: coords(:, :)
    integer(ip), intent(in) :: m
    real(wp), intent(in) :: points(3, m)
    integer(ip), intent(out) :: nearest(m)
    real(wp), intent(in), optional :: max_distance
    integer(ip) :: i
    do i = 1, m
      nearest(i) = nearest_master_node(grid, coords, points(:, i), max_distance)
    end do
  end subroutine nearest_master_nodes

  !> The master nodes whose squared distance from point is at most radius**2, not listed in
  !> excluded: the first size(list) of them (by bucket) in list, their number in count (which may
  !> exceed size(list)). Only the buckets that overlap the box point +- radius are read.
  pure subroutine masters_within(grid, coords, point, radius, list, count, excluded)
    type(bucket_grid_t), intent(in) :: grid
    real(wp), intent(in) :: coords(:, :), point(3), radius
    integer, intent(out) :: list(:), count
    integer, intent(in), optional :: excluded(:)
    integer(ip) :: lo(3), hi(3), ix, iy, iz, a, b, j, node
    real(wp) :: d2, r2
    count = 0
    if (grid%n_nodes <= 0) return
    do a = 1, 3
      lo(a) = axis_index(grid, a, point(a) - radius)
      hi(a) = axis_index(grid, a, point(a) + radius)
    end do
    r2 = radius**2
    do iz = lo(3), hi(3)
      do iy = lo(2), hi(2)
        do ix = lo(1), hi(1)
          b = ix + grid%n_buckets(1) * (iy - 1 + grid%n_buckets(2) * (iz - 1))
          do j = grid%bucket_start(b), grid%bucket_start(b + 1) - 1
            node = grid%bucket_nodes(j)
            d2 = (coords(1, node) - point(1))**2 + (coords(2, node) - point(2))**2 + (coords(3, node) - point(3))**2
            if (.not. (d2 <= r2)) cycle
            if (present(excluded)) then
              if (any(excluded == node)) cycle
            end if
            count = count + 1
            if (count <= size(list)) list(count) = node
          end do
        end do
      end do
    end do
  end subroutine masters_within

  !> nearest_master_node over the n master nodes in list only: the nearest to point, the lower index
  !> on ties, 0 when the list is empty or the nearest lies farther than max_distance. The same
  !> answer as nearest_master_node whenever list holds every master node within max_distance of
  !> point that the search may count (the same arithmetic). With distance, the list is in
  !> ascending order of distance(i), each node's distance from a place `shift` away from point:
  !> a node is then at least distance(i) - shift from point, and the scan stops once that exceeds
  !> the nearest so far or max_distance (by more than slack, the round-off allowance).
  pure integer(ip) function nearest_in_list(coords, point, n, list, max_distance, distance, shift, slack) result(best)
    real(wp), intent(in) :: coords(:, :), point(3), max_distance
    integer, intent(in) :: n, list(n)
    real(wp), intent(in), optional :: distance(n), shift, slack
    integer(ip) :: i, node
    real(wp) :: d2, best_d2, apart
    best = 0
    best_d2 = huge(1.0_wp)
    do i = 1, n
      if (present(distance)) then
        apart = distance(i) - shift - slack
        if (apart > max_distance) exit
        if (best > 0 .and. apart > 0.0_wp) then
          if (apart**2 > best_d2) exit
        end if
      end if
      node = list(i)
      d2 = sum((coords(:, node) - point)**2)
      if (best == 0 .or. d2 < best_d2 .or. (d2 == best_d2 .and. node < best)) then
        best_d2 = d2
        best = node
      end if
    end do
    if (best > 0 .and. best_d2 > max_distance**2) best = 0
  end function nearest_in_list

end module contact_buckets
