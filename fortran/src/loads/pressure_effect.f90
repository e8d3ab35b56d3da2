!> Pressure on the shell faces of parts (LS-DYNA *LOAD_SHELL): p(t) = scale x curve(t) on every
!> element of a part, along the element's current normal (a follower load). The corner forces join
!> the element forces before the corner exchange, so shared nodes sum them in the fixed order; the
!> work is summed per element over this rank's elements, as the element energies are, step by step
!> as the solver does for f_ext: at time t, over the step that ended there.
module pressure_effect
  use paradyn_kinds, only: wp
  use nodal_state, only: nodal_state_t
  use nodal_effect, only: nodal_effect_t, stage_loads, stage_corners, stage_constraints
  use load_curves, only: load_curves_t, curve_value, curve_ended_at_zero
  use pressure_kernels, only: pressure_corner_forces, pressure_step_work
  implicit none
  private
  public :: pressure_effect_t, pressure_member

  type, extends(nodal_effect_t) :: pressure_effect_t
    type(load_curves_t) :: curves
    real(wp), allocatable :: scale(:)           !< Pa, per load
    integer, allocatable :: curve(:)            !< 1-based curve of each load
    integer, allocatable :: first(:)            !< CSR over loads into elements (n_loads + 1)
    integer, allocatable :: elements(:)         !< local elements of each load's part, ascending
    integer, allocatable :: connectivity(:, :)  !< (4, local elements): local nodes, for the work
    real(wp) :: dt = 0.0_wp                     !< the step that ends at the next load time (0: unknown)
  contains
    procedure :: add_corner_forces => pressure_add_corner_forces
    procedure :: add_forces => pressure_work_of_last_step
    procedure :: constrain => pressure_keep_step
    procedure :: acts_at => pressure_acts_at
    procedure :: idle => pressure_idle
  end type pressure_effect_t

contains

  !> The member for the deck's pressure loads (part, scale, curve; 1-based) on this rank's elements:
  !> element_part and connectivity of the local elements (local node numbers).
  function pressure_member(id, curves, part, scale, curve, element_part, connectivity) result(e)
    integer, intent(in) :: id, part(:), curve(:), element_part(:), connectivity(:, :)
    type(load_curves_t), intent(in) :: curves
    real(wp), intent(in) :: scale(:)
    type(pressure_effect_t) :: e
    integer :: l, k
    e%id = id
    e%curves = curves
    e%scale = scale
    e%curve = curve
    e%connectivity = connectivity
    allocate (e%first(size(part) + 1))
    e%first(1) = 1
    do l = 1, size(part)
      e%first(l + 1) = e%first(l) + count(element_part == part(l))
    end do
    allocate (e%elements(e%first(size(part) + 1) - 1))
    do l = 1, size(part)
      e%elements(e%first(l):e%first(l + 1) - 1) = pack([(k, k = 1, size(element_part))], element_part == part(l))
    end do
  end function pressure_member

  !> Pressure of load l at time t.
  pure real(wp) function load_pressure(e, l, t) result(p)
    class(pressure_effect_t), intent(in) :: e
    integer, intent(in) :: l
    real(wp), intent(in) :: t
    p = e%scale(l) * curve_value(e%curves, e%curve(l), t)
  end function load_pressure

  subroutine pressure_add_corner_forces(e, connectivity, x, time, corner)
    class(pressure_effect_t), intent(inout) :: e
    integer, intent(in) :: connectivity(:, :)
    real(wp), intent(in) :: x(:, :), time
    real(wp), intent(inout) :: corner(:, :)
    integer :: l
    do l = 1, size(e%scale)
      if (curve_ended_at_zero(e%curves, e%curve(l), time)) cycle
      call pressure_corner_forces(e%elements(e%first(l):e%first(l + 1) - 1), connectivity, x, &
                                  load_pressure(e, l, time), corner)
    end do
  end subroutine pressure_add_corner_forces

  !> No force on the nodes: the work of the step that ended at time (positions x, half-step
  !> velocities v of that step, so it started at x - dt v), by the trapezoidal rule in time.
  subroutine pressure_work_of_last_step(e, ns, time)
    class(pressure_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time
    integer :: l
    if (e%dt <= 0.0_wp) return   ! the start: no step ended yet
    do l = 1, size(e%scale)
      if (curve_ended_at_zero(e%curves, e%curve(l), time - e%dt)) cycle
      e%work = e%work + pressure_step_work(e%elements(e%first(l):e%first(l + 1) - 1), e%connectivity, ns%x, &
                                           ns%v, e%dt, load_pressure(e, l, time - e%dt), load_pressure(e, l, time))
    end do
  end subroutine pressure_work_of_last_step

  !> Not a constraint: keeps the step size, which the next load time's work needs.
  subroutine pressure_keep_step(e, ns, time, dt)
    class(pressure_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time, dt
    e%dt = dt
  end subroutine pressure_keep_step

  logical function pressure_acts_at(e, stage) result(acts)
    class(pressure_effect_t), intent(in) :: e
    integer, intent(in) :: stage
    acts = stage == stage_corners .or. stage == stage_loads .or. stage == stage_constraints
  end function pressure_acts_at

  !> Idle once every load's curve had ended at zero a step ago: no force, and no work of the
  !> step that ends at time.
  logical function pressure_idle(e, time) result(idle)
    class(pressure_effect_t), intent(in) :: e
    real(wp), intent(in) :: time
    integer :: l
    idle = all([(curve_ended_at_zero(e%curves, e%curve(l), time - e%dt), l = 1, size(e%scale))])
  end function pressure_idle

end module pressure_effect
