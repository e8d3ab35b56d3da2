!> Sorting integers in place: a few of them (the ranks that share a node, the four nodes of an
!> element) by insertion sort, the fastest for such short lists; many of them (a rank's node ids)
!> by a bottom-up merge sort, O(n log n).
module integer_sort
  implicit none
  private
  public :: sort_ascending, merge_sort_ascending, sorted_position, distinct_ascending

contains

  pure subroutine sort_ascending(a)
    integer, intent(inout) :: a(:)
    integer :: i, j, key
    do i = 2, size(a)
      key = a(i)
      j = i - 1
      do while (j >= 1)
        if (a(j) <= key) exit
        a(j + 1) = a(j)
        j = j - 1
      end do
      a(j + 1) = key
    end do
  end subroutine sort_ascending

  pure subroutine merge_sort_ascending(a)
    integer, intent(inout) :: a(:)
    integer, allocatable :: work(:)
    integer :: n, width, lo, mid, hi, i, j, k
    logical :: in_a
    n = size(a)
    allocate (work(n))
    width = 1
    in_a = .true.
    do while (width < n)
      do lo = 1, n, 2 * width
        mid = min(lo + width - 1, n)
        hi = min(lo + 2 * width - 1, n)
        i = lo
        j = mid + 1
        do k = lo, hi
          if (in_a) then
            if (j > hi .or. (i <= mid .and. a(min(i, n)) <= a(min(j, n)))) then
              work(k) = a(i)
              i = i + 1
            else
              work(k) = a(j)
              j = j + 1
            end if
          else
            if (j > hi .or. (i <= mid .and. work(min(i, n)) <= work(min(j, n)))) then
              a(k) = work(i)
              i = i + 1
            else
              a(k) = work(j)
              j = j + 1
            end if
          end if
        end do
      end do
      in_a = .not. in_a
      width = 2 * width
    end do
    if (.not. in_a) a = work
  end subroutine merge_sort_ascending

  !> Place of value in the ascending list a, which holds it (binary search).
  pure integer function sorted_position(a, value) result(lo)
    integer, intent(in) :: a(:), value
    integer :: hi, mid
    lo = 1
    hi = size(a)
    do while (lo < hi)
      mid = (lo + hi) / 2
      if (a(mid) < value) then
        lo = mid + 1
      else
        hi = mid
      end if
    end do
  end function sorted_position

  !> The distinct values, ascending.
  pure function distinct_ascending(values) result(distinct)
    integer, intent(in) :: values(:)
    integer, allocatable :: distinct(:)
    integer :: k, n
    distinct = values
    call merge_sort_ascending(distinct)
    n = 0
    do k = 1, size(distinct)
      if (n > 0) then
        if (distinct(k) == distinct(n)) cycle
      end if
      n = n + 1
      distinct(n) = distinct(k)
    end do
    distinct = distinct(1:n)
  end function distinct_ascending

end module integer_sort
