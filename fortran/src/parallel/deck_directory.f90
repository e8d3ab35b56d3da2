!> The deck's rows between the ranks (issue 19, item 5), through the node directory of
!> distributed_decomposition: node n's rows are read by its home rank, block_owner(n, n_nodes,
!> n_ranks) (a contiguous id range), and element e's by block_owner(e, n_elements, n_ranks). No
!> array here is sized by the global mesh: each rank sends and receives the rows of its own
!> elements and nodes, and the homes answer for their id range.
!> - fetch_node_rows: the rows of the nodes a rank's elements touch, from their homes, with the
!>   part of each node's lowest-numbered element; the homes learn which of their nodes are used.
!> - first_duplicate_element: the schema relation distinct_elements, each element checked at the
!>   home of its lowest node, in the order of model_deck's serial check.
!> - move_element_rows: element rows to the ranks that own them (recursive coordinate bisection).
module deck_directory
  use mpi_f08
  use paradyn_kinds, only: wp
  use domain_decomposition, only: block_owner
  use integer_sort, only: sort_ascending, sorted_position, distinct_ascending
  use rank_exchange, only: exchange_int, exchange_real, offsets
  implicit none
  private
  public :: block_range, fetch_node_rows, first_duplicate_element, move_element_rows
  public :: node_values   ! values per node row: coordinates 3, velocity 3, angular velocity 3, fixed 6,
                          ! rigid body 1, added mass 1

  integer, parameter :: node_values = 17

contains

  !> The first id and the count of rank's block of n ids (block_owner's ranges).
  pure subroutine block_range(n, rank, n_ranks, first, count)
    integer, intent(in) :: n, rank, n_ranks
    integer, intent(out) :: first, count
    first = int((int(rank, 8) * n) / n_ranks) + 1
    count = int((int(rank + 1, 8) * n) / n_ranks) - first + 1
  end subroutine block_range

  !> For this rank's elements (global ids ascending, their connectivity and parts): node_ids, the
  !> distinct nodes they touch, ascending; rows (node_values, size(node_ids)) from the homes'
  !> home_rows (node_values, home block); part: the part of each node's lowest-numbered element
  !> over all ranks; used(home block): whether any element of any rank touches the home's node.
  subroutine fetch_node_rows(comm, n_nodes, element_ids, connectivity, element_part, home_rows, node_ids, rows, &
                             part, used)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_nodes, element_ids(:), connectivity(:, :), element_part(:)
    real(wp), intent(in) :: home_rows(:, :)
    integer, allocatable, intent(out) :: node_ids(:), part(:)
    real(wp), allocatable, intent(out) :: rows(:, :)
    logical, allocatable, intent(out) :: used(:)
    integer, allocatable :: low(:), low_part(:), send(:), counts(:), recv(:), recv_counts(:), best(:), best_part(:)
    real(wp), allocatable :: reply(:), answer(:)
    integer :: n_ranks, rank, first, nb, e, k, j, r, n
    call MPI_Comm_size(comm, n_ranks)
    call MPI_Comm_rank(comm, rank)
    node_ids = distinct_ascending(reshape(connectivity, [size(connectivity)]))
    allocate (low(size(node_ids)), low_part(size(node_ids)), source=huge(1))
    do e = 1, size(element_ids)   ! ascending: the first element met is the node's lowest here
      do k = 1, 4
        j = sorted_position(node_ids, connectivity(k, e))
        if (element_ids(e) < low(j)) then
          low(j) = element_ids(e)
          low_part(j) = element_part(e)
        end if
      end do
    end do
    allocate (counts(n_ranks), source=0)
    do j = 1, size(node_ids)   ! ascending ids: grouped by home, in home order
      r = block_owner(node_ids(j), n_nodes, n_ranks) + 1
      counts(r) = counts(r) + 3
    end do
    send = reshape(transpose(reshape([node_ids, low, low_part], [size(node_ids), 3])), [3 * size(node_ids)])
    call exchange_int(comm, send, counts, recv, recv_counts)
    call block_range(n_nodes, rank, n_ranks, first, nb)
    allocate (used(nb), source=.false.)
    allocate (best(nb), best_part(nb), source=huge(1))
    do k = 1, size(recv) / 3
      n = recv(3 * k - 2) - first + 1
      used(n) = .true.
      if (recv(3 * k - 1) < best(n)) then
        best(n) = recv(3 * k - 1)
        best_part(n) = recv(3 * k)
      end if
    end do
    allocate (reply((node_values + 1) * (size(recv) / 3)))
    do k = 1, size(recv) / 3
      n = recv(3 * k - 2) - first + 1
      reply((node_values + 1) * (k - 1) + 1:(node_values + 1) * k) = [home_rows(:, n), real(best_part(n), wp)]
    end do
    call exchange_real(comm, reply, (recv_counts / 3) * (node_values + 1), answer)
    rows = reshape(answer, [node_values + 1, size(node_ids)])
    part = nint(rows(node_values + 1, :))
    rows = rows(1:node_values, :)
  end subroutine fetch_node_rows

  !> The schema relation distinct_elements over all ranks: later, the higher of the first two
  !> elements with the same four nodes (in any order), earlier the other, later_nodes its nodes;
  !> later = 0 when there is none. "First" as model_deck's serial check orders them: by the lowest
  !> node of the pair, then by element id. Every rank gets the same answer.
  subroutine first_duplicate_element(comm, n_nodes, element_ids, connectivity, later, earlier, later_nodes)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_nodes, element_ids(:), connectivity(:, :)
    integer, intent(out) :: later, earlier, later_nodes(4)
    integer, allocatable :: send(:), counts(:), recv(:), recv_counts(:), sorted(:, :), key(:)
    integer :: n_ranks, rank, e, k, i, r, m, found(3), pair(2), winner(2)
    call MPI_Comm_size(comm, n_ranks)
    call MPI_Comm_rank(comm, rank)
    allocate (counts(n_ranks), source=0)
    allocate (send(5 * size(element_ids)))
    allocate (sorted(4, size(element_ids)))
    do e = 1, size(element_ids)
      sorted(:, e) = connectivity(:, e)
      call sort_ascending(sorted(:, e))
      r = block_owner(sorted(1, e), n_nodes, n_ranks) + 1
      counts(r) = counts(r) + 5
    end do
    call pack_by_rank(element_ids, connectivity, sorted(1, :), n_nodes, n_ranks, counts, send)
    call exchange_int(comm, send, counts, recv, recv_counts)
    m = size(recv) / 5
    ! the received elements ordered by (lowest node, element id), as the serial check meets them
    deallocate (sorted)
    allocate (sorted(4, m), key(m))
    do k = 1, m
      sorted(:, k) = recv(5 * k - 3:5 * k)
      call sort_ascending(sorted(:, k))
    end do
    key = order_by_low_then_id(sorted(1, :), recv(1:5 * m:5))
    found = [huge(1), 0, 0]   ! (lowest node, later, earlier)
    outer: do k = 2, m
      do i = k - 1, 1, -1
        if (sorted(1, key(i)) /= sorted(1, key(k))) exit
      end do
      do i = i + 1, k - 1
        if (all(sorted(:, key(i)) == sorted(:, key(k)))) then
          found = [sorted(1, key(k)), recv(5 * key(k) - 4), recv(5 * key(i) - 4)]
          later_nodes = recv(5 * key(k) - 3:5 * key(k))
          exit outer
        end if
      end do
    end do outer
    pair = [found(1), rank]
    call MPI_Allreduce(pair, winner, 1, MPI_2INTEGER, MPI_MINLOC, comm)
    later = 0
    earlier = 0
    if (winner(1) == huge(1)) return
    if (rank /= winner(2)) later_nodes = 0
    call MPI_Bcast(found, 3, MPI_INTEGER, winner(2), comm)
    call MPI_Bcast(later_nodes, 4, MPI_INTEGER, winner(2), comm)
    later = found(2)
    earlier = found(3)
  end subroutine first_duplicate_element

  !> (id, connectivity) of each element, grouped by the home of its lowest node (counts: 5 each).
  pure subroutine pack_by_rank(element_ids, connectivity, low, n_nodes, n_ranks, counts, send)
    integer, intent(in) :: element_ids(:), connectivity(:, :), low(:), n_nodes, n_ranks, counts(:)
    integer, intent(inout) :: send(:)
    integer :: fill(n_ranks), e, r
    call offsets(counts, fill)
    do e = 1, size(element_ids)
      r = block_owner(low(e), n_nodes, n_ranks) + 1
      send(fill(r) + 1:fill(r) + 5) = [element_ids(e), connectivity(:, e)]
      fill(r) = fill(r) + 5
    end do
  end subroutine pack_by_rank

  !> The permutation that orders entries by (low, id) ascending.
  pure function order_by_low_then_id(low, id) result(order)
    integer, intent(in) :: low(:), id(:)
    integer :: order(size(low))
    integer :: i
    order = [(i, i = 1, size(low))]
    call sort_by_pairs(order, low, id)
  end function order_by_low_then_id

  !> Merge sort of order by (low(order), id(order)).
  pure recursive subroutine sort_by_pairs(order, low, id)
    integer, intent(inout) :: order(:)
    integer, intent(in) :: low(:), id(:)
    integer :: half, i, j, k
    integer, allocatable :: left(:), right(:)
    if (size(order) < 2) return
    half = size(order) / 2
    left = order(1:half)
    right = order(half + 1:)
    call sort_by_pairs(left, low, id)
    call sort_by_pairs(right, low, id)
    i = 1
    j = 1
    do k = 1, size(order)
      if (j > size(right)) then
        order(k) = left(i)
        i = i + 1
      else if (i > size(left)) then
        order(k) = right(j)
        j = j + 1
      else if (low(right(j)) < low(left(i)) .or. (low(right(j)) == low(left(i)) .and. id(right(j)) < id(left(i)))) then
        order(k) = right(j)
        j = j + 1
      else
        order(k) = left(i)
        i = i + 1
      end if
    end do
  end subroutine sort_by_pairs

  !> Element rows (ids ascending, connectivity, parts) to the ranks owner(k) (0-based) names for
  !> each; on return the rows this rank owns, ids ascending (every sender's rows are ascending and
  !> the senders' blocks follow each other).
  subroutine move_element_rows(comm, owner, element_ids, connectivity, element_part)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: owner(:)
    integer, allocatable, intent(inout) :: element_ids(:), connectivity(:, :), element_part(:)
    integer, allocatable :: send(:), counts(:), fill(:), recv(:), recv_counts(:)
    integer :: n_ranks, e, r, m
    call MPI_Comm_size(comm, n_ranks)
    allocate (counts(n_ranks), fill(n_ranks), source=0)
    do e = 1, size(element_ids)
      counts(owner(e) + 1) = counts(owner(e) + 1) + 6
    end do
    call offsets(counts, fill)
    allocate (send(sum(counts)))
    do e = 1, size(element_ids)
      r = owner(e) + 1
      send(fill(r) + 1:fill(r) + 6) = [element_ids(e), connectivity(:, e), element_part(e)]
      fill(r) = fill(r) + 6
    end do
    call exchange_int(comm, send, counts, recv, recv_counts)
    m = size(recv) / 6
    element_ids = recv(1:6 * m:6)
    connectivity = reshape([(recv(6 * e - 4:6 * e - 1), e = 1, m)], [4, m])
    element_part = recv(6:6 * m:6)
  end subroutine move_element_rows

end module deck_directory
