!> Prescribed nodal velocities (LS-DYNA *BOUNDARY_PRESCRIBED_MOTION_NODE, VAD = 0): after each
!> velocity update, a dof's half-step velocity becomes scale x curve(t + dt / 2), so the node's
!> displacement is the midpoint-rule integral of the curve. The reaction that imposes it does work,
!> counted on the owned nodes; a prescribed zero still holds the node, so the member is never idle.
!> A motion with a birth and a death (LS-DYNA BIRTH, DEATH) acts on the steps whose midpoint
!> t + dt / 2 lies between them: before and after, the dof is free (its own velocity, its forces);
!> at the first step it acts, the reaction's work takes the free velocity as the last step's.
module prescribed_velocity
  use paradyn_kinds, only: wp
  use paradyn_schema, only: effect_prescribed_velocity
  use nodal_state, only: nodal_state_t
  use nodal_effect, only: nodal_effect_t, stage_constraints
  use load_curves, only: load_curves_t, curve_value
  implicit none
  private
  public :: prescribed_velocity_t, prescribed_velocity_make, impose_velocities

  type, extends(nodal_effect_t) :: prescribed_velocity_t
    type(load_curves_t) :: curves
    integer, allocatable :: node(:), dof(:), curve(:)   !< local node, dof 1..6, 1-based curve
    real(wp), allocatable :: scale(:)                   !< m/s or rad/s
    real(wp), allocatable :: initial(:)                 !< the dof's velocity at t = 0
    real(wp), allocatable :: target(:), previous(:)     !< workspace: this and the last step's velocity
    real(wp), allocatable :: birth(:), death(:)         !< the motion acts while birth <= t + dt / 2 <= death
    logical :: lives = .false.                          !< some motion has a birth or a death
    logical, allocatable :: acting(:)                   !< workspace: the rows acting this step
  contains
    procedure :: acts_at
    procedure :: constrain
  end type prescribed_velocity_t

contains

  !> The member for the deck's prescribed velocities: local node of each (0 where this rank does
  !> not hold it; those rows are dropped), dof, scale, curve, and the dof's initial velocity.
  function prescribed_velocity_make(curves, local_node, dof, scale, curve, initial, birth, death) result(e)
    integer, intent(in) :: local_node(:), dof(:), curve(:)
    type(load_curves_t), intent(in) :: curves
    real(wp), intent(in) :: scale(:), initial(:), birth(:), death(:)
    type(prescribed_velocity_t) :: e
    logical :: held(size(local_node))
    held = local_node > 0
    e%id = effect_prescribed_velocity
    e%curves = curves
    e%node = pack(local_node, held)
    e%dof = pack(dof, held)
    e%curve = pack(curve, held)
    e%scale = pack(scale, held)
    e%initial = pack(initial, held)
    e%birth = pack(birth, held)
    e%death = pack(death, held)
    e%lives = any(e%birth > 0.0_wp) .or. any(e%death < 1.0e20_wp)
    allocate (e%target(size(e%node)), e%previous(size(e%node)), e%acting(size(e%node)))
  end function prescribed_velocity_make

  !> Sets dof(i) of node(i) to target(i) and adds the reaction's work on the nodes of weight 1:
  !> the impulse m (target - v_free) times the mean of the velocities before and after the step
  !> (previous, target), which is what central differences turn into kinetic energy.
  pure subroutine impose_velocities(node, dof, target, previous, mass, inertia, weight, v, w, work)
    integer, intent(in) :: node(:), dof(:)
    real(wp), intent(in) :: target(:), previous(:), mass(:), inertia(:), weight(:)
    real(wp), intent(inout) :: v(:, :), w(:, :), work
    integer :: i, j
    real(wp) :: free, m
    do i = 1, size(node)
      j = node(i)
      if (dof(i) <= 3) then
        free = v(dof(i), j)
        m = mass(j)
        v(dof(i), j) = target(i)
      else
        free = w(dof(i) - 3, j)
        m = inertia(j)
        w(dof(i) - 3, j) = target(i)
      end if
      work = work + weight(j) * 0.5_wp * m * (target(i) - free) * (previous(i) + target(i))
    end do
  end subroutine impose_velocities

  !> The half-step velocity of the step from time to time + dt; the last step's was set here too,
  !> from the curve at time - dt_previous / 2 (the initial velocity before the first step).
  subroutine constrain(e, ns, time, dt, dt_previous)
    class(prescribed_velocity_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time, dt, dt_previous
    integer :: i
    do i = 1, size(e%node)
      e%target(i) = e%scale(i) * curve_value(e%curves, e%curve(i), time + 0.5_wp * dt)
      e%previous(i) = e%scale(i) * curve_value(e%curves, e%curve(i), time - 0.5_wp * dt_previous)
    end do
    if (time <= 0.0_wp) e%previous = e%initial
    if (.not. e%lives) then
      call impose_velocities(e%node, e%dof, e%target, e%previous, ns%mass, ns%inertia, ns%weight, ns%v, ns%w, e%work)
      return
    end if
    do i = 1, size(e%node)   ! the rows alive this step; one born now had its own velocity last step
      e%acting(i) = e%birth(i) <= time + 0.5_wp * dt .and. time + 0.5_wp * dt <= e%death(i)
      if (e%acting(i) .and. time > 0.0_wp .and. e%birth(i) > time - 0.5_wp * dt_previous) &
        e%previous(i) = free_velocity(i)
    end do
    call impose_velocities(pack(e%node, e%acting), pack(e%dof, e%acting), pack(e%target, e%acting), &
                           pack(e%previous, e%acting), ns%mass, ns%inertia, ns%weight, ns%v, ns%w, e%work)
  contains
    real(wp) function free_velocity(i) result(v)
      integer, intent(in) :: i
      if (e%dof(i) <= 3) then
        v = ns%v(e%dof(i), e%node(i))
      else
        v = ns%w(e%dof(i) - 3, e%node(i))
      end if
    end function free_velocity
  end subroutine constrain

  pure logical function acts_at(e, stage)
    class(prescribed_velocity_t), intent(in) :: e
    integer, intent(in) :: stage
    acts_at = stage == stage_constraints
  end function acts_at

end module prescribed_velocity
