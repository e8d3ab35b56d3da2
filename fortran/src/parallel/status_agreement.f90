!> One verdict for all ranks: a check that fails on one rank (a node without mass in its part of
!> the mesh, say) must stop every rank, with that rank's message, or the others wait forever in
!> the next collective (issue 17).
module status_agreement
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Allreduce, MPI_Bcast, MPI_INTEGER, MPI_CHARACTER, MPI_MAX, &
                     MPI_MIN
  implicit none
  private
  public :: agree_on_status

contains

  !> Every rank gets the worst status of all ranks (the largest code) and the message of the
  !> lowest rank that has it. Collective over comm.
  subroutine agree_on_status(comm, status, message)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(inout) :: status
    character(len=*), intent(inout) :: message
    integer :: worst, rank, mine, source
    call MPI_Allreduce(status, worst, 1, MPI_INTEGER, MPI_MAX, comm)
    if (worst == 0) return
    call MPI_Comm_rank(comm, rank)
    mine = merge(rank, huge(1), status == worst)
    call MPI_Allreduce(mine, source, 1, MPI_INTEGER, MPI_MIN, comm)
    call MPI_Bcast(message, len(message), MPI_CHARACTER, source, comm)
    status = worst
  end subroutine agree_on_status

end module status_agreement
