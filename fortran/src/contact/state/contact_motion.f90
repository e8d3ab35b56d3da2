!> The per-step check of how far the contact nodes have moved since the last bucket sort (an
!> automatic sort falls once one has moved a tenth of the smallest bucket: contact_sort_due). No MPI.
module contact_motion
  use paradyn_kinds, only: wp
  use contact_interface, only: contact_t, clock_seconds
  use contact_slots, only: slot_of
  implicit none
  private
  public :: contact_movement

contains

  !> The largest distance that contact nodes have moved since the last sort: the given nodes
  !> (members, at columns `columns` of x), or without them every contact node at c%x. A
  !> maximum is exact in any order, so the threads and ranks may share it; squared distances
  !> and one square root at the end (norm2's scaling against overflow costs more than the rest).
  subroutine contact_movement(c, moved, clock, members, columns, x)
    type(contact_t), intent(inout) :: c
    real(wp), intent(out) :: moved
    procedure(clock_seconds) :: clock
    integer, intent(in), optional :: members(:), columns(:)
    real(wp), intent(in), optional :: x(:, :)
    real(wp) :: t0
    integer :: i, j, k, n
    t0 = clock()
    moved = 0.0_wp
    if (present(members) .and. present(columns) .and. present(x)) then
      n = size(members)
      if (c%member_sort /= c%n_sorts .or. .not. allocated(c%member_at)) then   ! a sort since
        c%member_at = columns
        c%member_at_sort = c%x_at_sort(:, [(slot_of(c, members(i)), i = 1, n)])
        c%member_sort = c%n_sorts
        c%member_run = .false.
        if (n > 0) c%member_run = all(c%member_at == [(c%member_at(1) + i - 1, i = 1, n)])
      end if
      if (c%member_run) then
        ! the members' columns are one run (all the nodes are contact nodes): contiguous reads
        k = c%member_at(1) - 1
        !$omp parallel do schedule(static) reduction(max:moved)
        do i = 1, n
          moved = max(moved, (x(1, k + i) - c%member_at_sort(1, i))**2 + (x(2, k + i) - c%member_at_sort(2, i))**2 &
                             + (x(3, k + i) - c%member_at_sort(3, i))**2)
        end do
        !$omp end parallel do
        moved = sqrt(moved)
        c%time_sort = c%time_sort + clock() - t0
        return
      end if
      !$omp parallel do schedule(static) private(j) reduction(max:moved)
      do i = 1, n
        j = c%member_at(i)
        moved = max(moved, (x(1, j) - c%member_at_sort(1, i))**2 + (x(2, j) - c%member_at_sort(2, i))**2 &
                           + (x(3, j) - c%member_at_sort(3, i))**2)
      end do
      !$omp end parallel do
    else if (c%sort_interval == 0 .and. c%last_sort >= 0) then   ! else contact_sort_due does not ask
      !$omp parallel do schedule(static) reduction(max:moved)
      do k = 1, size(c%x, 2)
        moved = max(moved, (c%x(1, k) - c%x_at_sort(1, k))**2 + (c%x(2, k) - c%x_at_sort(2, k))**2 &
                           + (c%x(3, k) - c%x_at_sort(3, k))**2)
      end do
      !$omp end parallel do
    end if
    moved = sqrt(moved)
    c%time_sort = c%time_sort + clock() - t0
  end subroutine contact_movement

end module contact_motion
