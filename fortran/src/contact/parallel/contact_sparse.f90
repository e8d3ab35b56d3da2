!> The sparse exchange of local contact (contact_neighbours): each rank sends a message to the
!> ranks it chooses, and none knows in advance who sends to it. Synchronous sends, probes for
!> whatever arrives, and a non-blocking barrier entered once this rank's sends are matched: when
!> the barrier completes every message has been received (the NBX pattern).
module contact_sparse
  use mpi_f08
  use paradyn_kinds, only: wp, i8
  use traffic_counter, only: traffic_t, count_messages, count_allreduce
  implicit none
  private
  public :: sparse_exchange

  integer, parameter :: sparse_tag = 720

contains

  !> A sparse exchange (sends, probes, a non-blocking barrier): buffer(start(i) : start(i + 1) - 1)
  !> goes to rank dest(i); message i received came from sources(i), from received(rstart(i)) on.
  !> Two tags, alternating, keep a fast rank's next exchange apart from this one. Collective.
  subroutine sparse_exchange(comm, n_ranks, round, dest, start, buffer, sources, rstart, received, traffic)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_ranks
    integer, intent(inout) :: round   !< exchanges so far
    integer, intent(in) :: dest(:), start(:)
    real(wp), intent(in), asynchronous :: buffer(:)
    integer, allocatable, intent(out) :: sources(:), rstart(:)
    real(wp), allocatable, intent(out) :: received(:)
    type(traffic_t), intent(inout) :: traffic
    type(MPI_Request) :: requests(size(dest)), barrier
    type(MPI_Status) :: status
    real(wp), allocatable :: grown(:)
    logical :: arrived, sent, done, barrier_on
    integer :: i, tag, n, at
    tag = sparse_tag + mod(round, 2)
    round = round + 1
    do i = 1, size(dest)
      call MPI_Issend(buffer(start(i):start(i + 1) - 1), start(i + 1) - start(i), MPI_DOUBLE_PRECISION, dest(i), &
                      tag, comm, requests(i))
    end do
    allocate (sources(0), rstart(1), received(1024))
    rstart(1) = 1
    at = 0
    barrier_on = .false.
    do
      call MPI_Iprobe(MPI_ANY_SOURCE, tag, comm, arrived, status)
      if (arrived) then
        call MPI_Get_count(status, MPI_DOUBLE_PRECISION, n)
        if (at + n > size(received)) then
          allocate (grown(max(2 * size(received), at + n)))
          grown(1:at) = received(1:at)
          call move_alloc(grown, received)
        end if
        call MPI_Recv(received(at + 1:at + n), n, MPI_DOUBLE_PRECISION, status%MPI_SOURCE, tag, comm, &
                      MPI_STATUS_IGNORE)
        sources = [sources, status%MPI_SOURCE]
        at = at + n
        rstart = [rstart, at + 1]
      else if (barrier_on) then
        call MPI_Test(barrier, done, MPI_STATUS_IGNORE)
        if (done) exit
      else
        call MPI_Testall(size(dest), requests, sent, MPI_STATUSES_IGNORE)
        if (sent) then
          call MPI_Ibarrier(comm, barrier)
          barrier_on = .true.
        end if
      end if
    end do
    call count_messages(traffic, size(dest), int(8 * (start(size(dest) + 1) - 1), i8), int(8 * at, i8))
    call count_allreduce(traffic, 0_i8, n_ranks)   ! the barrier
  end subroutine sparse_exchange

end module contact_sparse
