!> Rotation ties as a member of the nodal effect family (constraints stage, after the rigid
!> bodies): the tied nodes' angular velocities and rotary inertias are gathered from their owners
!> (one owner each, the others add zero: the sum is exact), every rank holds every tie by the same
!> impulses (rotation_ties), and each keeps the nodes it holds. The result is the same on any
!> layout; the cost is one reduction of six numbers per tied node, in proportion to the ties.
module rotation_tie_effect
  use mpi_f08
  use paradyn_kinds, only: wp
  use paradyn_schema, only: effect_rotation_ties
  use nodal_state, only: nodal_state_t
  use nodal_effect, only: nodal_effect_t, stage_constraints
  use rotation_ties, only: tie_rotations
  use domain_decomposition, only: domain_t, local_node
  implicit none
  private
  public :: rotation_tie_effect_t, rotation_tie_effect_make

  type, extends(nodal_effect_t) :: rotation_tie_effect_t
    type(MPI_Comm) :: comm
    integer, allocatable :: slave(:)        !< per tie: its slave, an index into the tied nodes
    integer, allocatable :: masters(:, :)   !< (4, ties): its masters, indices into the tied nodes
    real(wp), allocatable :: weight(:, :)   !< (4, ties)
    integer, allocatable :: local(:)        !< per tied node: the local node, 0 where not held
    integer :: rank = 0
  contains
    procedure :: acts_at
    procedure :: constrain
  end type rotation_tie_effect_t

contains

  !> The member for the ties of the deck: node(k) (global, 1-based) follows masters(:, k) with
  !> weight(:, k); dom: this rank's domain (the nodes it holds).
  function rotation_tie_effect_make(node, masters, weight, dom, comm) result(e)
    integer, intent(in) :: node(:), masters(:, :)
    real(wp), intent(in) :: weight(:, :)
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    type(rotation_tie_effect_t) :: e
    integer, allocatable :: unique(:)
    integer :: k
    e%id = effect_rotation_ties
    e%comm = comm
    call MPI_Comm_rank(comm, e%rank)
    unique = tied_nodes(node, masters)
    e%slave = [(findloc(unique, node(k), dim=1), k = 1, size(node))]
    allocate (e%masters(4, size(node)))
    do k = 1, size(node)
      e%masters(:, k) = [findloc(unique, masters(1, k), dim=1), findloc(unique, masters(2, k), dim=1), &
                         findloc(unique, masters(3, k), dim=1), findloc(unique, masters(4, k), dim=1)]
    end do
    e%weight = weight
    e%local = [(local_node(dom, unique(k)), k = 1, size(unique))]
  end function rotation_tie_effect_make

  !> The global nodes of the ties, ascending, once each (the factory maps them to local nodes).
  pure function tied_nodes(node, masters) result(unique)
    integer, intent(in) :: node(:), masters(:, :)
    integer, allocatable :: unique(:)
    integer, allocatable :: rest(:)
    integer :: n
    rest = [node, reshape(masters, [size(masters)])]
    allocate (unique(0))
    do while (size(rest) > 0)
      n = minval(rest)
      unique = [unique, n]
      rest = pack(rest, rest /= n)
    end do
  end function tied_nodes

  subroutine constrain(e, ns, time, dt, dt_previous)
    class(rotation_tie_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time, dt, dt_previous
    real(wp) :: values(6, size(e%local)), work
    integer :: u, j, n_ranks
    values = 0.0_wp   ! per tied node: w, then 1 / its rotary inertia about each axis (0: held)
    do u = 1, size(e%local)
      j = e%local(u)
      if (j == 0) cycle
      if (ns%weight(j) == 0.0_wp) cycle
      values(1:3, u) = ns%w(:, j)
      if (ns%inertia(j) > 0.0_wp) values(4:6, u) = merge(0.0_wp, 1.0_wp / ns%inertia(j), ns%fixed(4:6, j) /= 0)
    end do
    call MPI_Comm_size(e%comm, n_ranks)
    if (n_ranks > 1) call MPI_Allreduce(MPI_IN_PLACE, values, size(values), MPI_DOUBLE_PRECISION, MPI_SUM, e%comm)
    call tie_rotations(e%slave, e%masters, e%weight, values(4:6, :), values(1:3, :), work)
    if (e%rank == 0) e%work = e%work + work
    do u = 1, size(e%local)
      j = e%local(u)
      if (j > 0) ns%w(:, j) = values(1:3, u)
    end do
  end subroutine constrain

  pure logical function acts_at(e, stage)
    class(rotation_tie_effect_t), intent(in) :: e
    integer, intent(in) :: stage
    acts_at = stage == stage_constraints
  end function acts_at

end module rotation_tie_effect
