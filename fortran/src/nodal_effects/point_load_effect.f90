!> Point loads as a member of the nodal effect family: nodal forces and moments that grow
!> linearly over a ramp time and then stay (the kernels are in point_loads).
module point_load_effect
  use paradyn_kinds, only: wp
  use paradyn_schema, only: effect_point_loads
  use nodal_state, only: nodal_state_t
  use nodal_effect, only: nodal_effect_t, stage_loads
  use point_loads, only: point_load_forces
  implicit none
  private
  public :: point_load_effect_t, point_load_effect_make

  type, extends(nodal_effect_t) :: point_load_effect_t
    integer :: n_loads = 0
    integer, allocatable :: node(:)      !< local node of each load, 0 where this rank does not hold it
    integer, allocatable :: dof(:)
    real(wp), allocatable :: value(:), ramp_time(:)
  contains
    procedure :: acts_at
    procedure :: add_forces
  end type point_load_effect_t

contains

  !> The member from the deck's loads (local_node: each load's node in local numbering, or 0).
  function point_load_effect_make(local_node, dof, value, ramp_time) result(e)
    integer, intent(in) :: local_node(:), dof(:)
    real(wp), intent(in) :: value(:), ramp_time(:)
    type(point_load_effect_t) :: e
    e%id = effect_point_loads
    e%n_loads = size(local_node)
    e%node = local_node
    e%dof = dof
    e%value = value
    e%ramp_time = ramp_time
  end function point_load_effect_make

  pure logical function acts_at(e, stage)
    class(point_load_effect_t), intent(in) :: e
    integer, intent(in) :: stage
    acts_at = stage == stage_loads
  end function acts_at

  subroutine add_forces(e, ns, time)
    class(point_load_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time
    call point_load_forces(e%n_loads, e%node, e%dof, e%value, e%ramp_time, time, ns%f_ext)
  end subroutine add_forces

end module point_load_effect
