!> Planar rigid walls (LS-DYNA's *RIGIDWALL_PLANAR and _MOVING): an infinite plane through a point
!> with a unit normal, moving at a constant velocity, that pushes back every node behind it with a
!> penalty spring of stiffness k = scale m / dt^2 (docs/theory.md, "Rigid walls"). Frictionless.
!>
!> Compiled without floating-point contraction (fortran/CMakeLists.txt): a node must get the same
!> force whether it falls in the vector body or the scalar remainder of the loop, whatever the layout.
module rigid_wall
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: wall_position, rigid_wall_forces

contains

  !> The point of the plane at time t: it moves with the wall, the normal stays.
  pure function wall_position(point, velocity, time) result(p)
    real(wp), intent(in) :: point(3), velocity(3), time
    real(wp) :: p(3)
    p = point + time * velocity
  end function wall_position

  !> Adds to force(1:3, j) the penalty force -k_j d_j n of every node j behind the wall at time t:
  !> d_j = (x_j - p(t)) . n < 0, k_j = stiffness_per_mass m_j (stiffness_per_mass = scale / dt^2).
  !> normal is a unit vector; rotations feel nothing (the wall acts on the node, not on the shell).
  pure subroutine rigid_wall_forces(n, x, mass, point, normal, velocity, time, stiffness_per_mass, force)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(3, n), mass(n), point(3), normal(3), velocity(3), time, stiffness_per_mass
    real(wp), intent(inout) :: force(:, :)
    real(wp) :: p(3), d
    integer :: j
    p = wall_position(point, velocity, time)
    do j = 1, n
      d = (x(1, j) - p(1)) * normal(1) + (x(2, j) - p(2)) * normal(2) + (x(3, j) - p(3)) * normal(3)
      if (d < 0.0_wp) force(1:3, j) = force(1:3, j) - (stiffness_per_mass * mass(j) * d) * normal
    end do
  end subroutine rigid_wall_forces

end module rigid_wall
