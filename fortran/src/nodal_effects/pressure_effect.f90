!> Pressure on the shell faces of parts (LS-DYNA *LOAD_SHELL): p(t) = scale x curve(t) on every
!> element of a part, along the element's current normal (a follower load). The corner forces join
!> the element forces before the corner exchange, so shared nodes sum them in the fixed order. The
!> work is summed per element over this rank's elements, as the element energies are: at each
!> call, what the corner forces did since the last positions (trapezoidal rule in time).
module pressure_effect
  use paradyn_kinds, only: wp
  use paradyn_schema, only: effect_pressure
  use nodal_effect, only: nodal_effect_t, stage_corners
  use load_curves, only: load_curves_t, curve_value, curve_ended_at_zero
  use pressure_kernels, only: pressure_corner_forces
  implicit none
  private
  public :: pressure_effect_t, pressure_effect_make

  type, extends(nodal_effect_t) :: pressure_effect_t
    type(load_curves_t) :: curves
    real(wp), allocatable :: scale(:)           !< Pa, per load
    integer, allocatable :: curve(:)            !< 1-based curve of each load
    integer, allocatable :: first(:)            !< CSR over loads into elements (n_loads + 1)
    integer, allocatable :: elements(:)         !< local elements of each load's part, ascending
    real(wp), allocatable :: f_previous(:, :)   !< (3, entries of elements): corner force at the last call
    real(wp), allocatable :: x_sum_previous(:, :)   !< (3, entries): sum of the corners' positions then
    logical :: have_previous = .false.          !< false until the first call (no work before it)
    real(wp) :: time_previous = 0.0_wp          !< time of the last call
  contains
    procedure :: acts_at
    procedure :: add_corner_forces
    procedure :: idle
  end type pressure_effect_t

contains

  !> The member for the deck's pressure loads (part, scale, curve; 1-based) on this rank's local
  !> elements, whose parts are element_part.
  function pressure_effect_make(curves, part, scale, curve, element_part) result(e)
    type(load_curves_t), intent(in) :: curves
    integer, intent(in) :: part(:), curve(:), element_part(:)
    real(wp), intent(in) :: scale(:)
    type(pressure_effect_t) :: e
    integer :: l, k
    e%id = effect_pressure
    e%curves = curves
    e%scale = scale
    e%curve = curve
    allocate (e%first(size(part) + 1))
    e%first(1) = 1
    do l = 1, size(part)
      e%first(l + 1) = e%first(l) + count(element_part == part(l))
    end do
    allocate (e%elements(e%first(size(part) + 1) - 1))
    do l = 1, size(part)
      e%elements(e%first(l):e%first(l + 1) - 1) = pack([(k, k = 1, size(element_part))], element_part == part(l))
    end do
    allocate (e%f_previous(3, size(e%elements)), e%x_sum_previous(3, size(e%elements)), source=0.0_wp)
  end function pressure_effect_make

  pure logical function acts_at(e, stage)
    class(pressure_effect_t), intent(in) :: e
    integer, intent(in) :: stage
    acts_at = stage == stage_corners
  end function acts_at

  subroutine add_corner_forces(e, connectivity, x, time, corner)
    class(pressure_effect_t), intent(inout) :: e
    integer, intent(in) :: connectivity(:, :)
    real(wp), intent(in) :: x(:, :), time
    real(wp), intent(inout) :: corner(:, :)
    integer :: l
    do l = 1, size(e%scale)
      if (ended(e, l)) cycle
      associate (first => e%first(l), last => e%first(l + 1) - 1)
        call pressure_corner_forces(e%elements(first:last), connectivity, x, &
                                    e%scale(l) * curve_value(e%curves, e%curve(l), time), corner, &
                                    e%f_previous(:, first:last), e%x_sum_previous(:, first:last), &
                                    e%have_previous, e%work)
      end associate
    end do
    e%have_previous = .true.
    e%time_previous = time
  end subroutine add_corner_forces

  !> Idle once every load's curve had ended at zero by the last call: no force now, and none then
  !> to do work since.
  pure logical function idle(e, time)
    class(pressure_effect_t), intent(in) :: e
    real(wp), intent(in) :: time
    integer :: l
    idle = all([(ended(e, l), l = 1, size(e%scale))])
  end function idle

  !> Whether load l had ended at zero by the last call (then it has no force and no more work).
  pure logical function ended(e, l)
    class(pressure_effect_t), intent(in) :: e
    integer, intent(in) :: l
    ended = e%have_previous .and. curve_ended_at_zero(e%curves, e%curve(l), e%time_previous)
  end function ended

end module pressure_effect
