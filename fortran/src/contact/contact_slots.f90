!> The held slots of the contact state (docs/theory.md, "Dividing the contact state"): a rank
!> numbers the contact nodes it holds 1 to n_held in ascending contact-node index, and every
!> per-node array of contact_t (positions, velocities, masses, the forces of two steps, the
!> positions at the last sort, the touched lists and marks, the gather flags) is indexed by that
!> slot. On one rank and in the replicated scheme every contact node is held (slot = index); under
!> local contact a rank holds its domain's contact nodes and its ghosts, renumbered at each refresh
!> of the ghosts (contact_hold). The passes still name nodes by contact-node index and reach the
!> arrays through c%slot (4 bytes per contact node of the model): the intermediate step of the
!> design, before the passes' lists are the rank's own. No MPI here.
module contact_slots
  use paradyn_kinds, only: wp
  use contact_interface, only: contact_t
  implicit none
  private
  public :: contact_node_state, contact_hold

contains

  !> The state of the contact nodes held (held(k): contact node k is), after contact_setup:
  !> allocated once the caller has released the deck it read; masses: every contact node's mass
  !> (those of the nodes held are kept).
  subroutine contact_node_state(c, held, masses)
    type(contact_t), intent(inout) :: c
    logical, intent(in) :: held(:)
    real(wp), intent(in) :: masses(:)
    integer :: n, s
    c%held_node = pack([(s, s = 1, c%n_nodes)], held)
    n = size(c%held_node)
    c%held_most = n
    allocate (c%slot(c%n_nodes), source=0)
    c%slot(c%held_node) = [(s, s = 1, n)]
    allocate (c%x(3, n), c%v(3, n), c%force(3, n), c%force_old(3, n), c%x_at_sort(3, n), source=0.0_wp)
    c%mass = masses(c%held_node)
    allocate (c%touched(n), c%touched_old(n), c%mark(n), source=0)
    allocate (c%in_gather(n), source=.true.)
  end subroutine contact_node_state

  !> Hold the contact nodes held (indices, ascending) from now on: the state of a node held before
  !> moves to its new slot, a node newly held starts from zero (the caller fills its position,
  !> velocity and mass), and the touched lists keep their order without the nodes no longer held
  !> (only the owners, which always hold their nodes, apply a node's force and count its energy).
  subroutine contact_hold(c, held)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: held(:)
    real(wp), allocatable :: x(:, :), v(:, :), force(:, :), force_old(:, :), x_at_sort(:, :), mass(:)
    integer, allocatable :: mark(:), from(:), old_node(:)
    logical, allocatable :: in_gather(:)
    integer :: n, s, o
    n = size(held)
    c%held_most = max(c%held_most, n)
    allocate (from(n))
    from = c%slot(held)
    allocate (x(3, n), v(3, n), force(3, n), force_old(3, n), x_at_sort(3, n), mass(n), source=0.0_wp)
    allocate (mark(n), source=0)
    allocate (in_gather(n), source=.true.)
    do s = 1, n
      o = from(s)
      if (o == 0) cycle
      x(:, s) = c%x(:, o)
      v(:, s) = c%v(:, o)
      force(:, s) = c%force(:, o)
      force_old(:, s) = c%force_old(:, o)
      x_at_sort(:, s) = c%x_at_sort(:, o)
      mass(s) = c%mass(o)
      mark(s) = c%mark(o)
      in_gather(s) = c%in_gather(o)
    end do
    call move_alloc(x, c%x)
    call move_alloc(v, c%v)
    call move_alloc(force, c%force)
    call move_alloc(force_old, c%force_old)
    call move_alloc(x_at_sort, c%x_at_sort)
    call move_alloc(mass, c%mass)
    call move_alloc(mark, c%mark)
    call move_alloc(in_gather, c%in_gather)
    call move_alloc(c%held_node, old_node)
    c%slot(old_node) = 0
    c%slot(held) = [(s, s = 1, n)]
    c%held_node = held
    call keep_held(c%slot, old_node, c%touched, c%n_touched, n)
    call keep_held(c%slot, old_node, c%touched_old, c%n_touched_old, n)
  end subroutine contact_hold

  !> A touched list (old slots, list(1:count)) in new slots, without the nodes no longer held, in
  !> its order; resized to n.
  pure subroutine keep_held(slot, old_node, list, count, n)
    integer, intent(in) :: slot(:), old_node(:), n
    integer, allocatable, intent(inout) :: list(:)
    integer, intent(inout) :: count
    integer, allocatable :: kept(:)
    integer :: i, m
    allocate (kept(n), source=0)
    m = 0
    do i = 1, count
      if (slot(old_node(list(i))) == 0) cycle
      m = m + 1
      kept(m) = slot(old_node(list(i)))
    end do
    count = m
    call move_alloc(kept, list)
  end subroutine keep_held

end module contact_slots
