!> Base accelerations (LS-DYNA *LOAD_BODY_X/Y/Z with a load curve): the body acceleration of the
!> non-inertial frame of a shaken support, a(t) = sum over the rows of value x curve(t) x the unit
!> vector of direction, on every node; the force m a(t) on its translations (rotations untouched),
!> at the loads stage. The solver integrates the work of f_ext itself.
module base_acceleration_effect
  use paradyn_kinds, only: wp
  use paradyn_schema, only: effect_base_acceleration
  use nodal_state, only: nodal_state_t
  use nodal_effect, only: nodal_effect_t, stage_loads
  use load_curves, only: load_curves_t, curve_value, curve_ended_at_zero
  use gravity_effect, only: gravity_forces
  implicit none
  private
  public :: base_acceleration_effect_t, base_acceleration_effect_make

  type, extends(nodal_effect_t) :: base_acceleration_effect_t
    type(load_curves_t) :: curves
    real(wp), allocatable :: direction(:, :)   !< (3, rows): unit vectors (0 where the deck's is 0)
    real(wp), allocatable :: scale(:)          !< m/s^2, per row
    integer, allocatable :: curve(:)           !< 1-based curve of each row
  contains
    procedure :: acts_at
    procedure :: add_forces
    procedure :: idle
  end type base_acceleration_effect_t

contains

  !> The member for the deck's base accelerations: directions (3, rows), values and curves
  !> (1-based), over the deck's curves.
  function base_acceleration_effect_make(curves, direction, value, curve) result(e)
    type(load_curves_t), intent(in) :: curves
    real(wp), intent(in) :: direction(:, :), value(:)
    integer, intent(in) :: curve(:)
    type(base_acceleration_effect_t) :: e
    integer :: k
    real(wp) :: length
    e%id = effect_base_acceleration
    e%curves = curves
    e%scale = value
    e%curve = curve
    allocate (e%direction(3, size(value)), source=0.0_wp)
    do k = 1, size(value)
      length = norm2(direction(:, k))
      if (length > 0.0_wp) e%direction(:, k) = direction(:, k) / length
    end do
  end function base_acceleration_effect_make

  !> The acceleration of every node at time: the rows summed in deck order (the same on every rank).
  pure function acceleration(e, time) result(a)
    class(base_acceleration_effect_t), intent(in) :: e
    real(wp), intent(in) :: time
    real(wp) :: a(3)
    integer :: k
    a = 0.0_wp
    do k = 1, size(e%scale)
      a = a + (e%scale(k) * curve_value(e%curves, e%curve(k), time)) * e%direction(:, k)
    end do
  end function acceleration

  subroutine add_forces(e, ns, time)
    class(base_acceleration_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time
    call gravity_forces(acceleration(e, time), ns%mass, ns%f_ext)   ! m a on the translations, as gravity
  end subroutine add_forces

  pure logical function acts_at(e, stage)
    class(base_acceleration_effect_t), intent(in) :: e
    integer, intent(in) :: stage
    acts_at = stage == stage_loads
  end function acts_at

  !> Idle once every row's curve has ended at zero: no force from then on.
  pure logical function idle(e, time)
    class(base_acceleration_effect_t), intent(in) :: e
    real(wp), intent(in) :: time
    integer :: k
    idle = all([(curve_ended_at_zero(e%curves, e%curve(k), time), k = 1, size(e%scale))])
  end function idle

end module base_acceleration_effect
