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
    do k = 1, 4
      do c = 1, size(nodal, 1)
        do i = 1, n
          grouped(i, c, k) = nodal(c, connectivity(k, first + i - 1))
        end do
      end do
    end do
  end subroutine gather_group

  !> nodal(:, j) = sum of corner(:, slot(s)) for s = start(j) .. start(j + 1) - 1, in that order.
  pure subroutine assemble_nodes(n_nodes, start, slot, corner, nodal)
    integer, intent(in) :: n_nodes
    integer, intent(in) :: start(n_nodes + 1), slot(:)
    real(wp), intent(in) :: corner(:, :)
    real(wp), intent(out) :: nodal(size(corner, 1), n_nodes)
    integer :: j, s
    do j = 1, n_nodes
      nodal(:, j) = 0.0_wp
      do s = start(j), start(j + 1) - 1
        nodal(:, j) = nodal(:, j) + corner(:, slot(s))
      end do
    end do
  end subroutine assemble_nodes

end module nodal_assembly
