!> Follower pressure on shell faces (LS-DYNA *LOAD_SHELL): the equivalent corner forces of the
!> one-point quadrilateral, p A n / 4 on each corner with A n = (x3 - x1) x (x4 - x2) / 2 from the
!> current positions, and the work they did since the last positions. A triangle (third node
!> repeated as the fourth) puts p A n / 3 on each of its three corners, none on the fourth.
!>
!> Compiled without floating-point contraction (fortran/CMakeLists.txt): an element's forces and
!> work must not depend on where it falls in a loop, so that they are the same on every layout.
module pressure_kernels
  use paradyn_kinds, only: wp
  use vector_algebra, only: cross
  implicit none
  private
  public :: pressure_corner_forces, corner_force_per_pressure

contains

  !> p A n / 4 per unit pressure of an element with corners xe(:, 1:4) (counter-clockwise).
  pure function corner_force_per_pressure(xe) result(f)
    real(wp), intent(in) :: xe(3, 4)
    real(wp) :: f(3)
    f = 0.125_wp * cross(xe(:, 3) - xe(:, 1), xe(:, 4) - xe(:, 2))
  end function corner_force_per_pressure

  !> Subtracts the pressure forces of the listed local elements from their corners (6, 4 x
  !> elements), which hold internal forces (the velocity update subtracts them). With
  !> have_previous, adds to work what each element's corner force f did since the last call, when
  !> it was f_previous and the sum of its corners' positions was x_sum_previous (trapezoidal rule:
  !> the four corners, or a triangle's three, carry the same force); then keeps this call's f and sum.
  pure subroutine pressure_corner_forces(elements, connectivity, x, pressure, corner, f_previous, &
                                         x_sum_previous, have_previous, work)
    integer, intent(in) :: elements(:), connectivity(:, :)
    real(wp), intent(in) :: x(:, :), pressure
    real(wp), intent(inout) :: corner(:, :), f_previous(:, :), x_sum_previous(:, :), work
    logical, intent(in) :: have_previous
    integer :: i, e, k
    real(wp) :: xe(3, 4), f(3), x_sum(3)
    do i = 1, size(elements)
      e = elements(i)
      xe = x(:, connectivity(:, e))
      if (connectivity(3, e) == connectivity(4, e)) then
        f = (pressure / 6.0_wp) * cross(xe(:, 2) - xe(:, 1), xe(:, 3) - xe(:, 1))
        x_sum = xe(:, 1) + xe(:, 2) + xe(:, 3)
      else
        f = pressure * corner_force_per_pressure(xe)
        x_sum = xe(:, 1) + xe(:, 2) + xe(:, 3) + xe(:, 4)
      end if
      if (have_previous) work = work + 0.5_wp * dot_product(f_previous(:, i) + f, x_sum - x_sum_previous(:, i))
      do k = 1, merge(3, 4, connectivity(3, e) == connectivity(4, e))
        corner(1:3, 4 * (e - 1) + k) = corner(1:3, 4 * (e - 1) + k) - f
      end do
      f_previous(:, i) = f
      x_sum_previous(:, i) = x_sum
    end do
  end subroutine pressure_corner_forces

end module pressure_kernels
