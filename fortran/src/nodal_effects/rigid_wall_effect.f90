!> Planar rigid walls as a member of the nodal effect family: at the start of a step, the penalty
!> force on every node behind a wall goes into the nodes' external forces (kernel: rigid_wall), so
!> its work, the springs' stored energy and a moving wall's work, counts as external work.
module rigid_wall_effect
  use paradyn_kinds, only: wp
  use paradyn_schema, only: effect_rigid_wall
  use nodal_state, only: nodal_state_t
  use nodal_effect, only: nodal_effect_t, stage_loads
  use rigid_wall, only: rigid_wall_forces
  implicit none
  private
  public :: rigid_wall_effect_t, rigid_wall_effect_make

  type, extends(nodal_effect_t) :: rigid_wall_effect_t
    integer :: n_walls = 0
    real(wp), allocatable :: point(:, :)           !< (3, n_walls), a point of each plane at time 0
    real(wp), allocatable :: normal(:, :)          !< (3, n_walls), unit, towards the model
    real(wp), allocatable :: velocity(:, :)        !< (3, n_walls)
    real(wp), allocatable :: stiffness_per_mass(:) !< penalty_scale / dt^2: k = this times the node's mass
  contains
    procedure :: acts_at
    procedure :: add_forces
  end type rigid_wall_effect_t

contains

  !> The member from the deck's walls ((3, n_walls) and (n_walls)) for a run of step dt.
  function rigid_wall_effect_make(point, normal, velocity, penalty_scale, dt) result(e)
    real(wp), intent(in) :: point(:, :), normal(:, :), velocity(:, :), penalty_scale(:), dt
    type(rigid_wall_effect_t) :: e
    integer :: w
    e%id = effect_rigid_wall
    e%n_walls = size(point, 2)
    e%point = point
    e%velocity = velocity
    allocate (e%normal(3, e%n_walls))
    do w = 1, e%n_walls   ! the deck checks that no normal is zero
      e%normal(:, w) = normal(:, w) / norm2(normal(:, w))
    end do
    e%stiffness_per_mass = penalty_scale / dt**2
  end function rigid_wall_effect_make

  pure logical function acts_at(e, stage)
    class(rigid_wall_effect_t), intent(in) :: e
    integer, intent(in) :: stage
    acts_at = stage == stage_loads
  end function acts_at

  subroutine add_forces(e, ns, time)
    class(rigid_wall_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time
    integer :: w
    do w = 1, e%n_walls
      call rigid_wall_forces(ns%n, ns%x, ns%mass, e%point(:, w), e%normal(:, w), e%velocity(:, w), time, &
                             e%stiffness_per_mass(w), ns%f_ext)
    end do
  end subroutine add_forces

end module rigid_wall_effect
