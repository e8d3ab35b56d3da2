!> The contact state in a checkpoint (solver_checkpoint): each rank's rows for the contact nodes
!> it owns, the sums over the whole contact, and their restore (a restart redoes the sort at the
!> positions of the last one and refreshes the ghosts before its first step).
module contact_checkpoint
  use paradyn_kinds, only: wp, i8
  use contact_interface, only: contact_restore
  use contact_exchange, only: node_subset_setup
  use contact_parallel, only: parallel_contact_t
  use contact_slots, only: slot_of
  implicit none
  private
  public :: contact_checkpoint_rows, contact_checkpoint_restore, contact_checkpoint_width, contact_checkpoint_sums

  integer, parameter :: contact_checkpoint_width = 7   !< force, position at the last sort, place in the sum

contains

  !> The checkpoint rows of the contact nodes this rank owns (nodes, ascending; every contact node
  !> has one owner, so the ranks' rows together are one per contact node): force, position at the
  !> last sort, and 1 if it carried a force in the last step (0 = no force). The owner holds every
  !> record that touches its node, so its force is the whole one.
  subroutine contact_checkpoint_rows(pc, rows, nodes)
    type(parallel_contact_t), intent(in) :: pc
    real(wp), allocatable, intent(out) :: rows(:, :)
    integer, allocatable, intent(out) :: nodes(:)
    integer, allocatable :: slots(:)
    integer :: k
    nodes = pc%nodes%owned_member
    allocate (slots(size(nodes)))
    do k = 1, size(nodes)
      slots(k) = slot_of(pc%c, nodes(k))
    end do
    allocate (rows(contact_checkpoint_width, size(nodes)))
    rows(1:3, :) = pc%c%force(:, slots)
    rows(4:6, :) = pc%c%x_at_sort(:, slots)
    rows(7, :) = 0.0_wp
    if (pc%c%n_touched == 0) return   ! (before the first step every mark equals the stamp, 0)
    do k = 1, size(nodes)
      if (pc%c%mark(slots(k)) == pc%c%stamp) rows(7, k) = 1.0_wp
    end do
  end subroutine contact_checkpoint_rows

  !> The checkpoint's sums over the whole contact: the energy, the deepest penetration and the
  !> force on each definition (sums(3 + 3 k - 2 : 3 + 3 k) for definition k), the same on every
  !> rank (exact sums added over the ranks: contact_stages, contact_finish).
  subroutine contact_checkpoint_sums(pc, sums)
    type(parallel_contact_t), intent(in) :: pc
    real(wp), intent(out) :: sums(:)
    sums(1) = pc%c%energy
    sums(2) = pc%c%max_penetration
    sums(3:) = reshape(pc%c%definition_force, [size(sums) - 2])
  end subroutine contact_checkpoint_sums

  !> The contact state of a checkpoint (the rows of contact_checkpoint_rows of the nodes held, in
  !> held_node's order, and the attributes).
  subroutine contact_checkpoint_restore(pc, rows, last_sort, energy, max_penetration)
    type(parallel_contact_t), intent(inout) :: pc
    real(wp), intent(in) :: rows(:, :), energy, max_penetration
    integer(i8), intent(in) :: last_sort
    logical :: new_gather_set
    integer :: places(size(rows, 2)), k, n
    ! the nodes that carried a force, in ascending order (their order no longer matters: the
    ! energy's sum is exact, and each node's force is its own sum)
    n = 0
    places = 0
    do k = 1, size(rows, 2)
      if (rows(7, k) <= 0.0_wp) cycle
      n = n + 1
      places(k) = n
    end do
    call contact_restore(pc%c, rows(1:3, :), places, rows(4:6, :), last_sort, energy, &
                         max_penetration, new_gather_set)
    if (new_gather_set) call node_subset_setup(pc%nodes, pc%c%in_gather)
    pc%nb%refresh_pending = .true.
  end subroutine contact_checkpoint_restore

end module contact_checkpoint
