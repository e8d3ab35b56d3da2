!> The solver of one rank as a set of small parts: where its elements and nodes are (domain, halo),
!> the section of each part, the nodal and element state, the step clock, the phase timers, the
!> run control built at set-up, the contact, and the effects of the step (effect_pipeline). The time loop (explicit_solver) only calls them.
module solver_state
  use paradyn_kinds, only: wp
  use domain_decomposition, only: domain_t
  use halo_exchange, only: halo_t
  use shell_section, only: shell_properties_t
  use work_queues, only: work_queues_t
  use nodal_state, only: nodal_state_t
  use element_state, only: element_state_t
  use step_clock, only: step_clock_t
  use phase_timers, only: phase_timers_t
  use run_control, only: run_control_t
  use contact_parallel, only: parallel_contact_t
  use effect_table, only: effect_table_t
  use nodal_effect, only: nodal_effect_holder_t
  use model_deck, only: deck_t
  implicit none
  private
  public :: solver_t

  type :: solver_t
    type(domain_t) :: dom
    type(halo_t) :: halo
    type(shell_properties_t), allocatable :: props(:)   !< per part
    type(nodal_state_t) :: nodes
    type(element_state_t) :: elements
    type(step_clock_t) :: clock
    type(phase_timers_t) :: timers
    type(run_control_t) :: control
    type(parallel_contact_t) :: contact
    logical :: has_contact = .false.
    ! erosion in contact (eroded_contact): whether a contact part can erode, this rank's elements
    ! known eroded and its nodes known to have no live element
    logical :: contact_erodes = .false.
    logical, allocatable :: eroded_known(:), dead_known(:)
    ! contacts born later (contact_births): each definition's birth time, whether its check at the
    ! birth is still to come, and this rank's rows of the deck for it (kept only while one is)
    real(wp), allocatable :: birth_time(:)
    logical, allocatable :: birth_pending(:)
    type(deck_t) :: birth_deck
    type(effect_table_t) :: effects                          !< what runs, with its counters
    type(nodal_effect_holder_t), allocatable :: nodal_effects(:)   !< the running loads and constraints
    logical :: has_loads = .false., has_constraints = .false., has_corner_loads = .false.
    logical :: external_forces_zero = .true.                 !< f_ext is all zero (no load was active)
    integer, allocatable :: part_effect(:)                   !< per part: effect_elastic_shells or _plastic_shells
    integer :: rank = 0, n_ranks = 1, threads = 1
    real(wp), allocatable :: corner(:, :)      !< (6, corners + ghost slots): forces per element corner
    real(wp), allocatable :: workspace(:, :)   !< per thread: one group's gathered nodes and forces
    type(work_queues_t) :: group_queues        !< the threads' shares of the element groups
    ! output buffers: this rank's owned nodes and its elements
    real(wp), allocatable :: node_out(:, :), element_out(:, :)   !< results_write_frame's layouts
    real(wp), allocatable :: v_free(:, :)   !< (3, n) the velocities before the constraints, at a record
    real(wp), allocatable :: w_free(:, :)   !< (3, n) and the angular velocities
    real(wp) :: reaction(6) = 0             !< the constraints' resultant force (N) and moment about the origin (N m) at the last record
    real(wp), allocatable :: element_work(:)   !< each element's plastic work at a history record
    real(wp), allocatable :: tracked_out(:, :)   !< (6, n_tracked): this rank's share, summed to rank 0
    integer, allocatable :: node_part(:)         !< per local node: the part of its lowest-numbered element
    integer :: n_parts = 0, n_contacts = 0, n_walls = 0
    real(wp) :: external_work = 0, damping_work = 0   !< summed over this rank's owned nodes
    ! rank 0: the total energy of the first record of this process and the largest energy since,
    ! for the energy balance error that /control energy_error_limit watches
    real(wp) :: energy_first = 0, energy_scale = 0
    logical :: have_energy_first = .false.
    logical :: started = .false., finished = .false., stop_requested = .false.
    logical :: floor_stop = .false.   !< the step fell below the floor (the state is that of a good step)
    logical :: energy_stop = .false.  !< the energy balance error passed its limit (the state is finite)
    real(wp) :: dt_min = huge(1.0_wp), dt_max = 0   !< the smallest and largest stable step (safety included)
    real(wp) :: dt_rigid_only = huge(1.0_wp)   !< the step of a model of rigid bodies alone (else huge)
    ! mass scaling at set-up (mass_scaling): the added mass per part and in all, the model's mass
    real(wp), allocatable :: added_mass_part(:)
    real(wp) :: added_mass = 0, model_mass = 0, mass_scaling_step = 0
    integer :: scaled_elements = 0
    real(wp) :: wall_start = 0, last_progress = 0
  end type solver_t

end module solver_state
