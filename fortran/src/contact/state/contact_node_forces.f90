!> The contact forces of the last step on the nodes a rank holds: subtracted from the internal
!> forces (they act like external ones), and read back for the frames (LS-DYNA's NCFORC). Only the
!> nodes touched in the step have a force.
module contact_node_forces
  use paradyn_kinds, only: wp
  use contact_interface, only: contact_t
  implicit none
  private
  public :: contact_apply_forces, contact_add_nodal_forces

contains

  !> f_int (6, local nodes) less each touched node's contact force.
  pure subroutine contact_apply_forces(c, f_int)
    type(contact_t), intent(in) :: c
    real(wp), intent(inout) :: f_int(:, :)
    call add_touched(c, -1.0_wp, f_int)
  end subroutine contact_apply_forces

  !> force (3, local nodes) plus each touched node's contact force.
  pure subroutine contact_add_nodal_forces(c, force)
    type(contact_t), intent(in) :: c
    real(wp), intent(inout) :: force(:, :)
    call add_touched(c, 1.0_wp, force)
  end subroutine contact_add_nodal_forces

  !> values(1:3, node) + sign x each touched node's contact force (sign +-1: exact, so f - x and
  !> f + (-1) x are the same bits).
  pure subroutine add_touched(c, sign, values)
    type(contact_t), intent(in) :: c
    real(wp), intent(in) :: sign
    real(wp), intent(inout) :: values(:, :)
    integer :: i, k, j
    do i = 1, c%n_touched
      k = c%touched(i)
      j = c%column(k)
      if (j > 0) values(1:3, j) = values(1:3, j) + sign * c%force(:, k)
    end do
  end subroutine add_touched

end module contact_node_forces
