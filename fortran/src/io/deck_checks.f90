!> The deck's relations checked over the ranks' rows, and the mesh rows moved to the ranks that
!> run them (issue 19, item 5). The reader leaves each rank with its block of the element rows and
!> the home block of the node rows (deck_directory); here every rank gets the rows of the nodes
!> its elements touch, the relations are checked in model_deck's order (deck_relations), each
!> one agreed over the ranks before the next (the first offending entry, lowest id, is the one a
!> rank holding the whole deck would name; every rank gets the same message), and with partition
!> = "rcb" the element rows move to their owners, found by a bisection of the distributed
!> centroids (distributed_rcb). No array here is sized by the global mesh.
module deck_checks
  use mpi_f08
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: status_ok, status_bad_input
  use model_deck, only: deck_t, node_row
  use deck_relations, only: precision_message, repeated_node_message, duplicate_element_message, shape_message, &
                            thickness_update_message, &
                            small_table_message, rigid_node_message, unused_node_message, wall_normal_message, &
                            wall_behind_message, wall_rows_message, check_curve_relations
  use rigid_wall, only: wall_t, wall_make, wall_gap
  use integer_sort, only: sorted_position
  use deck_directory, only: fetch_node_rows, first_duplicate_element, move_element_rows, node_values
  use deck_fingerprint, only: fingerprint_add
  use domain_decomposition, only: element_centroids, partition_rcb
  use distributed_rcb, only: rcb_owners
  implicit none
  private
  public :: agree_on_first, chain_fingerprint, distribute_and_check

  ! the element-row relations first_element_message checks
  integer, parameter :: repeated_nodes = 1, element_shape = 2, rigid_nodes = 3, thickness_updates = 4

contains

  !> Every rank passes the key of its first problem (a global id, huge(1) for none) and its
  !> message; all return the message of the lowest key (of the lowest rank on a tie) and that key.
  subroutine agree_on_first(comm, key, message)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(inout) :: key
    character(len=*), intent(inout) :: message
    integer :: pair(2), winner(2), rank
    character(len=1024) :: text
    call MPI_Comm_rank(comm, rank)
    text = message
    pair = [key, rank]
    call MPI_Allreduce(pair, winner, 1, MPI_2INTEGER, MPI_MINLOC, comm)
    key = winner(1)
    message = ''
    if (key == huge(1)) return
    call MPI_Bcast(text, len(text), MPI_CHARACTER, winner(2), comm)
    message = trim(text)
  end subroutine agree_on_first

  !> The message of the lowest element id whose row breaks the relation, over the ranks ('' when none).
  subroutine first_element_message(d, comm, relation, message)
    type(deck_t), intent(in) :: d
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: relation   !< repeated_nodes, element_shape, rigid_nodes or thickness_updates
    character(len=*), intent(out) :: message
    integer :: key, row
    key = huge(1)
    message = ''
    do row = 1, size(d%element_ids)
      if (relation == repeated_nodes) then
        message = repeated_node_message(d, row)
      else if (relation == rigid_nodes) then
        message = rigid_node_message(d, row)
      else if (relation == thickness_updates) then
        message = thickness_update_message(d, row)
      else
        message = shape_message(d, row)
      end if
      if (message /= '') then
        key = d%element_ids(row)
        exit
      end if
    end do
    call agree_on_first(comm, key, message)
  end subroutine first_element_message

  !> The FNV-1a hash (deck_fingerprint) continued over the ranks' blocks of a dataset in rank
  !> order, as over the whole dataset: each rank takes the hash from the rank before, adds its
  !> rows, passes it on; the last rank's hash goes to all. n_ranks messages per dataset.
  subroutine chain_fingerprint(comm, hash, values)
    type(MPI_Comm), intent(in) :: comm
    integer(i8), intent(inout) :: hash
    real(wp), intent(in) :: values(:)
    integer :: rank, n_ranks
    call MPI_Comm_rank(comm, rank)
    call MPI_Comm_size(comm, n_ranks)
    if (rank > 0) call MPI_Recv(hash, 1, MPI_INTEGER8, rank - 1, 0, comm, MPI_STATUS_IGNORE)
    call fingerprint_add(hash, values)
    if (rank < n_ranks - 1) call MPI_Send(hash, 1, MPI_INTEGER8, rank + 1, 0, comm)
    call MPI_Bcast(hash, 1, MPI_INTEGER8, n_ranks - 1, comm)
  end subroutine chain_fingerprint

  !> From the reader's blocks (d%element_ids: this rank's element block; d%node_ids: its home
  !> block of nodes) to model_deck's layout, checking the relations on the way. Collective;
  !> status_bad_input with the message of the first broken relation, the same on every rank.
  subroutine distribute_and_check(d, comm, status, message)
    type(deck_t), intent(inout) :: d
    type(MPI_Comm), intent(in) :: comm
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    real(wp), allocatable :: home(:, :)
    integer, allocatable :: home_ids(:)
    logical, allocatable :: used(:)
    integer :: later, earlier, later_nodes(4)
    logical :: fixed_here
    status = status_bad_input
    message = precision_message(d)
    if (message /= '') return
    call first_element_message(d, comm, repeated_nodes, message)
    if (message /= '') return
    call first_duplicate_element(comm, d%n_nodes, d%element_ids, d%connectivity, later, earlier, later_nodes)
    if (later > 0) then
      message = duplicate_element_message(later, earlier, later_nodes)
      return
    end if
    home_ids = d%node_ids
    allocate (home(node_values, size(home_ids)))
    home(1:3, :) = d%coordinates
    home(4:6, :) = d%velocity
    home(7:9, :) = d%angular_velocity
    home(10:15, :) = real(d%fixed, wp)
    home(16, :) = real(d%node_rigid_body, wp)
    home(17, :) = d%added_mass
    fixed_here = any(d%fixed /= 0)
    call MPI_Allreduce(fixed_here, d%any_fixed, 1, MPI_LOGICAL, MPI_LOR, comm)
    call held_nodes(d, comm, home, used)
    call first_element_message(d, comm, element_shape, message)
    if (message /= '') return
    call first_element_message(d, comm, thickness_updates, message)
    if (message /= '') return
    message = small_table_message(d)
    if (message /= '') return
    call first_element_message(d, comm, rigid_nodes, message)
    if (message /= '') return
    call check_used(comm, home_ids, used, message)
    if (message /= '') return
    call check_rigid_walls(d, comm, home_ids, home(1:3, :), message)
    if (message /= '') return
    call check_curve_relations(d, message)
    if (message /= '') return
    if (d%partition == partition_rcb) call rcb_rows(d, comm, home)
    status = status_ok
  end subroutine distribute_and_check

  !> The rows of the nodes of this rank's elements, from the homes' block `home`, into d; used:
  !> which nodes of the home block some element touches.
  subroutine held_nodes(d, comm, home, used)
    type(deck_t), intent(inout) :: d
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: home(:, :)
    logical, allocatable, intent(out) :: used(:)
    real(wp), allocatable :: rows(:, :)
    call fetch_node_rows(comm, d%n_nodes, d%element_ids, d%connectivity, d%element_part, home, d%node_ids, rows, &
                         d%node_part, used)
    d%coordinates = rows(1:3, :)
    d%velocity = rows(4:6, :)
    d%angular_velocity = rows(7:9, :)
    d%fixed = nint(rows(10:15, :))
    d%node_rigid_body = nint(rows(16, :))
    d%added_mass = rows(17, :)
  end subroutine held_nodes

  !> The schema relation node_in_element: the lowest unused node and their count over all homes.
  subroutine check_used(comm, home_ids, used, message)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: home_ids(:)
    logical, intent(in) :: used(:)
    character(len=*), intent(out) :: message
    integer :: mine(2), first, unused
    message = ''
    mine = [huge(1), count(.not. used)]
    if (mine(2) > 0) mine(1) = home_ids(findloc(used, .false., dim=1))
    call MPI_Allreduce(mine(1), first, 1, MPI_INTEGER, MPI_MIN, comm)
    call MPI_Allreduce(mine(2), unused, 1, MPI_INTEGER, MPI_SUM, comm)
    if (unused > 0) message = unused_node_message(first, unused)
  end subroutine check_used

  !> The schema relations rigid_wall_nodes_wall, rigid_wall_normal_nonzero, rigid_wall_geometry
  !> and rigid_wall_nodes_in_front, wall by wall: the node the wall acts on of the lowest signed gap
  !> (lowest id on a tie) over the homes' blocks (home_ids ascending). A node counts as inside below
  !> a gap of 1e-9 of the model's size, so that nodes placed on the surface are not refused for a
  !> rounding error.
  subroutine check_rigid_walls(d, comm, home_ids, x, message)
    type(deck_t), intent(in) :: d
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: home_ids(:)
    real(wp), intent(in) :: x(:, :)
    character(len=*), intent(out) :: message
    real(wp) :: tolerance, size_here, mine(2), lowest(2), gap, normal(3)
    logical :: acts(size(home_ids))
    type(wall_t) :: wall
    integer :: w, j, k
    message = wall_rows_message(d, size(d%rigid_wall_shape))
    if (message /= '' .or. d%n_rigid_walls == 0) return
    size_here = 0.0_wp
    if (size(x) > 0) size_here = maxval(abs(x))
    call MPI_Allreduce(size_here, tolerance, 1, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
    tolerance = 1.0e-9_wp * tolerance
    do w = 1, d%n_rigid_walls
      message = wall_normal_message(d, w)
      if (message /= '') return
      wall = wall_make(d%rigid_wall_shape(w), d%rigid_wall_point(:, w), d%rigid_wall_normal(:, w), &
                       d%rigid_wall_edge(:, w), d%rigid_wall_size(:, w), d%rigid_wall_radius(w), &
                       d%rigid_wall_length(w), d%rigid_wall_velocity(:, w), 0.0_wp, 0.0_wp, 1.0_wp)
      acts = .not. any(d%rigid_wall_node_wall(1:d%n_rigid_wall_nodes) == w)
      do k = 1, d%n_rigid_wall_nodes
        if (d%rigid_wall_node_wall(k) /= w .or. size(home_ids) == 0) cycle
        j = sorted_position(home_ids, d%rigid_wall_node(k))
        if (home_ids(j) == d%rigid_wall_node(k)) acts(j) = .true.
      end do
      mine = [huge(1.0_wp), huge(1.0_wp)]
      do j = 1, size(home_ids)
        if (.not. acts(j)) cycle
        call wall_gap(wall, x(:, j) - wall%point, gap, normal)
        if (gap < mine(1)) mine = [gap, real(home_ids(j), wp)]
      end do
      call MPI_Allreduce(mine, lowest, 1, MPI_2DOUBLE_PRECISION, MPI_MINLOC, comm)
      if (lowest(1) < -tolerance) then
        message = wall_behind_message(w, nint(lowest(2)), lowest(1))
        return
      end if
    end do
  end subroutine check_rigid_walls

  !> Recursive coordinate bisection without the mesh on one rank (distributed_rcb): each rank
  !> computes the centroids of its block, the bisection runs on them distributed, the element rows
  !> move to their owners and fetch the rows of their nodes again.
  subroutine rcb_rows(d, comm, home)
    type(deck_t), intent(inout) :: d
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: home(:, :)
    real(wp), allocatable :: centroids(:, :)
    integer, allocatable :: owner(:), local(:, :)
    logical, allocatable :: used(:)
    integer :: n_ranks, k, n
    call MPI_Comm_size(comm, n_ranks)
    if (n_ranks == 1) return
    allocate (local(4, size(d%element_ids)), centroids(3, size(d%element_ids)), owner(size(d%element_ids)))
    do k = 1, size(d%element_ids)
      local(:, k) = [(node_row(d, d%connectivity(n, k)), n = 1, 4)]
    end do
    call element_centroids(d%coordinates, local, centroids)
    call rcb_owners(comm, d%element_ids, centroids, owner)
    call move_element_rows(comm, owner, d%element_ids, d%connectivity, d%element_part)
    call held_nodes(d, comm, home, used)
  end subroutine rcb_rows

end module deck_checks
