!> Moving data between nodes and element groups, and the fixed-order nodal sum.
!>
!> Element kernels write per-corner forces; each node then sums the corners that touch it in
!> ascending global element order. The sum has no races (no atomics) and gives the same bits for
!> any number of threads or ranks.
module nodal_assembly
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: gather_group, assemble_nodes

contains

  !> Copy the nodal values of elements first..first+n-1 into group arrays a(i, component, corner).
  !> Element index innermost: the compiler gathers several elements' values per instruction.
  pure subroutine gather_group(n, first, connectivity, nodal, grouped)
    integer, intent(in) :: n, first
    integer, intent(in) :: connectivity(:, :)
    real(wp), intent(in) :: nodal(:, :)
    real(wp), intent(out) :: grouped(n, size(nodal, 1), 4)
    integer :: i, k, c
    if (size(nodal, 1) == 3) then   ! positions, velocities, angular velocities
      call gather_three(n, first, size(connectivity, 2), connectivity, size(nodal, 2), nodal, grouped)
      return
    end if
    do k = 1, 4
      do c = 1, size(nodal, 1)
        do i = 1, n
          grouped(i, c, k) = nodal(c, connectivity(k, first + i - 1))
        end do
      end do
    end do
  end subroutine gather_group

  !> gather_group with three components and extents the compiler knows (a fifth faster).
  pure subroutine gather_three(n, first, n_elements, connectivity, n_nodes, nodal, grouped)
    integer, intent(in) :: n, first, n_elements, n_nodes
    integer, intent(in) :: connectivity(4, n_elements)
    real(wp), intent(in) :: nodal(3, n_nodes)
    real(wp), intent(out) :: grouped(n, 3, 4)
    integer :: i, k, c
    do k = 1, 4
      do c = 1, 3
        do i = 1, n
          grouped(i, c, k) = nodal(c, connectivity(k, first + i - 1))
        end do
      end do
    end do
  end subroutine gather_three

  !> nodal(:, j) = sum of corner(:, slot(s)) for s = start(j) .. start(j + 1) - 1, in that order.
  pure subroutine assemble_nodes(n_nodes, start, slot, corner, nodal)
    integer, intent(in) :: n_nodes
    integer, intent(in) :: start(n_nodes + 1), slot(:)
    real(wp), intent(in) :: corner(:, :)
    real(wp), intent(out) :: nodal(size(corner, 1), n_nodes)
    integer :: j, s
    if (size(corner, 1) == 6) then   ! the engine's forces and masses
      call assemble_six(n_nodes, size(corner, 2), start, slot, corner, nodal)
      return
    end if
    do j = 1, n_nodes
      nodal(:, j) = 0.0_wp
      do s = start(j), start(j + 1) - 1
        nodal(:, j) = nodal(:, j) + corner(:, slot(s))
      end do
    end do
  end subroutine assemble_nodes

  !> assemble_nodes with six components: extents the compiler knows make each corner's sum six
  !> straight adds instead of a loop of unknown length (a third of the time of the general loop,
  !> docs/performance.md); the same adds in the same order, so the same bits.
  pure subroutine assemble_six(n_nodes, n_corners, start, slot, corner, nodal)
    integer, intent(in) :: n_nodes, n_corners
    integer, intent(in) :: start(n_nodes + 1), slot(:)
    real(wp), intent(in) :: corner(6, n_corners)
    real(wp), intent(out) :: nodal(6, n_nodes)
    integer :: j, s
    do j = 1, n_nodes
      nodal(:, j) = 0.0_wp
      do s = start(j), start(j + 1) - 1
        nodal(:, j) = nodal(:, j) + corner(:, slot(s))
      end do
    end do
  end subroutine assemble_six

end module nodal_assembly
