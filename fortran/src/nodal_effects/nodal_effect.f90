!> The family of effects that act on the nodes (docs/architecture.md, families): loads at the
!> start of a step, constraints on the velocities after their update, and loads on element
!> corners before the corner exchange. A member overrides the hooks it uses and says so in
!> acts_at; the solver's pipeline calls only those, and only for the members the deck declares
!> (effect_factory), so an effect the scene does not call for costs nothing. A member with a state
!> of its own (the rigid bodies' motion) gives it to checkpoints through state_words; a member
!> whose forces the history reports (the rigid walls' RWFORC) gives their exact sums through history_sums,
!> one whose constraints can let go (the welds) counts them in failures.
module nodal_effect
  use paradyn_kinds, only: wp, i8
  use nodal_state, only: nodal_state_t
  implicit none
  private
  public :: nodal_effect_t, nodal_effect_holder_t, stage_loads, stage_constraints, stage_corners

  integer, parameter :: stage_loads = 1        !< add_forces: forces at time t on the nodes' f_ext
  integer, parameter :: stage_constraints = 2  !< constrain: after the half-step velocity update
  integer, parameter :: stage_corners = 3      !< add_corner_forces: on element corners, before their exchange

  type, abstract :: nodal_effect_t
    integer :: id = 0              !< the effect's id in paradyn_schema (effect_<name>)
    !> work done on the model so far by a member that accounts for its own (constraints, corner
    !> loads), over this rank's owned nodes or its elements; the work of f_ext the solver counts
    real(wp) :: work = 0.0_wp
  contains
    procedure(acts_at_hook), deferred :: acts_at
    procedure :: add_forces => no_forces
    procedure :: constrain => no_constraint
    procedure :: add_corner_forces => no_corner_forces
    procedure :: idle => never_idle
    procedure :: state_words => no_state
    procedure :: restore_state => no_restore
    procedure :: history_sums => no_history_sums
    !> how many of the member's constraints have let go so far (welds), the same on every rank
    procedure :: failures => no_failures
    !> mass(j): the mass that moves with local node j, for the contact's stability cap (default:
    !> unchanged, the node's own); a member that moves nodes together gives them their group's
    procedure :: carried_mass => own_mass
  end type nodal_effect_t

  !> A member in a list (a Fortran array cannot hold different members directly).
  type :: nodal_effect_holder_t
    class(nodal_effect_t), allocatable :: effect
  end type nodal_effect_holder_t

  abstract interface
    !> Whether the member uses the hook of stage (stage_loads, stage_constraints, stage_corners).
    pure logical function acts_at_hook(e, stage)
      import :: nodal_effect_t
      class(nodal_effect_t), intent(in) :: e
      integer, intent(in) :: stage
    end function acts_at_hook
  end interface

contains

  !> Adds to ns%f_ext the forces at time (positions ns%x); every rank that holds a node adds the
  !> whole force, as each rank updates its own copy of a shared node.
  pure subroutine own_mass(e, mass)
    class(nodal_effect_t), intent(in) :: e
    real(wp), intent(inout) :: mass(:)
  end subroutine own_mass

  subroutine no_forces(e, ns, time)
    class(nodal_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time
  end subroutine no_forces

  !> Sets velocities after the update of the step from time to time + dt (ns%v, ns%w are the
  !> half-step velocities), before the positions move; dt_previous is the step that ended at time
  !> (the step varies: docs/theory.md). Adds its work to e%work.
  subroutine no_constraint(e, ns, time, dt, dt_previous)
    class(nodal_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time, dt, dt_previous
  end subroutine no_constraint

  !> Adds forces on element corners (corner 4 (e - 1) + k of local element e, the internal-force
  !> sign) at the positions x of time, before the corners are exchanged and summed in fixed order.
  subroutine no_corner_forces(e, connectivity, x, time, corner)
    class(nodal_effect_t), intent(inout) :: e
    integer, intent(in) :: connectivity(:, :)
    real(wp), intent(in) :: x(:, :), time
    real(wp), intent(inout) :: corner(:, :)
  end subroutine no_corner_forces

  !> Whether the member has nothing to do at time (its curves ended at zero, say): the pipeline
  !> then skips it and counts the cycle as skipped.
  pure logical function never_idle(e, time) result(idle)
    class(nodal_effect_t), intent(in) :: e
    real(wp), intent(in) :: time
    idle = .false.
  end function never_idle

  !> The member's own state that a checkpoint keeps (the same on every rank), none by default.
  function no_state(e) result(words)
    class(nodal_effect_t), intent(in) :: e
    real(wp), allocatable :: words(:)
    allocate (words(0))
  end function no_state

  !> The member's state from a checkpoint's words (as state_words gave them).
  subroutine no_restore(e, words)
    class(nodal_effect_t), intent(inout) :: e
    real(wp), intent(in) :: words(:)
  end subroutine no_restore

  !> The exact accumulators (core/exact_sum) of the force vectors the member reports in the
  !> history, (exact_width, 3, rows), summed over this rank's owned nodes in the last step; none by default.
  function no_history_sums(e) result(sums)
    class(nodal_effect_t), intent(in) :: e
    integer(i8), allocatable :: sums(:, :, :)
    allocate (sums(0, 3, 0))
  end function no_history_sums

  !> No constraint of the member ever lets go.
  pure integer function no_failures(e) result(count)
    class(nodal_effect_t), intent(in) :: e
    count = 0
  end function no_failures

end module nodal_effect
