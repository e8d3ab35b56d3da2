!> MPI plumbing around the domain decomposition: the exchange of element-corner forces on shared
!> nodes with neighbour ranks (nothing else crosses the network each step besides contact, whose
!> sharing is in contact_exchange) and the sums to rank 0 for the history. Buffers are allocated
!> once, at set-up. Fields are not gathered: each rank writes its own rows of results.h5.
module halo_exchange
  use mpi_f08
  use paradyn_kinds, only: wp, i8
  use domain_decomposition, only: domain_t
  use traffic_counter, only: traffic_t, count_messages
  implicit none
  private
  public :: halo_t, halo_setup, exchange_corners, sum_to_root

  type :: halo_t
    type(MPI_Comm) :: comm
    integer :: width = 6
    real(wp), allocatable :: send_buffer(:, :), recv_buffer(:, :)
    type(MPI_Request), allocatable :: requests(:)
    integer, allocatable :: owned_local(:)          !< local ids of the nodes this rank owns (and writes)
    type(traffic_t) :: traffic                      !< messages and bytes of the step's exchanges and reductions
  end type halo_t

contains

  subroutine halo_setup(dom, comm, halo)
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    type(halo_t), intent(out) :: halo
    integer :: k
    halo%comm = comm
    allocate (halo%send_buffer(halo%width, max(size(dom%send_slot), 1)))
    allocate (halo%recv_buffer(halo%width, max(size(dom%recv_slot), 1)))
    allocate (halo%requests(2 * dom%n_neighbours))
    halo%owned_local = pack([(k, k = 1, dom%n_nodes)], dom%node_owned == 1)
  end subroutine halo_setup

  !> Send our corner values on shared nodes to each neighbour and receive theirs into the ghost
  !> slots of `corner` (width x (4 n_elements + n_ghost_slots)).
  subroutine exchange_corners(dom, halo, corner)
    type(domain_t), intent(in) :: dom
    type(halo_t), intent(inout) :: halo
    real(wp), intent(inout) :: corner(:, :)
    integer :: k, first, last, n, w
    if (dom%n_neighbours == 0) return
    w = size(corner, 1)
    do k = 1, dom%n_neighbours
      first = dom%recv_start(k)
      last = dom%recv_start(k + 1) - 1
      n = last - first + 1
      call MPI_Irecv(halo%recv_buffer(1, first), w * n, MPI_DOUBLE_PRECISION, dom%neighbour(k), 7, &
                     halo%comm, halo%requests(k))
    end do
    do k = 1, dom%n_neighbours
      first = dom%send_start(k)
      last = dom%send_start(k + 1) - 1
      n = last - first + 1
      halo%send_buffer(1:w, first:last) = corner(:, dom%send_slot(first:last))
      call MPI_Isend(halo%send_buffer(1, first), w * n, MPI_DOUBLE_PRECISION, dom%neighbour(k), 7, &
                     halo%comm, halo%requests(dom%n_neighbours + k))
    end do
    call MPI_Waitall(2 * dom%n_neighbours, halo%requests, MPI_STATUSES_IGNORE)
    call count_messages(halo%traffic, dom%n_neighbours, int(8 * w * size(dom%send_slot), i8), &
                        int(8 * w * size(dom%recv_slot), i8))
    corner(:, dom%recv_slot) = halo%recv_buffer(1:w, 1:size(dom%recv_slot))
  end subroutine exchange_corners

  subroutine sum_to_root(halo, values)
    type(halo_t), intent(in) :: halo
    real(wp), intent(inout) :: values(:)
    real(wp) :: total(size(values))
    call MPI_Reduce(values, total, size(values), MPI_DOUBLE_PRECISION, MPI_SUM, 0, halo%comm)
    values = total
  end subroutine sum_to_root

end module halo_exchange