!> The ties of tiebreak contacts that failed this step (contact_stages marks them in the records
!> of the candidates each rank searched) added to the contact's list of failed ties on every rank:
!> one allgather of their keys (tie_keys) and an ordered union, so that the list is the same on
!> any layout. Collective; nothing to do (no message) where no definition is a tiebreak.
module tie_failures
  use mpi_f08
  use paradyn_kinds, only: i8
  use paradyn_schema, only: contact_kind_tiebreak
  use contact_interface, only: contact_t
  use tie_keys, only: tie_key, merge_keys
  implicit none
  private
  public :: gather_tie_failures, has_tiebreak

contains

  !> Whether a definition of c can fail by its ties.
  logical function has_tiebreak(c)
    type(contact_t), intent(in) :: c
    has_tiebreak = .false.
    if (allocated(c%passes)) has_tiebreak = any(c%passes%kind == contact_kind_tiebreak)
  end function has_tiebreak

  subroutine gather_tie_failures(comm, c)
    type(MPI_Comm), intent(in) :: comm
    type(contact_t), intent(inout) :: c
    integer(i8), allocatable :: mine(:), all(:)
    integer, allocatable :: counts(:), displs(:)
    integer :: k, n, n_ranks, r
    if (.not. allocated(c%failed_ties)) allocate (c%failed_ties(0))
    if (.not. has_tiebreak(c)) return
    allocate (mine(0))
    if (allocated(c%record_failed) .and. c%last >= c%first) then
      do k = c%first, c%last
        if (.not. c%record_failed(k)) cycle
        associate (pass => c%passes(c%candidates(3, k)))
        mine = [mine, tie_key(pass%pair, pass%slaves(c%candidates(1, k)))]
        end associate
      end do
    end if
    call MPI_Comm_size(comm, n_ranks)
    allocate (counts(n_ranks), displs(n_ranks))
    n = size(mine)
    call MPI_Allgather(n, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, comm)
    displs(1) = 0
    do r = 2, n_ranks
      displs(r) = displs(r - 1) + counts(r - 1)
    end do
    if (sum(counts) == 0) return
    allocate (all(sum(counts)))
    call MPI_Allgatherv(mine, n, MPI_INTEGER8, all, counts, displs, MPI_INTEGER8, comm)
    c%failed_ties = merge_keys(c%failed_ties, all)
  end subroutine gather_tie_failures

end module tie_failures
