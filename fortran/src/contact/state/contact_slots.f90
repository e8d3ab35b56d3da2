!> The held slots of the contact state (docs/theory.md, "Dividing the contact state"): a rank
!> numbers the contact nodes it holds 1 to n_held in ascending contact-node index, and every
!> per-node array of contact_t (positions, velocities, masses, the forces of two steps, the
!> positions at the last sort, the touched lists and marks, the gather flags) is indexed by that
!> slot. On one rank and in the replicated scheme every contact node is held (slot = index); under
!> local contact a rank holds its domain's contact nodes and its ghosts, renumbered at each refresh
!> of the ghosts (contact_hold). The passes name nodes by contact-node index and keep their slots
!> (contact_pass_slots); slot_of finds any other node's: slot(node) where every node is held,
!> else a search in the held table, so no rank under local contact holds a map sized by the
!> contact nodes of the model. No MPI here.
module contact_slots
  use paradyn_kinds, only: wp
  use integer_sort, only: sorted_position
  use contact_interface, only: contact_t
  implicit none
  private
  public :: contact_node_state, contact_hold, slot_of, contact_pass_slots, contact_pass_slots_moved

contains

  !> The state of the contact nodes held (held: their contact-node ids, ascending; masses, their
  !> local columns on this rank, 0 for none, and whether it owns them, in that order), after
  !> contact_setup: allocated once the caller has released the deck it read. Where every contact
  !> node is held (not c%local) slot(node) is each one's slot.
  subroutine contact_node_state(c, held, masses, columns, owned)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: held(:), columns(:)
    real(wp), intent(in) :: masses(:)
    logical, intent(in) :: owned(:)
    integer :: n, s
    c%held_node = held
    n = size(held)
    c%held_most = n
    if (.not. c%local) then
      allocate (c%slot(c%n_nodes), source=0)
      c%slot(held) = [(s, s = 1, n)]
    end if
    allocate (c%x(3, n), c%v(3, n), c%force(3, n), c%force_old(3, n), c%x_at_sort(3, n), source=0.0_wp)
    c%mass = masses
    c%column = columns
    c%own = owned
    allocate (c%touched(n), c%touched_old(n), c%mark(n), source=0)
    allocate (c%in_gather(n), source=.true.)
  end subroutine contact_node_state

  !> Hold the contact nodes held (indices, ascending) from now on (local contact): the state of a
  !> node held before moves to its new slot (its column and ownership too), a node newly held
  !> starts from zero (a ghost: the caller fills its position, velocity and mass), and the touched
  !> lists keep their order without the nodes no longer held (only the owners, which always hold
  !> their nodes, apply a node's force and count its energy).
  subroutine contact_hold(c, held, to)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: held(:)
    integer, allocatable, intent(out) :: to(:)   !< each old slot's new one (0: no longer held)
    real(wp), allocatable :: x(:, :), v(:, :), force(:, :), force_old(:, :), x_at_sort(:, :), mass(:)
    integer, allocatable :: mark(:), from(:), column(:)
    logical, allocatable :: in_gather(:), own(:)
    integer :: n, s, o
    n = size(held)
    c%held_most = max(c%held_most, n)
    ! both lists ascending: each new slot's old one (from) and each old slot's new one (to), 0 for none
    allocate (from(n), source=0)
    allocate (to(size(c%held_node)), source=0)
    o = 1
    do s = 1, n
      do while (o <= size(c%held_node))
        if (c%held_node(o) >= held(s)) exit
        o = o + 1
      end do
      if (o > size(c%held_node)) exit
      if (c%held_node(o) == held(s)) then
        from(s) = o
        to(o) = s
      end if
    end do
    allocate (x(3, n), v(3, n), force(3, n), force_old(3, n), x_at_sort(3, n), mass(n), source=0.0_wp)
    allocate (mark(n), column(n), source=0)
    allocate (in_gather(n), source=.true.)
    allocate (own(n), source=.false.)
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
      column(s) = c%column(o)
      own(s) = c%own(o)
    end do
    call move_alloc(x, c%x)
    call move_alloc(v, c%v)
    call move_alloc(force, c%force)
    call move_alloc(force_old, c%force_old)
    call move_alloc(x_at_sort, c%x_at_sort)
    call move_alloc(mass, c%mass)
    call move_alloc(mark, c%mark)
    call move_alloc(in_gather, c%in_gather)
    call move_alloc(column, c%column)
    call move_alloc(own, c%own)
    c%held_node = held
    call keep_held(to, c%touched, c%n_touched, n)
    call keep_held(to, c%touched_old, c%n_touched_old, n)
  end subroutine contact_hold

  !> A touched list (old slots, list(1:count)) in new slots (to: each old slot's new one, 0 if no
  !> longer held), without the nodes no longer held, in its order; resized to n.
  pure subroutine keep_held(to, list, count, n)
    integer, intent(in) :: to(:), n
    integer, allocatable, intent(inout) :: list(:)
    integer, intent(inout) :: count
    integer, allocatable :: kept(:)
    integer :: i, m
    allocate (kept(n), source=0)
    m = 0
    do i = 1, count
      if (to(list(i)) == 0) cycle
      m = m + 1
      kept(m) = to(list(i))
    end do
    count = m
    call move_alloc(kept, list)
  end subroutine keep_held

  !> The slot of contact node `node` (0: not held here): slot(node) where every node is held, else
  !> a search in the ascending held_node.
  pure integer function slot_of(c, node) result(s)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: node
    if (allocated(c%slot)) then
      s = c%slot(node)
      return
    end if
    s = sorted_position(c%held_node, node)
    if (s > size(c%held_node)) then
      s = 0
    else if (c%held_node(s) /= node) then
      s = 0
    end if
  end function slot_of

  !> The passes' slots after a refresh that kept their lists (the same segments held): each old
  !> slot's new one (to, from contact_hold); ok is false if one of their nodes is no longer held
  !> (the caller then builds them anew with contact_pass_slots).
  subroutine contact_pass_slots_moved(c, to, ok)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: to(:)
    logical, intent(out) :: ok
    integer :: p
    ok = .true.
    do p = 1, size(c%passes)
      associate (pass => c%passes(p))
      pass%slave_at = to(pass%slave_at)
      if (pass%edges) pass%slave_other_at = to(pass%slave_other_at)
      pass%master_at = to(pass%master_at)
      pass%segment_at = reshape(to(pack(pass%segment_at, .true.)), shape(pass%segment_at))
      ok = ok .and. all(pass%slave_at > 0) .and. all(pass%master_at > 0) .and. all(pass%segment_at > 0)
      if (.not. allocated(pass%own_segments)) cycle
      pass%own_segment_at = reshape(to(pack(pass%own_segment_at, .true.)), shape(pass%own_segment_at))
      ok = ok .and. all(pass%own_segment_at > 0)
      end associate
    end do
  end subroutine contact_pass_slots_moved

  !> The passes' slots of their slaves, masters and segments' nodes, after the slots or the
  !> segments held have changed. Ascending lists are matched against the ascending held table in
  !> one pass (a search per entry cost a fifth of a two-rank run's contact at every refresh), the
  !> segments' nodes through their masters, the own segments through their elements.
  subroutine contact_pass_slots(c)
    type(contact_t), intent(inout) :: c
    integer, allocatable :: own_at(:)
    integer :: p, i, m
    do p = 1, size(c%passes)
      associate (pass => c%passes(p))
      pass%slave_at = held_slots(c, pass%slaves)
      if (pass%edges) pass%slave_other_at = held_slots(c, pass%slave_other)
      pass%master_at = held_slots(c, pass%masters)
      if (allocated(pass%segment_at)) deallocate (pass%segment_at)
      allocate (pass%segment_at(4, size(pass%segments, 2)))
      do i = 1, size(pass%segments, 2)
        do m = 1, 4
          if (allocated(pass%segment_corner)) then
            pass%segment_at(m, i) = pass%master_at(pass%segment_corner(m, i))
          else
            pass%segment_at(m, i) = slot_of(c, pass%segments(m, i))
          end if
        end do
      end do
      if (.not. allocated(pass%own_segments)) cycle
      if (allocated(pass%own_segment_at)) deallocate (pass%own_segment_at)
      allocate (pass%own_segment_at(4, size(pass%own_segments, 2)))
      own_at = places_in(pass%segment_element, pass%own_element)
      do i = 1, size(pass%own_segments, 2)
        do m = 1, 4
          if (own_at(i) > 0) then   ! an own segment is held: its place among the segments
            pass%own_segment_at(m, i) = pass%segment_at(m, own_at(i))
          else
            pass%own_segment_at(m, i) = slot_of(c, pass%own_segments(m, i))
          end if
        end do
      end do
      end associate
    end do
  end subroutine contact_pass_slots

  !> The slots of contact nodes ids, 0 where not held: one merge with the ascending held_node
  !> where ids ascend, else slot_of for each.
  pure function held_slots(c, ids) result(at)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: ids(:)
    integer :: at(size(ids)), i
    if (ascending(ids)) then
      at = merged_places(c%held_node, ids)
    else
      at = [(slot_of(c, ids(i)), i = 1, size(ids))]
    end if
  end function held_slots

  !> The place of each of ids in the ascending table, 0 where absent: one merge where ids ascend,
  !> else a search for each.
  pure function places_in(table, ids) result(at)
    integer, intent(in) :: table(:), ids(:)
    integer :: at(size(ids)), i, t
    if (ascending(ids)) then
      at = merged_places(table, ids)
      return
    end if
    at = 0
    do i = 1, size(ids)
      t = sorted_position(table, ids(i))
      if (t <= size(table)) then
        if (table(t) == ids(i)) at(i) = t
      end if
    end do
  end function places_in

  !> places_in for ascending ids: one pass over both.
  pure function merged_places(table, ids) result(at)
    integer, intent(in) :: table(:), ids(:)
    integer :: at(size(ids)), i, t
    at = 0
    t = 1
    do i = 1, size(ids)
      do while (t <= size(table))
        if (table(t) >= ids(i)) exit
        t = t + 1
      end do
      if (t > size(table)) exit
      if (table(t) == ids(i)) at(i) = t
    end do
  end function merged_places

  pure logical function ascending(ids)
    integer, intent(in) :: ids(:)
    ascending = .true.
    if (size(ids) > 1) ascending = all(ids(2:) >= ids(:size(ids) - 1))
  end function ascending

end module contact_slots
