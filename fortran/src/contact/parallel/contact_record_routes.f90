!> The records of local contact between ranks (docs/theory.md, "Parallel contact and
!> determinism"): every step each record a rank computed (its own slaves) goes by value to the
!> ranks whose domains hold one of its five nodes (this domain's holders from the halo, a ghost's
!> from its sender: contact_neighbours), and every rank orders the records it has by pass and the
!> slave's contact node, which is the order (pass, slave) of one rank: each node's force is then
!> bitwise the serial sum.
module contact_record_routes
  use paradyn_kinds, only: wp
  use integer_sort, only: merge_sort_ascending, sorted_position
  use traffic_counter, only: traffic_t
  use contact_sparse, only: sparse_exchange
  use contact_interface, only: contact_t
  use contact_room, only: contact_record_room
  use contact_neighbours, only: neighbours_t, in_domain
  implicit none
  private
  public :: share_records_locally

  integer, parameter :: record_width = 22     !< pass, 5 nodes (slave first), 15 forces, penetration

contains

  !> The records this rank computed (its own slaves: c%record_*(1:c%n_candidates), empty where
  !> node 1 is 0) go to the ranks whose domains hold one of their nodes; after the call c%record_*
  !> and c%candidates hold every record this rank has, in pass and slave order (c%n_candidates of
  !> them). Collective.
  subroutine share_records_locally(nb, c, traffic)
    type(neighbours_t), intent(inout) :: nb
    type(contact_t), intent(inout) :: c
    type(traffic_t), intent(inout) :: traffic
    integer, allocatable :: dest(:), start(:), fill(:), n_to(:), sources(:), rstart(:), own(:)
    real(wp), allocatable :: buffer(:), received(:)
    integer :: ranks(21), n, i, j, d, n_own
    own = pack([(j, j = 1, c%n_candidates)], c%record_nodes(1, 1:c%n_candidates) /= 0)
    n_own = size(own)
    ! the destinations, ascending, and the records for each
    allocate (dest(0))
    do i = 1, n_own
      call destinations(own(i), ranks, n)
      do j = 1, n
        if (.not. any(dest == ranks(j))) dest = [dest, ranks(j)]
      end do
    end do
    call merge_sort_ascending(dest)
    allocate (n_to(size(dest)), source=0)
    do i = 1, size(dest)
      nb%slot(dest(i)) = i
    end do
    do i = 1, n_own
      call destinations(own(i), ranks, n)
      n_to(nb%slot(ranks(1:n))) = n_to(nb%slot(ranks(1:n))) + 1
    end do
    ! each message: the number of records, then the records
    allocate (start(size(dest) + 1), fill(size(dest)))
    start(1) = 1
    do i = 1, size(dest)
      start(i + 1) = start(i) + 1 + record_width * n_to(i)
      fill(i) = start(i) + 1
    end do
    allocate (buffer(start(size(dest) + 1) - 1))
    do i = 1, n_own
      call destinations(own(i), ranks, n)
      do j = 1, n
        d = nb%slot(ranks(j))
        buffer(fill(d):fill(d) + record_width - 1) = record_row(c, own(i))
        fill(d) = fill(d) + record_width
      end do
    end do
    do i = 1, size(dest)
      buffer(start(i)) = real(n_to(i), wp)
    end do
    call sparse_exchange(nb%comm, nb%n_ranks, nb%round, dest, start, buffer, sources, rstart, received, &
                         traffic)
    call take_records(c, own, received, rstart)
  contains
    !> The ranks record k goes to: the holders of its nodes (held here: this domain's or ghosts), not
    !> this rank, once each.
    subroutine destinations(k, ranks, n)
      integer, intent(in) :: k
      integer, intent(out) :: ranks(:), n
      integer :: m, node, h
      n = 0
      do m = 1, 5
        node = c%record_nodes(m, k)
        if (in_domain(nb, node)) then
          h = sorted_position(nb%domain_node, node)
          call add_ranks(nb%holder(nb%holder_start(h):nb%holder_start(h + 1) - 1), nb%rank, ranks, n)
        else
          h = sorted_position(nb%ghost_node, node)
          call add_ranks(nb%ghost_holder(nb%ghost_holder_start(h):nb%ghost_holder_start(h + 1) - 1), nb%rank, ranks, n)
        end if
      end do
    end subroutine destinations
  end subroutine share_records_locally

  !> Append to ranks(1:n) the holders that are not me and not there yet.
  pure subroutine add_ranks(holders, me, ranks, n)
    integer, intent(in) :: holders(:), me
    integer, intent(inout) :: ranks(:), n
    integer :: j
    do j = 1, size(holders)
      if (holders(j) == me .or. any(ranks(1:n) == holders(j))) cycle
      n = n + 1
      ranks(n) = holders(j)
    end do
  end subroutine add_ranks

  pure function record_row(c, k) result(row)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: k
    real(wp) :: row(record_width)
    row(1) = real(c%candidates(3, k), wp)
    row(2:6) = real(c%record_nodes(:, k), wp)
    row(7:21) = reshape(c%record_force(:, :, k), [15])
    row(22) = c%record_penetration(k)
  end function record_row

  !> This rank's records (own) and those received (messages received(rstart(i) :)), in pass and
  !> slave order, into c%record_* and c%candidates.
  subroutine take_records(c, own, received, rstart)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: own(:), rstart(:)
    real(wp), intent(in) :: received(:)
    real(wp), allocatable :: rows(:, :)
    integer, allocatable :: keys(:), order(:), first(:)
    integer :: i, j, n, at, p, k
    n = size(own)
    do i = 1, size(rstart) - 1
      n = n + nint(received(rstart(i)))
    end do
    allocate (rows(record_width, n))
    do i = 1, size(own)
      rows(:, i) = record_row(c, own(i))
    end do
    n = size(own)
    do i = 1, size(rstart) - 1
      at = rstart(i) + 1
      do j = 1, nint(received(rstart(i)))
        rows(:, n + j) = received(at + record_width * (j - 1):at + record_width * j - 1)
      end do
      n = n + nint(received(rstart(i)))
    end do
    ! the order (pass, slave's contact node) is the order (pass, slave) of one rank: a pass's
    ! slaves are ascending. Each pass's records go after those of the passes before it
    ! (first(p)), in the order of their slaves' ids (a slave has one record per pass)
    allocate (first(size(c%passes) + 1), source=0)
    do i = 1, n
      first(nint(rows(1, i)) + 1) = first(nint(rows(1, i)) + 1) + 1
    end do
    do p = 1, size(c%passes)
      first(p + 1) = first(p + 1) + first(p)
    end do
    call contact_record_room(c, n)   ! rows holds them all: what c%record_* held may go
    do p = 1, size(c%passes)
      keys = pack(nint(rows(2, 1:n)), nint(rows(1, 1:n)) == p)
      order = keys
      call merge_sort_ascending(order)
      k = 0
      do i = 1, n
        if (nint(rows(1, i)) /= p) cycle
        k = k + 1
        j = first(p) + sorted_position(order, keys(k))
        c%candidates(:, j) = [0, 0, p]
        c%record_nodes(:, j) = nint(rows(2:6, i))
        c%record_force(:, :, j) = reshape(rows(7:21, i), [3, 5])
        c%record_penetration(j) = rows(22, i)
      end do
    end do
    c%n_candidates = n
  end subroutine take_records

end module contact_record_routes
