!> Whether a quadrilateral can be a shell element at all: convex, with no coincident or collinear
!> corners. A concave or collapsed element turns inside out at the first step (issue 17); named
!> before the run, the user can remesh it. A triangle (third node repeated as the fourth) only needs
!> an area: its three corners neither coincident nor collinear.
module quad_shape
  use paradyn_kinds, only: wp
  use vector_algebra, only: cross
  implicit none
  private
  public :: quad_shape_fault, triangle_shape_fault, shape_sound, shape_degenerate, shape_concave

  integer, parameter :: shape_sound = 0
  integer, parameter :: shape_degenerate = 1   !< coincident or collinear corners, or crossed sides: no area
  integer, parameter :: shape_concave = 2      !< a corner turns the other way (a concave or bow-tie quad)

contains

  !> The fault of the quadrilateral x(:, 1:4) (corners in connectivity order) and the corner (1..4)
  !> where it shows: at each corner, the turn from the incoming to the outgoing side must point
  !> along the element normal (the cross product of the diagonals), by more than round-off.
  pure subroutine quad_shape_fault(x, fault, corner)
    real(wp), intent(in) :: x(3, 4)
    integer, intent(out) :: fault, corner
    real(wp) :: normal(3), turn, floor
    integer :: k
    normal = cross(x(:, 3) - x(:, 1), x(:, 4) - x(:, 2))
    floor = 1.0e-10_wp * dot_product(normal, normal)
    fault = shape_sound
    corner = 0
    do k = 1, 4
      turn = dot_product(cross(x(:, k) - x(:, modulo(k - 2, 4) + 1), x(:, modulo(k, 4) + 1) - x(:, k)), normal)
      if (abs(turn) <= floor .or. floor == 0.0_wp) then
        fault = shape_degenerate
      else if (turn < 0.0_wp) then
        fault = shape_concave
      end if
      if (fault /= shape_sound) then
        corner = k
        return
      end if
    end do
  end subroutine quad_shape_fault

  !> The fault of the triangle x(:, 1:3): shape_degenerate (at corner 1) when twice its area is at
  !> most 1e-5 of its longest side squared (coincident or collinear corners), else shape_sound.
  pure subroutine triangle_shape_fault(x, fault, corner)
    real(wp), intent(in) :: x(3, 3)
    integer, intent(out) :: fault, corner
    real(wp) :: normal(3), longest
    normal = cross(x(:, 2) - x(:, 1), x(:, 3) - x(:, 1))
    longest = max(sum((x(:, 2) - x(:, 1))**2), sum((x(:, 3) - x(:, 2))**2), sum((x(:, 1) - x(:, 3))**2))
    fault = shape_sound
    corner = 0
    if (dot_product(normal, normal) <= 1.0e-10_wp * longest**2) then
      fault = shape_degenerate
      corner = 1
    end if
  end subroutine triangle_shape_fault

end module quad_shape
