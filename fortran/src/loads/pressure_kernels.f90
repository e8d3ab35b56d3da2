!> Follower pressure on shell faces (LS-DYNA *LOAD_SHELL): the equivalent corner forces of the
!> one-point quadrilateral, p A n / 4 on each corner with A n = (x3 - x1) x (x4 - x2) / 2 from the
!> current positions, and the work they do over a step.
!>
!> Compiled without floating-point contraction (fortran/CMakeLists.txt): an element's forces and
!> work must not depend on where it falls in a loop, so that they are the same on every layout.
module pressure_kernels
  use paradyn_kinds, only: wp
  use vector_algebra, only: cross
  implicit none
  private
  public :: pressure_corner_forces, pressure_step_work, corner_force_per_pressure

contains

  !> p A n / 4 per unit pressure of an element with corners xe(:, 1:4) (counter-clockwise).
  pure function corner_force_per_pressure(xe) result(f)
    real(wp), intent(in) :: xe(3, 4)
    real(wp) :: f(3)
    f = 0.125_wp * cross(xe(:, 3) - xe(:, 1), xe(:, 4) - xe(:, 2))
  end function corner_force_per_pressure

  !> Subtracts the pressure forces of the listed local elements from their corners: corner holds
  !> internal forces (6, 4 x elements), which the velocity update subtracts.
  pure subroutine pressure_corner_forces(elements, connectivity, x, pressure, corner)
    integer, intent(in) :: elements(:), connectivity(:, :)
    real(wp), intent(in) :: x(:, :), pressure
    real(wp), intent(inout) :: corner(:, :)
    integer :: i, e, k
    real(wp) :: f(3)
    do i = 1, size(elements)
      e = elements(i)
      f = pressure * corner_force_per_pressure(x(:, connectivity(:, e)))
      do k = 1, 4
        corner(1:3, 4 * (e - 1) + k) = corner(1:3, 4 * (e - 1) + k) - f
      end do
    end do
  end subroutine pressure_corner_forces

  !> Work of the pressure on the listed elements over a step dt that ended at x, the corners
  !> moving with v (so from x - dt v): the trapezoidal rule between the forces at the start
  !> (pressure p_start) and at the end (p_end), as the solver integrates the work of f_ext.
  pure real(wp) function pressure_step_work(elements, connectivity, x, v, dt, p_start, p_end) result(work)
    integer, intent(in) :: elements(:), connectivity(:, :)
    real(wp), intent(in) :: x(:, :), v(:, :), dt, p_start, p_end
    integer :: i, e
    real(wp) :: xe(3, 4), ve(3, 4), f(3)
    work = 0.0_wp
    do i = 1, size(elements)
      e = elements(i)
      xe = x(:, connectivity(:, e))
      ve = v(:, connectivity(:, e))
      f = p_start * corner_force_per_pressure(xe - dt * ve) + p_end * corner_force_per_pressure(xe)
      work = work + 0.5_wp * dt * dot_product(f, ve(:, 1) + ve(:, 2) + ve(:, 3) + ve(:, 4))
    end do
  end function pressure_step_work

end module pressure_kernels
