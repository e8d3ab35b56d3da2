!> Sums over the elements of the model taken in element order across the ranks, so that they are
!> bitwise those of one rank adding every element in turn, whatever the layout (issue 19, item 5:
!> no rank holds the global mesh). Each element's terms go to the home of its id
!> (block_owner(e, n_elements, n_ranks), where the blocks layout already holds them); the homes
!> add in rank order, each continuing the running sums of the rank before (n_ranks messages).
module ordered_sums
  use mpi_f08
  use paradyn_kinds, only: wp
  use domain_decomposition, only: block_owner
  use deck_directory, only: block_range
  use rank_exchange, only: exchange_int, exchange_real
  use mass_scaling, only: mass_scaling_t
  implicit none
  private
  public :: mass_scaling_totals

contains

  !> The model's mass, the added mass per part and in all, the smallest element step and the
  !> scaled count of mass_scaling_setup's per-element terms (elements: the global ids of ms's
  !> rows, parts: their parts). Collective; every rank gets the same totals.
  subroutine mass_scaling_totals(comm, n_elements, elements, parts, ms)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_elements, elements(:), parts(:)
    type(mass_scaling_t), intent(inout) :: ms
    integer, allocatable :: counts(:), fill(:), ids(:), recv_ids(:), recv_counts(:), place(:)
    real(wp), allocatable :: terms(:), recv_terms(:), sums(:)
    integer :: n_ranks, rank, k, r, first, n, e
    real(wp) :: dt_min
    call MPI_Comm_size(comm, n_ranks)
    call MPI_Comm_rank(comm, rank)
    allocate (counts(n_ranks), fill(n_ranks), source=0)
    do k = 1, size(elements)
      r = block_owner(elements(k), n_elements, n_ranks) + 1
      counts(r) = counts(r) + 2
    end do
    fill(1) = 0
    do r = 2, n_ranks
      fill(r) = fill(r - 1) + counts(r - 1)
    end do
    allocate (ids(sum(counts)), terms(sum(counts)))
    do k = 1, size(elements)
      r = block_owner(elements(k), n_elements, n_ranks) + 1
      ids(fill(r) + 1:fill(r) + 2) = [elements(k), parts(k)]
      terms(fill(r) + 1:fill(r) + 2) = [ms%element_mass(k), ms%element_added(k)]
      fill(r) = fill(r) + 2
    end do
    call exchange_int(comm, ids, counts, recv_ids, recv_counts)
    call exchange_real(comm, terms, counts, recv_terms)
    call block_range(n_elements, rank, n_ranks, first, n)
    allocate (place(n))
    do k = 1, size(recv_ids) / 2
      place(recv_ids(2 * k - 1) - first + 1) = k
    end do
    ! the running sums: [model mass, added mass of each part]
    allocate (sums(1 + size(ms%added_part)), source=0.0_wp)
    if (rank > 0) call MPI_Recv(sums, size(sums), MPI_DOUBLE_PRECISION, rank - 1, 0, comm, MPI_STATUS_IGNORE)
    do e = 1, n
      k = place(e)
      sums(1) = sums(1) + recv_terms(2 * k - 1)
      if (recv_terms(2 * k) > 0.0_wp) sums(1 + recv_ids(2 * k)) = sums(1 + recv_ids(2 * k)) + recv_terms(2 * k)
    end do
    if (rank < n_ranks - 1) call MPI_Send(sums, size(sums), MPI_DOUBLE_PRECISION, rank + 1, 0, comm)
    call MPI_Bcast(sums, size(sums), MPI_DOUBLE_PRECISION, n_ranks - 1, comm)
    ms%model_mass = sums(1)
    ms%added_part = sums(2:)
    ms%added = sum(ms%added_part)
    call MPI_Allreduce(ms%dt_element_min, dt_min, 1, MPI_DOUBLE_PRECISION, MPI_MIN, comm)
    ms%dt_element_min = dt_min
    call MPI_Allreduce(ms%dt_rigid_min, dt_min, 1, MPI_DOUBLE_PRECISION, MPI_MIN, comm)
    ms%dt_rigid_min = dt_min
    call MPI_Allreduce(MPI_IN_PLACE, ms%scaled, 1, MPI_INTEGER, MPI_SUM, comm)
  end subroutine mass_scaling_totals

end module ordered_sums
