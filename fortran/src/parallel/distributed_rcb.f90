!> Recursive coordinate bisection over distributed centroids (issue 19, item 5): the owners of
!> domain_decomposition's rcb_partition (docs/theory.md, "Parallel design": each set of elements
!> meant for q ranks cut across the longest side of its bounding box, the lowest axis on a tie;
!> the first n floor(q / 2) / q of the set in (coordinate, element id) order to the first
!> floor(q / 2) ranks) without any rank holding every centroid. Each rank keeps the centroids of
!> the elements it read; the sets of a level are known on every rank from the rank ranges alone;
!> per level, the sets' counts and boxes are reductions, and the cut of each set is a distributed
!> selection of its n_low-th element in (coordinate, id) order: every rank proposes the median of
!> its remaining candidates, the weighted median of the proposals (an MPI_Allgatherv; a rank
!> proposes only for the sets it has candidates in) is counted against (an MPI_Allreduce) and the
!> candidates shrink to one side, until the proposal is the n_low-th. Each round removes at least
!> a quarter of a set's candidates: O(log n) rounds a level, log2 p levels. Memory per rank: its
!> elements, a count per set, and 4 numbers per proposal of all ranks in a round.
module distributed_rcb
  use mpi_f08
  use paradyn_kinds, only: wp, i8
  implicit none
  private
  public :: rcb_owners

  !> An element's key along an axis: (coordinate, id), ordered lexicographically.
  type :: key_t
    real(wp) :: value = 0
    integer :: id = 0
  end type key_t

contains

  !> owner(k): the rank (0-based) that rcb_partition gives element ids(k), centroid centroids(:, k).
  !> Collective; every element of the mesh is held by exactly one rank.
  subroutine rcb_owners(comm, ids, centroids, owner)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: ids(:)
    real(wp), intent(in) :: centroids(:, :)
    integer, intent(out) :: owner(:)
    integer, allocatable :: set_rank0(:), set_q(:), member(:)
    integer :: n_ranks, s
    call MPI_Comm_size(comm, n_ranks)
    set_rank0 = [0]
    set_q = [max(n_ranks, 1)]
    allocate (member(size(ids)), source=1)   ! each element's set at this level
    do while (any(set_q > 1))
      call cut_level(comm, ids, centroids, set_rank0, set_q, member)
      ! the next level's sets: each set for q ranks becomes its lower and upper half
      set_rank0 = [(set_rank0(s), set_rank0(s) + set_q(s) / 2, s = 1, size(set_q))]
      set_q = [(set_q(s) / 2, set_q(s) - set_q(s) / 2, s = 1, size(set_q))]
      ! sets of one rank stay as they are (their upper half is empty): drop the empty halves
      member = renumbered(member, set_q)
      call drop_empty(set_rank0, set_q)
    end do
    owner = set_rank0(member)
  end subroutine rcb_owners

  !> After the halving, set s became sets 2 s - 1 and 2 s; member(k) already names its half.
  !> Renumber to the list without the empty halves (q = 0).
  pure function renumbered(member, set_q) result(out)
    integer, intent(in) :: member(:), set_q(:)
    integer :: out(size(member))
    integer :: place(size(set_q)), s, n
    n = 0
    do s = 1, size(set_q)
      if (set_q(s) > 0) n = n + 1
      place(s) = n
    end do
    out = place(member)
  end function renumbered

  pure subroutine drop_empty(set_rank0, set_q)
    integer, allocatable, intent(inout) :: set_rank0(:), set_q(:)
    set_rank0 = pack(set_rank0, set_q > 0)
    set_q = pack(set_q, set_q > 0)
  end subroutine drop_empty

  !> One level: each set with q > 1 is cut; member(k) becomes 2 s - 1 (lower half) or 2 s (upper
  !> half) for an element of set s (a set of one rank, whose halves are q = 0 and q = 1, keeps its
  !> elements in its upper half).
  subroutine cut_level(comm, ids, centroids, set_rank0, set_q, member)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: ids(:), set_rank0(:), set_q(:)
    real(wp), intent(in) :: centroids(:, :)
    integer, intent(inout) :: member(:)
    integer(i8), allocatable :: counts(:), n_low(:)
    real(wp), allocatable :: low(:, :), high(:, :), extent(:, :)
    integer, allocatable :: axis(:), order(:), start(:)
    type(key_t), allocatable :: keys(:), pivot(:)
    integer :: s, k, n_sets, j
    n_sets = size(set_q)
    allocate (counts(n_sets), source=0_i8)
    allocate (low(3, n_sets), source=huge(1.0_wp))
    allocate (high(3, n_sets), source=-huge(1.0_wp))
    do k = 1, size(ids)
      s = member(k)
      counts(s) = counts(s) + 1
      low(:, s) = min(low(:, s), centroids(:, k))
      high(:, s) = max(high(:, s), centroids(:, k))
    end do
    call MPI_Allreduce(MPI_IN_PLACE, counts, n_sets, MPI_INTEGER8, MPI_SUM, comm)
    call MPI_Allreduce(MPI_IN_PLACE, low, 3 * n_sets, MPI_DOUBLE_PRECISION, MPI_MIN, comm)
    call MPI_Allreduce(MPI_IN_PLACE, high, 3 * n_sets, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
    allocate (axis(n_sets), n_low(n_sets), extent(3, n_sets))
    do s = 1, n_sets
      axis(s) = 1
      n_low(s) = (counts(s) * (set_q(s) / 2)) / set_q(s)   ! 0 for one rank: its set stays whole
      if (counts(s) == 0) cycle
      extent(:, s) = high(:, s) - low(:, s)
      do j = 2, 3
        if (extent(j, s) > extent(axis(s), s)) axis(s) = j
      end do
    end do
    ! this rank's members of each set, sorted by their key along the set's axis
    allocate (keys(size(ids)))
    do k = 1, size(ids)
      keys(k) = key_t(centroids(axis(member(k)), k), ids(k))
    end do
    call group_and_sort(member, keys, n_sets, order, start)
    call select_pivots(comm, keys(order), start, n_low, pivot)
    do k = 1, size(ids)
      s = member(k)
      member(k) = 2 * s
      if (n_low(s) > 0) then
        if (.not. after(keys(k), pivot(s))) member(k) = 2 * s - 1
      end if
    end do
  end subroutine cut_level

  !> order: the elements grouped by set, each group ascending by key; start(s): where set s's
  !> group starts in order (start(n_sets + 1) = size + 1).
  pure subroutine group_and_sort(member, keys, n_sets, order, start)
    integer, intent(in) :: member(:), n_sets
    type(key_t), intent(in) :: keys(:)
    integer, allocatable, intent(out) :: order(:), start(:)
    integer, allocatable :: fill(:)
    integer :: k, s
    allocate (start(n_sets + 1), source=0)
    do k = 1, size(member)
      start(member(k) + 1) = start(member(k) + 1) + 1
    end do
    start(1) = 1
    do s = 1, n_sets
      start(s + 1) = start(s + 1) + start(s)
    end do
    fill = start(1:n_sets)
    allocate (order(size(member)))
    do k = 1, size(member)
      order(fill(member(k))) = k
      fill(member(k)) = fill(member(k)) + 1
    end do
    do s = 1, n_sets
      call sort_keys(order(start(s):start(s + 1) - 1), keys)
    end do
  end subroutine group_and_sort

  !> Merge sort of the positions by keys(positions).
  pure recursive subroutine sort_keys(positions, keys)
    integer, intent(inout) :: positions(:)
    type(key_t), intent(in) :: keys(:)
    integer, allocatable :: left(:), right(:)
    integer :: half, i, j, k
    if (size(positions) < 2) return
    half = size(positions) / 2
    left = positions(1:half)
    right = positions(half + 1:)
    call sort_keys(left, keys)
    call sort_keys(right, keys)
    i = 1
    j = 1
    do k = 1, size(positions)
      if (j > size(right)) then
        positions(k) = left(i)
        i = i + 1
      else if (i > size(left)) then
        positions(k) = right(j)
        j = j + 1
      else if (after(keys(left(i)), keys(right(j)))) then
        positions(k) = right(j)
        j = j + 1
      else
        positions(k) = left(i)
        i = i + 1
      end if
    end do
  end subroutine sort_keys

  !> Whether a comes after b in (value, id) order.
  pure logical function after(a, b)
    type(key_t), intent(in) :: a, b
    after = a%value > b%value .or. (a%value == b%value .and. a%id > b%id)
  end function after

  !> For each set s with 0 < n_low(s): pivot(s), the key of its n_low(s)-th element over all ranks
  !> in key order. sorted: this rank's keys grouped by set (start), each group ascending.
  subroutine select_pivots(comm, sorted, start, n_low, pivot)
    type(MPI_Comm), intent(in) :: comm
    type(key_t), intent(in) :: sorted(:)
    integer, intent(in) :: start(:)
    integer(i8), intent(in) :: n_low(:)
    type(key_t), allocatable, intent(out) :: pivot(:)
    integer, allocatable :: first(:), last(:)
    integer(i8), allocatable :: below(:), at_most(:)
    real(wp), allocatable :: proposals(:, :)
    logical, allocatable :: done(:)
    integer :: n_sets, s
    n_sets = size(n_low)
    allocate (pivot(n_sets), done(n_sets), below(n_sets), at_most(n_sets))
    done = n_low <= 0
    below = 0   ! elements of the set known to come before every candidate, over all ranks
    first = start(1:n_sets)          ! this rank's candidates of set s: sorted(first(s):last(s))
    last = start(2:n_sets + 1) - 1
    do while (.not. all(done))
      call gather_proposals(comm, sorted, first, last, done, proposals)
      call weighted_medians(proposals, done, pivot)
      at_most = 0
      do s = 1, n_sets
        if (.not. done(s)) at_most(s) = count_at_most(sorted(first(s):last(s)), pivot(s))
      end do
      call MPI_Allreduce(MPI_IN_PLACE, at_most, n_sets, MPI_INTEGER8, MPI_SUM, comm)
      do s = 1, n_sets
        if (done(s)) cycle
        if (below(s) + at_most(s) == n_low(s)) then
          done(s) = .true.
        else if (below(s) + at_most(s) > n_low(s)) then   ! the n_low-th comes before the pivot
          last(s) = first(s) + int(count_before(sorted(first(s):last(s)), pivot(s))) - 1
        else                                              ! after it: the pivot and before go
          below(s) = below(s) + at_most(s)
          first(s) = first(s) + int(count_at_most(sorted(first(s):last(s)), pivot(s)))
        end if
      end do
    end do
  end subroutine select_pivots

  !> Every rank's proposals (set, value, id, weight) for the sets not done where it has candidates:
  !> the median of its candidates, weighted by their count (MPI_Allgatherv: a rank sends only the
  !> sets its elements are in). proposals (4, all ranks' proposals), rank after rank.
  subroutine gather_proposals(comm, sorted, first, last, done, proposals)
    type(MPI_Comm), intent(in) :: comm
    type(key_t), intent(in) :: sorted(:)
    integer, intent(in) :: first(:), last(:)
    logical, intent(in) :: done(:)
    real(wp), allocatable, intent(out) :: proposals(:, :)
    real(wp), allocatable :: mine(:, :)
    integer, allocatable :: counts(:), displs(:)
    integer :: n_ranks, s, n, m, r
    call MPI_Comm_size(comm, n_ranks)
    allocate (mine(4, count(.not. done .and. last >= first)))
    n = 0
    do s = 1, size(done)
      if (done(s) .or. last(s) < first(s)) cycle
      n = n + 1
      m = (first(s) + last(s)) / 2
      mine(:, n) = [real(s, wp), sorted(m)%value, real(sorted(m)%id, wp), real(last(s) - first(s) + 1, wp)]
    end do
    allocate (counts(n_ranks), displs(n_ranks))
    call MPI_Allgather(4 * n, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, comm)
    displs(1) = 0
    do r = 2, n_ranks
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
    allocate (proposals(4, sum(counts) / 4))
    call MPI_Allgatherv(mine, 4 * n, MPI_DOUBLE_PRECISION, proposals, counts, displs, MPI_DOUBLE_PRECISION, comm)
  end subroutine gather_proposals

  !> pivot(s) for each set not done: the proposal whose cumulative weight, in key order, first
  !> reaches half the weight of the set's proposals.
  pure subroutine weighted_medians(proposals, done, pivot)
    real(wp), intent(in) :: proposals(:, :)
    logical, intent(in) :: done(:)
    type(key_t), intent(inout) :: pivot(:)
    type(key_t), allocatable :: keys(:)
    integer, allocatable :: start(:), order(:), fill(:)
    integer :: k, s, j
    real(wp) :: total, so_far
    allocate (start(size(done) + 1), source=0)
    do k = 1, size(proposals, 2)   ! the proposals bucketed by set
      s = nint(proposals(1, k))
      start(s + 1) = start(s + 1) + 1
    end do
    start(1) = 1
    do s = 1, size(done)
      start(s + 1) = start(s + 1) + start(s)
    end do
    fill = start(1:size(done))
    allocate (order(size(proposals, 2)), keys(size(proposals, 2)))
    do k = 1, size(proposals, 2)
      s = nint(proposals(1, k))
      order(fill(s)) = k
      fill(s) = fill(s) + 1
      keys(k) = key_t(proposals(2, k), nint(proposals(3, k)))
    end do
    do s = 1, size(done)
      if (done(s)) cycle
      associate (mine => order(start(s):start(s + 1) - 1))
        call sort_keys(mine, keys)
        total = sum(proposals(4, mine))
        so_far = 0.0_wp
        do j = 1, size(mine)
          so_far = so_far + proposals(4, mine(j))
          if (2.0_wp * so_far >= total) exit
        end do
        pivot(s) = keys(mine(min(j, size(mine))))
      end associate
    end do
  end subroutine weighted_medians

  !> How many of the ascending keys come at or before x (binary search).
  pure integer(i8) function count_at_most(keys, x) result(n)
    type(key_t), intent(in) :: keys(:)
    type(key_t), intent(in) :: x
    integer :: lo, hi, mid
    lo = 0
    hi = size(keys)   ! keys(1:lo) <= x < keys(hi + 1:)
    do while (lo < hi)
      mid = (lo + hi + 1) / 2
      if (after(keys(mid), x)) then
        hi = mid - 1
      else
        lo = mid
      end if
    end do
    n = lo
  end function count_at_most

  !> How many of the ascending keys come strictly before x.
  pure integer(i8) function count_before(keys, x) result(n)
    type(key_t), intent(in) :: keys(:)
    type(key_t), intent(in) :: x
    n = count_at_most(keys, x)
    if (n > 0) then
      if (keys(n)%id == x%id .and. keys(n)%value == x%value) n = n - 1
    end if
  end function count_before

end module distributed_rcb
