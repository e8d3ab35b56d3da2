!> What the time loop needs from the deck, built once at set-up so the global deck can be released:
!> output and progress intervals, damping, the point loads and tracked nodes in local numbering,
!> the sizes for the run record and checkpoints, and the effects the deck switches on.
module run_control
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t
  use domain_decomposition, only: domain_t, local_node
  use paradyn_schema, only: material_j2_plasticity, contact_gather_all, enum_name, enum_partition
  implicit none
  private
  public :: run_control_t, run_control_setup, deck_effects

  type :: run_control_t
    real(wp) :: end_time = 0, output_interval = 0, history_interval = 0, progress_interval = 0
    real(wp) :: mass_damping = 0, checkpoint_interval = 0
    integer :: n_nodes = 0, n_elements = 0   !< of the whole model
    integer :: max_points = 0                !< the most through-thickness points of any part
    integer :: n_loads = 0, n_tracked = 0
    integer, allocatable :: load_node(:)     !< local node of each load, 0 where not held here
    integer, allocatable :: load_dof(:)
    real(wp), allocatable :: load_value(:), load_ramp_time(:)
    integer, allocatable :: tracked_local(:) !< local node of each tracked node where this rank owns it, else 0
    character(len=:), allocatable :: effects, partition
    logical :: contact_gather_all = .false.  !< /control contact_gather = "all": every contact node every step
  end type run_control_t

contains

  subroutine run_control_setup(rc, deck, dom)
    type(run_control_t), intent(out) :: rc
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    integer :: k, j
    rc%end_time = deck%end_time
    rc%output_interval = deck%output_interval
    rc%history_interval = deck%history_interval
    rc%progress_interval = deck%progress_interval
    rc%mass_damping = deck%mass_damping
    rc%checkpoint_interval = deck%checkpoint_interval
    rc%n_nodes = deck%n_nodes
    rc%n_elements = deck%n_elements
    rc%max_points = maxval(deck%integration_points)
    rc%n_loads = deck%n_loads
    allocate (rc%load_node(deck%n_loads))
    do k = 1, deck%n_loads
      rc%load_node(k) = local_node(dom, deck%load_node(k))
    end do
    rc%load_dof = deck%load_dof
    rc%load_value = deck%load_value
    rc%load_ramp_time = deck%load_ramp_time
    rc%n_tracked = deck%n_tracked
    allocate (rc%tracked_local(deck%n_tracked), source=0)
    do k = 1, deck%n_tracked   ! each tracked node is reported by its owner alone
      j = local_node(dom, deck%tracked_nodes(k))
      if (j == 0) cycle
      if (dom%node_owned(j) == 0) cycle
      rc%tracked_local(k) = j
    end do
    rc%effects = deck_effects(deck)
    rc%partition = enum_name(enum_partition, deck%partition)
    rc%contact_gather_all = deck%contact_gather == contact_gather_all
  end subroutine run_control_setup

  !> Effects this deck switches on, in the order the engine runs them.
  function deck_effects(deck) result(list)
    type(deck_t), intent(in) :: deck
    character(len=:), allocatable :: list
    list = 'shell_elements,time_integration'
    if (any(deck%material_model(deck%part_material) == material_j2_plasticity)) list = list//',plasticity'
    if (any(deck%fixed /= 0)) list = list//',fixed_boundaries'
    if (deck%n_loads > 0) list = list//',point_loads'
    if (deck%n_contacts > 0) list = list//',contact'
    if (deck%mass_damping > 0) list = list//',mass_damping'
  end function deck_effects

end module run_control
