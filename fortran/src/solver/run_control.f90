!> What the time loop needs from the deck, built once at set-up so the deck can be released:
!> output and progress intervals, damping, the tracked nodes in local numbering and the sizes for
!> the run record and checkpoints. (The loads are members of the effect pipeline.)
module run_control
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t, engine_precision
  use domain_decomposition, only: domain_t, local_node
  use paradyn_schema, only: contact_gather_all, enum_name, enum_partition, enum_precision, shell_element_full
  implicit none
  private
  public :: run_control_t, run_control_setup

  type :: run_control_t
    real(wp) :: end_time = 0, output_interval = 0, history_interval = 0, progress_interval = 0
    real(wp) :: mass_damping = 0, checkpoint_interval = 0
    real(wp) :: energy_error_limit = 0       !< stop once the energy balance error passes it (0: never)
    real(wp) :: time_step_floor = 0          !< stop once the step falls below this fraction of the first
    real(wp) :: contact_travel_limit = 0     !< most contact-node travel per step / thinner wall (0: no limit)
    real(wp) :: contact_closing_limit = 0    !< most closing per step of a near pair / its thinner wall (0: off)
    real(wp) :: dt_cap = huge(1.0_wp)        !< the largest step the rigid walls' penalty allows (s)
    integer :: n_nodes = 0, n_elements = 0   !< of the whole model
    integer :: max_points = 0                !< the most stored points of any part (through-thickness x in-plane)
    integer :: n_tracked = 0
    integer, allocatable :: tracked_local(:) !< local node of each tracked node where this rank owns it, else 0
    character(len=:), allocatable :: partition
    character(len=:), allocatable :: precision   !< this engine's: "double" or "mixed" (the deck asked for it)
    logical :: contact_gather_all = .false.  !< /control contact_gather = "all": every contact node every step
    integer, allocatable :: contact_pairs(:, :)   !< (2, pairs): the deck's part pairs, for the effect table
    character(len=16), allocatable :: fingerprint_groups(:)   !< the deck's, for the checkpoint
    real(wp), allocatable :: fingerprints(:)
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
    rc%energy_error_limit = deck%energy_error_limit
    rc%time_step_floor = deck%time_step_floor
    rc%contact_travel_limit = deck%contact_travel_limit
    rc%contact_closing_limit = deck%contact_closing_limit
    rc%n_nodes = deck%n_nodes
    rc%n_elements = deck%n_elements
    ! a fully integrated part stores its 4 in-plane points' (element_state)
    rc%max_points = maxval(deck%integration_points * merge(4, 1, deck%shell_element == shell_element_full))
    rc%n_tracked = deck%n_tracked
    allocate (rc%tracked_local(deck%n_tracked), source=0)
    do k = 1, deck%n_tracked   ! each tracked node is reported by its owner alone
      j = local_node(dom, deck%tracked_nodes(k))
      if (j == 0) cycle
      if (dom%node_owned(j) == 0) cycle
      rc%tracked_local(k) = j
    end do
    rc%partition = enum_name(enum_partition, deck%partition)
    rc%precision = enum_name(enum_precision, engine_precision)
    rc%contact_gather_all = deck%contact_gather == contact_gather_all
    rc%contact_pairs = deck%contact_pairs(:, 1:deck%n_contacts)
    rc%fingerprint_groups = deck%fingerprint_groups
    rc%fingerprints = deck%fingerprints
  end subroutine run_control_setup

end module run_control
