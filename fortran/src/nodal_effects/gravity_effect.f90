!> Gravity (LS-DYNA *LOAD_BODY): a constant acceleration g on every node, the force m g on its
!> translations (rotations untouched). The solver integrates the work of f_ext itself.
module gravity_effect
  use paradyn_kinds, only: wp
  use paradyn_schema, only: effect_gravity
  use nodal_state, only: nodal_state_t
  use nodal_effect, only: nodal_effect_t, stage_loads
  implicit none
  private
  public :: gravity_effect_t, gravity_effect_make, gravity_forces

  type, extends(nodal_effect_t) :: gravity_effect_t
    real(wp) :: g(3) = 0.0_wp   !< m/s^2
  contains
    procedure :: acts_at
    procedure :: add_forces
  end type gravity_effect_t

contains

  !> The member for the body acceleration g (the deck's /control gravity_x, _y, _z).
  function gravity_effect_make(g) result(e)
    real(wp), intent(in) :: g(3)
    type(gravity_effect_t) :: e
    e%id = effect_gravity
    e%g = g
  end function gravity_effect_make

  !> Adds m g to the translational external forces of every node.
  pure subroutine gravity_forces(g, mass, force_external)
    real(wp), intent(in) :: g(3), mass(:)
    real(wp), intent(inout) :: force_external(:, :)
    integer :: j
    do j = 1, size(mass)
      force_external(1:3, j) = force_external(1:3, j) + mass(j) * g
    end do
  end subroutine gravity_forces

  subroutine add_forces(e, ns, time)
    class(gravity_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time
    call gravity_forces(e%g, ns%mass, ns%f_ext)
  end subroutine add_forces

  pure logical function acts_at(e, stage)
    class(gravity_effect_t), intent(in) :: e
    integer, intent(in) :: stage
    acts_at = stage == stage_loads
  end function acts_at

end module gravity_effect
