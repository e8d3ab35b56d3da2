!> MPI sharing of contact data between the ranks: the positions and velocities of the contact
!> nodes (all of them, or the subset near contact), the candidates each rank found in its share of
!> the slaves, and the records each rank computed for its block of the candidates. Values are
!> copied, never summed, so every rank ends with bitwise the same data as a serial run. Buffers
!> are allocated at set-up; one rank copies without MPI.
module contact_exchange
  use mpi_f08
  use paradyn_kinds, only: wp
  use domain_decomposition, only: domain_t, local_node
  implicit none
  private
  public :: node_set_t, node_set_setup, allgather_node_set, node_subset_setup, allgather_node_subset
  public :: node_set_masses
  public :: record_share_t, record_share_setup, share_contact_records
  public :: candidate_share_t, candidate_share_setup, share_contact_candidates

  !> A set of global nodes (for example every node of the parts in contact) whose positions and
  !> velocities every rank needs: each owner sends its members to all ranks, all of them
  !> (allgather_node_set) or a subset chosen by node_subset_setup (allgather_node_subset).
  type :: node_set_t
    integer :: n = 0
    integer, allocatable :: local(:)          !< local id of each member on this rank, 0 if not held
    integer, allocatable :: owned_member(:)   !< members this rank owns, ascending
    integer, allocatable :: counts(:), displs(:)   !< in doubles, 6 per member
    integer, allocatable :: gathered_member(:)     !< members as they arrive, rank after rank
    integer, allocatable :: rank_end(:)       !< gathered_member(rank_end(r - 1) + 1 : rank_end(r)) from rank r - 1
    real(wp), allocatable :: send(:, :), recv(:, :)
    ! the subset: members this rank sends, members in the order they arrive, counts in doubles
    ! (6 per member and one value per rank)
    integer :: n_sub_send = 0, n_sub_recv = 0
    integer, allocatable :: sub_send(:), sub_recv(:), sub_counts(:), sub_displs(:)
    real(wp), allocatable :: sub_send_buffer(:), sub_recv_buffer(:)
  end type node_set_t

  !> Buffers to share the contact records that each rank computed for its share of the slaves.
  type :: record_share_t
    real(wp), allocatable :: send(:, :), recv(:, :)
    integer, allocatable :: counts(:), displs(:)
  end type record_share_t

  !> Counts to share the contact candidates (slave, nearest master) each rank found.
  type :: candidate_share_t
    integer, allocatable :: counts(:), displs(:)
  end type candidate_share_t

  integer, parameter :: record_width = 22   !< slave index, 5 nodes, 15 forces, penetration

contains

  subroutine record_share_setup(n_records, n_ranks, share)
    integer, intent(in) :: n_records, n_ranks
    type(record_share_t), intent(out) :: share
    allocate (share%send(record_width, n_records), share%recv(record_width, n_records))
    allocate (share%counts(n_ranks), share%displs(n_ranks))
  end subroutine record_share_setup

  subroutine candidate_share_setup(n_ranks, share)
    integer, intent(in) :: n_ranks
    type(candidate_share_t), intent(out) :: share
    allocate (share%counts(n_ranks), share%displs(n_ranks))
  end subroutine candidate_share_setup

  !> Every rank found n_mine candidate pairs (slave, nearest master, pass) among its cyclic share of
  !> the slaves; after this call every rank holds all n_all pairs, rank after rank.
  subroutine share_contact_candidates(comm, share, n_mine, mine, n_all, all)
    type(MPI_Comm), intent(in) :: comm
    type(candidate_share_t), intent(inout) :: share
    integer, intent(in) :: n_mine
    integer, intent(in) :: mine(:, :)
    integer, intent(out) :: n_all
    integer, intent(inout) :: all(:, :)
    integer :: n_values, width
    width = size(mine, 1)
    ! counts in integers (width per pair), so no scaled temporary is built every step
    call MPI_Allgather(width * n_mine, 1, MPI_INTEGER, share%counts, 1, MPI_INTEGER, comm)
    call displacements(share%counts, share%displs, n_values)
    call MPI_Allgatherv(mine, width * n_mine, MPI_INTEGER, all, share%counts, share%displs, &
                        MPI_INTEGER, comm)
    n_all = n_values / width
  end subroutine share_contact_candidates

  !> Every rank filled the records of its own slaves and left the others empty (node 0); after
  !> this call every rank holds all n records. Only records in contact travel. Values are copied,
  !> never summed, so the records are bitwise those of a serial run.
  subroutine share_contact_records(comm, share, n, nodes, forces, penetration)
    type(MPI_Comm), intent(in) :: comm
    type(record_share_t), intent(inout) :: share
    integer, intent(in) :: n
    integer, intent(inout) :: nodes(:, :)
    real(wp), intent(inout) :: forces(:, :, :), penetration(:)
    integer :: j, k, mine, total
    mine = 0
    do j = 1, n
      if (nodes(1, j) == 0) cycle
      mine = mine + 1
      share%send(1, mine) = real(j, wp)
      share%send(2:6, mine) = real(nodes(:, j), wp)
      share%send(7:21, mine) = reshape(forces(:, :, j), [15])
      share%send(22, mine) = penetration(j)
    end do
    ! counts in doubles, so no scaled temporary is built every step
    call MPI_Allgather(record_width * mine, 1, MPI_INTEGER, share%counts, 1, MPI_INTEGER, comm)
    call displacements(share%counts, share%displs, total)
    call MPI_Allgatherv(share%send, record_width * mine, MPI_DOUBLE_PRECISION, share%recv, &
                        share%counts, share%displs, MPI_DOUBLE_PRECISION, comm)
    do k = 1, total / record_width
      j = nint(share%recv(1, k))
      nodes(:, j) = nint(share%recv(2:6, k))
      forces(:, :, j) = reshape(share%recv(7:21, k), [3, 5])
      penetration(j) = share%recv(22, k)
    end do
  end subroutine share_contact_records

  !> members: global node ids, ascending. gathers: set up the gathers (collective); without them
  !> (local contact, which never gathers the set) only where each member lives, and no buffer
  !> sized by the set's members on other ranks.
  subroutine node_set_setup(dom, comm, members, gathers, set)
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: members(:)
    logical, intent(in) :: gathers
    type(node_set_t), intent(out) :: set
    integer :: k, total
    set%n = size(members)
    allocate (set%local(set%n), source=0)
    do k = 1, set%n
      set%local(k) = local_node(dom, members(k))
    end do
    set%owned_member = pack([(k, k = 1, set%n)], set%local > 0)
    set%owned_member = pack(set%owned_member, dom%node_owned(set%local(set%owned_member)) == 1)
    if (.not. gathers) return
    allocate (set%counts(dom%n_ranks), set%displs(dom%n_ranks))
    call MPI_Allgather(size(set%owned_member), 1, MPI_INTEGER, set%counts, 1, MPI_INTEGER, comm)
    call displacements(set%counts, set%displs, total)
    allocate (set%gathered_member(total))
    call MPI_Allgatherv(set%owned_member, size(set%owned_member), MPI_INTEGER, set%gathered_member, &
                        set%counts, set%displs, MPI_INTEGER, comm)
    allocate (set%send(6, max(size(set%owned_member), 1)), set%recv(6, max(total, 1)))
    allocate (set%rank_end(dom%n_ranks))
    set%rank_end = set%displs + set%counts
    ! from here on counted in doubles (6 per member), so no scaled temporary is built every step
    set%counts = 6 * set%counts
    set%displs = 6 * set%displs
    allocate (set%sub_send(max(size(set%owned_member), 1)), set%sub_recv(max(set%n, 1)))
    allocate (set%sub_counts(dom%n_ranks), set%sub_displs(dom%n_ranks))
    allocate (set%sub_send_buffer(6 * size(set%owned_member) + 1), set%sub_recv_buffer(6 * set%n + dom%n_ranks))
    call node_subset_setup(set, [(.true., k = 1, set%n)])
  end subroutine node_set_setup

  !> Choose the members that allgather_node_subset sends (in_subset, the same on every rank): the
  !> lists are derived without communication, since every rank knows who owns each member.
  subroutine node_subset_setup(set, in_subset)
    type(node_set_t), intent(inout) :: set
    logical, intent(in) :: in_subset(:)
    integer :: r, k, first, n_from_rank, total
    set%n_sub_send = 0
    do k = 1, size(set%owned_member)
      if (.not. in_subset(set%owned_member(k))) cycle
      set%n_sub_send = set%n_sub_send + 1
      set%sub_send(set%n_sub_send) = set%owned_member(k)
    end do
    set%n_sub_recv = 0
    first = 1
    do r = 1, size(set%rank_end)
      n_from_rank = 0
      do k = first, set%rank_end(r)
        if (.not. in_subset(set%gathered_member(k))) cycle
        n_from_rank = n_from_rank + 1
        set%n_sub_recv = set%n_sub_recv + 1
        set%sub_recv(set%n_sub_recv) = set%gathered_member(k)
      end do
      set%sub_counts(r) = 6 * n_from_rank + 1
      first = set%rank_end(r) + 1
    end do
    call displacements(set%sub_counts, set%sub_displs, total)
  end subroutine node_subset_setup

  !> Positions and velocities of the subset's members, on every rank (the other members keep
  !> their values), and the largest of the ranks' values. One rank copies without MPI.
  subroutine allgather_node_subset(comm, set, x, v, x_set, v_set, value, value_max)
    type(MPI_Comm), intent(in) :: comm
    type(node_set_t), intent(inout) :: set
    real(wp), intent(in) :: x(:, :), v(:, :), value
    real(wp), intent(inout) :: x_set(3, set%n), v_set(3, set%n)
    real(wp), intent(out) :: value_max
    integer :: i, j, k, r, at, m
    if (size(set%counts) == 1) then
      do i = 1, set%n_sub_send
        k = set%sub_send(i)
        j = set%local(k)
        x_set(:, k) = x(:, j)
        v_set(:, k) = v(:, j)
      end do
      value_max = value
      return
    end if
    do i = 1, set%n_sub_send
      j = set%local(set%sub_send(i))
      set%sub_send_buffer(6 * i - 5:6 * i - 3) = x(:, j)
      set%sub_send_buffer(6 * i - 2:6 * i) = v(:, j)
    end do
    set%sub_send_buffer(6 * set%n_sub_send + 1) = value
    call MPI_Allgatherv(set%sub_send_buffer, 6 * set%n_sub_send + 1, MPI_DOUBLE_PRECISION, &
                        set%sub_recv_buffer, set%sub_counts, set%sub_displs, MPI_DOUBLE_PRECISION, comm)
    value_max = -huge(1.0_wp)
    m = 0
    do r = 1, size(set%sub_counts)
      at = set%sub_displs(r)
      do i = 1, (set%sub_counts(r) - 1) / 6
        m = m + 1
        k = set%sub_recv(m)
        x_set(:, k) = set%sub_recv_buffer(at + 1:at + 3)
        v_set(:, k) = set%sub_recv_buffer(at + 4:at + 6)
        at = at + 6
      end do
      value_max = max(value_max, set%sub_recv_buffer(at + 1))
    end do
  end subroutine allgather_node_subset

  !> Positions and velocities of every member of the set, on every rank. One rank holds them
  !> all and copies them without MPI. Threads share the packing and unpacking.
  subroutine allgather_node_set(comm, set, x, v, x_set, v_set)
    type(MPI_Comm), intent(in) :: comm
    type(node_set_t), intent(inout) :: set
    real(wp), intent(in) :: x(:, :), v(:, :)
    real(wp), intent(out) :: x_set(3, set%n), v_set(3, set%n)
    integer :: n_owned, k, j
    if (size(set%counts) == 1) then
      !$omp parallel do schedule(static) private(j)
      do k = 1, set%n
        j = set%local(k)
        x_set(:, k) = x(:, j)
        v_set(:, k) = v(:, j)
      end do
      !$omp end parallel do
      return
    end if
    n_owned = size(set%owned_member)
    !$omp parallel do schedule(static) private(j)
    do k = 1, n_owned
      j = set%local(set%owned_member(k))
      set%send(1:3, k) = x(:, j)
      set%send(4:6, k) = v(:, j)
    end do
    !$omp end parallel do
    call MPI_Allgatherv(set%send, 6 * n_owned, MPI_DOUBLE_PRECISION, set%recv, set%counts, &
                        set%displs, MPI_DOUBLE_PRECISION, comm)
    !$omp parallel do schedule(static) private(j)
    do k = 1, set%n
      j = set%gathered_member(k)
      x_set(:, j) = set%recv(1:3, k)
      v_set(:, j) = set%recv(4:6, k)
    end do
    !$omp end parallel do
  end subroutine allgather_node_set

  !> The lumped masses (mass: local columns) of the set's members: gathered from their owners
  !> (gathers, a set from node_set_setup with its gathers; collective), or those of the members
  !> in this domain, 0 elsewhere: a shared node's mass is the same on every rank that holds it
  !> (the corners' sums are assembled in one order), so either way it is the owner's.
  subroutine node_set_masses(comm, set, gathers, mass, masses)
    type(MPI_Comm), intent(in) :: comm
    type(node_set_t), intent(inout) :: set
    logical, intent(in) :: gathers
    real(wp), intent(in) :: mass(:)
    real(wp), allocatable, intent(out) :: masses(:)
    real(wp), allocatable :: x_set(:, :), v_set(:, :)
    integer :: k
    if (gathers) then
      allocate (x_set(3, set%n), v_set(3, set%n))
      call allgather_node_set(comm, set, spread(mass, 1, 3), spread(mass, 1, 3), x_set, v_set)
      masses = x_set(1, :)
      return
    end if
    allocate (masses(set%n), source=0.0_wp)
    do k = 1, set%n
      if (set%local(k) > 0) masses(k) = mass(set%local(k))
    end do
  end subroutine node_set_masses

  subroutine displacements(counts, displs, total)
    integer, intent(in) :: counts(:)
    integer, intent(out) :: displs(:), total
    integer :: r
    total = 0
    do r = 1, size(counts)
      displs(r) = total
      total = total + counts(r)
    end do
  end subroutine displacements

end module contact_exchange
