!> The contact parts in the global layout, for the contact state's set-up on one rank and in the
!> replicated scheme (contact_setup), where every contact node is held anyway; local contact sets
!> up from each rank's own rows (contact_local_setup) and never calls this. replicated_contact_deck
!> gives that layout for the contact parts only: every rank gathers the rows of the elements of
!> the parts that some /contact/pairs entry names, and the coordinates of their nodes, from the
!> ranks that hold them (MPI_Allgatherv), into arrays indexed by global node and element id: (3
!> n_nodes + 5 n_elements) numbers per rank. A model without contact never calls it.
module contact_global_rows
  use mpi_f08
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t, node_row
  implicit none
  private
  public :: replicated_contact_deck

contains

  !> The deck with its mesh in the global layout (node_ids = 1 .. n_nodes, element_ids = 1 ..
  !> n_elements) holding the contact parts' elements and their nodes' coordinates; other elements
  !> get part 0 (no part) and node 1, other nodes the origin. Collective.
  function replicated_contact_deck(deck, comm) result(global)
    type(deck_t), intent(in) :: deck
    type(MPI_Comm), intent(in) :: comm
    type(deck_t) :: global
    integer, allocatable :: mine(:), all(:), counts(:), displs(:)
    real(wp), allocatable :: x(:), all_x(:)
    integer :: k, j, n, n_ranks, e, at
    call MPI_Comm_size(comm, n_ranks)
    n = 0
    do k = 1, size(deck%element_ids)
      if (any(deck%contact_pairs(:, 1:deck%n_contacts) == deck%element_part(k))) n = n + 1
    end do
    allocate (mine(6 * n), x(12 * n))
    n = 0
    do k = 1, size(deck%element_ids)
      if (.not. any(deck%contact_pairs(:, 1:deck%n_contacts) == deck%element_part(k))) cycle
      mine(6 * n + 1:6 * n + 6) = [deck%element_ids(k), deck%connectivity(:, k), deck%element_part(k)]
      do j = 1, 4
        x(12 * n + 3 * j - 2:12 * n + 3 * j) = deck%coordinates(:, node_row(deck, deck%connectivity(j, k)))
      end do
      n = n + 1
    end do
    allocate (counts(n_ranks), displs(n_ranks))
    call MPI_Allgather(size(mine), 1, MPI_INTEGER, counts, 1, MPI_INTEGER, comm)
    displs = [0, [(sum(counts(1:k)), k = 1, n_ranks - 1)]]
    allocate (all(sum(counts)))
    call MPI_Allgatherv(mine, size(mine), MPI_INTEGER, all, counts, displs, MPI_INTEGER, comm)
    counts = 2 * counts
    displs = 2 * displs
    allocate (all_x(sum(counts)))
    call MPI_Allgatherv(x, size(x), MPI_DOUBLE_PRECISION, all_x, counts, displs, MPI_DOUBLE_PRECISION, comm)
    global = deck
    global%node_ids = [(k, k = 1, deck%n_nodes)]
    global%element_ids = [(k, k = 1, deck%n_elements)]
    deallocate (global%coordinates, global%connectivity, global%element_part)
    allocate (global%coordinates(3, deck%n_nodes), source=0.0_wp)
    allocate (global%connectivity(4, deck%n_elements), source=1)
    allocate (global%element_part(deck%n_elements), source=0)
    do k = 0, size(all) / 6 - 1
      e = all(6 * k + 1)
      global%connectivity(:, e) = all(6 * k + 2:6 * k + 5)
      global%element_part(e) = all(6 * k + 6)
      do j = 1, 4
        at = 12 * k + 3 * j
        global%coordinates(:, global%connectivity(j, e)) = all_x(at - 2:at)
      end do
    end do
    deallocate (global%velocity, global%angular_velocity, global%fixed, global%node_part)
  end function replicated_contact_deck

end module contact_global_rows
