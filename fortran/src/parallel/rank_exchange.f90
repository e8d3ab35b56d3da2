!> All-to-all exchanges of lists between the ranks, as the set-up's distributed steps use them:
!> each rank sends a run of values to every rank (MPI_Alltoallv) and receives every rank's run
!> to it, rank after rank.
module rank_exchange
  use mpi_f08
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: exchange_int, exchange_real, offsets

contains

  !> send(displacement of rank r + 1 : ... + counts(r)) to each rank r; recv: what every rank sent
  !> here, rank after rank; recv_counts: how much from each.
  subroutine exchange_int(comm, send, counts, recv, recv_counts)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: send(:), counts(:)
    integer, allocatable, intent(out) :: recv(:), recv_counts(:)
    integer, allocatable :: send_displs(:), recv_displs(:)
    call exchange_counts(comm, counts, recv_counts, send_displs, recv_displs)
    allocate (recv(max(sum(recv_counts), 0)))
    call MPI_Alltoallv(send, counts, send_displs, MPI_INTEGER, recv, recv_counts, recv_displs, MPI_INTEGER, comm)
  end subroutine exchange_int

  !> As exchange_int for reals (the received counts are not returned).
  subroutine exchange_real(comm, send, counts, recv)
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: send(:)
    integer, intent(in) :: counts(:)
    real(wp), allocatable, intent(out) :: recv(:)
    integer, allocatable :: recv_counts(:), send_displs(:), recv_displs(:)
    call exchange_counts(comm, counts, recv_counts, send_displs, recv_displs)
    allocate (recv(max(sum(recv_counts), 0)))
    call MPI_Alltoallv(send, counts, send_displs, MPI_DOUBLE_PRECISION, recv, recv_counts, recv_displs, &
                       MPI_DOUBLE_PRECISION, comm)
  end subroutine exchange_real

  !> The counts each rank sends here, and both sides' displacements.
  subroutine exchange_counts(comm, counts, recv_counts, send_displs, recv_displs)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: counts(:)
    integer, allocatable, intent(out) :: recv_counts(:), send_displs(:), recv_displs(:)
    allocate (recv_counts(size(counts)), send_displs(size(counts)), recv_displs(size(counts)))
    call MPI_Alltoall(counts, 1, MPI_INTEGER, recv_counts, 1, MPI_INTEGER, comm)
    call offsets(counts, send_displs)
    call offsets(recv_counts, recv_displs)
  end subroutine exchange_counts

  !> Exclusive prefix sums: displs(r) = counts(1) + ... + counts(r - 1).
  pure subroutine offsets(counts, displs)
    integer, intent(in) :: counts(:)
    integer, intent(out) :: displs(:)
    integer :: r
    displs(1) = 0
    do r = 2, size(counts)
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
  end subroutine offsets

end module rank_exchange
