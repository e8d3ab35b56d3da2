!> The global search between bucket sorts without the bucket rings: each slave keeps a short list
!> of the master nodes around the place where it last searched the grid. The search reads the
!> master positions of the last sort, so while the grid is not built again and the slave stays
!> within `margin` of that place, every master node within the search radius of the slave is on
!> its list (the list holds those within the radius plus the margin), and the nearest of the list
!> is nearest_master_node's answer: the same arithmetic, the same tie rule (the lower index). A
!> slave that has moved farther, a grid built since, or a list longer than its room sends the
!> slave back to the grid. Each slave's list is its own, so threads that search different slaves
!> share nothing. The list is kept in ascending order of distance from where it was made, so a search
!> stops at the first node that cannot be nearer than the nearest so far (triangle inequality).
!> Memory: 2 room + 5 numbers per slave, O(contact nodes).
module nearest_cache
  use paradyn_kinds, only: wp, ip
  use contact_buckets, only: bucket_grid_t, nearest_master_node, masters_within, nearest_in_list
  implicit none
  private
  public :: near_lists_t, near_lists_setup, nearest_master_listed, near_list_room

  integer, parameter :: near_list_room = 32    !< master nodes a slave's list holds

  !> Each slave's list of nearby master nodes (index into the pass's masters).
  type :: near_lists_t
    integer, allocatable :: masters(:, :)      !< (near_list_room, n_slaves), nearest to the centre first
    real(wp), allocatable :: distance(:, :)    !< (near_list_room, n_slaves) their distances from the centre
    integer, allocatable :: count(:)           !< masters on the list; near_list_room + 1: did not fit
    integer, allocatable :: built(:)           !< the grid's build count when the list was made, 0 never
    real(wp), allocatable :: centre(:, :)      !< (3, n_slaves) where the slave stood then
  end type near_lists_t

contains

  !> Empty lists for n_slaves slaves.
  pure subroutine near_lists_setup(n_slaves, lists)
    integer, intent(in) :: n_slaves
    type(near_lists_t), intent(out) :: lists
    allocate (lists%masters(near_list_room, n_slaves), lists%count(n_slaves), lists%built(n_slaves), &
              source=0)
    allocate (lists%centre(3, n_slaves), lists%distance(near_list_room, n_slaves), source=0.0_wp)
  end subroutine near_lists_setup

  !> nearest_master_node(grid, coords, point, max_distance, excluded) for slave j: from the slave's
  !> list when it still holds, else from the grid, making a new list around point that holds while
  !> the slave stays within margin of it.
  pure subroutine nearest_master_listed(lists, j, grid, coords, point, max_distance, margin, found, excluded)
    type(near_lists_t), intent(inout) :: lists
    integer, intent(in) :: j
    type(bucket_grid_t), intent(in) :: grid
    real(wp), intent(in) :: coords(:, :), point(3), max_distance, margin
    integer(ip), intent(out) :: found
    integer, intent(in), optional :: excluded(:)
    real(wp) :: radius, slack, moved2
    integer :: count
    if (.not. all(abs(point) <= huge(1.0_wp))) then      ! NaN or infinite: no list
      found = nearest_master_node(grid, coords, point, max_distance, excluded)
      return
    end if
    moved2 = (point(1) - lists%centre(1, j))**2 + (point(2) - lists%centre(2, j))**2 &
             + (point(3) - lists%centre(3, j))**2
    if (lists%built(j) /= grid%builds .or. .not. (moved2 <= margin**2)) then
      ! with allowances for the round-off of the distances against both places
      radius = (max_distance + margin) * (1.0_wp + 1.0e-12_wp) + 2.0_wp * grid%tolerance
      call masters_within(grid, coords, point, radius, lists%masters(:, j), count, excluded)
      lists%count(j) = min(count, near_list_room + 1)
      lists%built(j) = grid%builds
      lists%centre(:, j) = point
      moved2 = 0.0_wp
      if (count <= near_list_room) call by_distance(lists%masters(1:count, j), lists%distance(1:count, j))
    end if
    if (lists%count(j) > near_list_room) then
      found = nearest_master_node(grid, coords, point, max_distance, excluded)
    else
      ! the slave is `shift` from the centre, so a master is at least its distance less that from it
      slack = 1.0e-12_wp * (max_distance + margin) + 2.0_wp * grid%tolerance
      found = nearest_in_list(coords, point, lists%count(j), lists%masters(:, j), max_distance, &
                              lists%distance(:, j), sqrt(moved2), slack)
    end if

  contains

    !> The list in ascending order of distance from point (insertion: at most near_list_room).
    pure subroutine by_distance(masters, distance)
      integer, intent(inout) :: masters(:)
      real(wp), intent(out) :: distance(:)
      integer :: i, k, m
      real(wp) :: d
      do i = 1, size(masters)
        m = masters(i)
        d = sqrt(sum((coords(:, m) - point)**2))
        k = i
        do while (k > 1)
          if (.not. (distance(k - 1) > d)) exit
          distance(k) = distance(k - 1)
          masters(k) = masters(k - 1)
          k = k - 1
        end do
        distance(k) = d
        masters(k) = m
      end do
    end subroutine by_distance
  end subroutine nearest_master_listed

end module nearest_cache
