!> Work sharing among the OpenMP threads of a rank: static ranges with stealing.
!>
!> Each thread starts on its own contiguous range of the items, the range schedule(static) would
!> give it, so that it touches the same memory step after step. A thread that has emptied its
!> range then takes the items left in the other threads' ranges, one at a time, so that a thread
!> the machine slows down for a while does not hold the others waiting at the end of the region
!> (docs/performance.md, "Threads: static ranges with stealing"). Which thread computes an item
!> must not change its result: callers write each item's result to the item's own place.
module work_queues
  implicit none
  private
  public :: queues_start, queues_take

  integer, parameter :: line = 16   !< default integers per 64-byte cache line

  !> One counter per thread's range, each on a cache line of its own so that the threads do not
  !> pull each other's counters around while they work on their own ranges.
  type, public :: work_queues_t
    integer, allocatable :: next(:, :)   !< next(1, t): next item of thread t's range
    integer, allocatable :: last(:)      !< last(t): last item of thread t's range
  end type work_queues_t

contains

  !> Deal items 1..n_items into n_threads contiguous ranges (sizes differing by at most one).
  !> Called outside the parallel region, before each loop over the items.
  subroutine queues_start(queues, n_items, n_threads)
    type(work_queues_t), intent(inout) :: queues
    integer, intent(in) :: n_items, n_threads
    integer :: t
    if (.not. allocated(queues%last)) then
      allocate (queues%next(line, n_threads), queues%last(n_threads))
    else if (size(queues%last) /= n_threads) then
      deallocate (queues%next, queues%last)
      allocate (queues%next(line, n_threads), queues%last(n_threads))
    end if
    do t = 1, n_threads
      queues%next(1, t) = int(int(t - 1, 8) * n_items / n_threads) + 1
      queues%last(t) = int(int(t, 8) * n_items / n_threads)
    end do
  end subroutine queues_start

  !> The next item for thread me (1-based), or 0 when every range is empty. Thread me empties
  !> its own range first, then the following threads' ranges in turn; emptied (private to the
  !> thread, 0 at the start of the loop) counts the ranges it has found empty.
  integer function queues_take(queues, me, emptied) result(item)
    type(work_queues_t), intent(inout) :: queues
    integer, intent(in) :: me
    integer, intent(inout) :: emptied
    integer :: t, n_ranges
    n_ranges = size(queues%last)
    do while (emptied < n_ranges)
      t = modulo(me - 1 + emptied, n_ranges) + 1
      !$omp atomic capture
      item = queues%next(1, t)
      queues%next(1, t) = queues%next(1, t) + 1
      !$omp end atomic
      if (item <= queues%last(t)) return
      emptied = emptied + 1
    end do
    item = 0
  end function queues_take

end module work_queues
