!> Sorting a few integers in place (the ranks that share a node, the four nodes of an element):
!> insertion sort, the fastest for such short lists.
module integer_sort
  implicit none
  private
  public :: sort_ascending

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

end module integer_sort
