!> The model as one rank holds it after reading a deck (global numbering, 1-based inside the
!> engine): where each dataset and /control attribute of the schema (paradyn_schema) goes in
!> deck_t (the relations between fields: deck_relations and io/deck_checks).
!>
!> Layout (issue 19, item 5; docs/formats.md, "The deck in the engine"): the tables sized by the
!> definitions (parts, materials, loads, curves, contact, rigid walls, tracked nodes, /control)
!> are held whole on every rank. The mesh is held in rows: connectivity and element_part hold the
!> rows of the global elements element_ids (ascending: this rank's elements), coordinates,
!> velocity, angular_velocity, fixed and node_part the rows of the global nodes node_ids
!> (ascending: the distinct nodes of those elements). n_nodes and n_elements stay the global
!> counts; element_row and node_row find a global id's row (0: not held).
module model_deck
  use paradyn_kinds, only: wp, ek
  use shell_section, only: shell_properties_t
  use paradyn_schema, only: material_is_plastic, size_none, deck_datasets, &
                            class_int, &
                            enum_name, enum_material_model, control_attributes, control_partition, &
                            dataset_nodes_coordinates, dataset_nodes_initial_velocity, &
                            dataset_nodes_initial_angular_velocity, dataset_nodes_fixed_dofs, &
                            dataset_elements_connectivity, dataset_elements_part, dataset_parts_thickness, &
                            dataset_parts_material, dataset_parts_integration_points, &
                            dataset_parts_hourglass_coefficient, dataset_parts_hourglass_form, &
                            dataset_parts_warping_correction, &
                            dataset_materials_model, dataset_materials_density, dataset_materials_youngs_modulus, &
                            dataset_materials_poisson_ratio, dataset_materials_yield_stress, &
                            dataset_materials_tangent_modulus, dataset_materials_hardening_mixing, &
                            dataset_loads_node, dataset_loads_dof, dataset_loads_value, dataset_loads_ramp_time, &
                            dataset_output_tracked_nodes, dataset_contact_pairs, dataset_contact_penalty_scale, &
                            dataset_contact_static_friction, dataset_contact_dynamic_friction, &
                            dataset_contact_friction_decay, dataset_contact_passes, dataset_contact_kind, &
                            dataset_contact_initial_penetration, &
                            dataset_rigid_walls_point, dataset_rigid_walls_normal, dataset_rigid_walls_velocity, &
                            dataset_rigid_walls_penalty_scale, &
                            contact_gather_near, control_contact_gather, control_end_time, &
                            control_output_interval, control_history_interval, control_time_step, &
                            control_time_step_safety, control_mass_damping, control_progress_interval, &
                            control_contact_sort_interval, control_checkpoint_interval, control_energy_error_limit, &
                            control_time_step_floor, control_contact_travel_limit, &
                            control_mass_scaling_step, control_mass_scaling_limit, &
                            n_effects, effect_switch, &
                            switch_off, control_precision, precision_double, precision_mixed, &
                            dataset_curves_first_point, dataset_curves_time, dataset_curves_value, &
                            dataset_pressure_part, dataset_pressure_value, dataset_pressure_curve, &
                            dataset_prescribed_node, dataset_prescribed_dof, dataset_prescribed_value, &
                            dataset_prescribed_curve, control_gravity_x, control_gravity_y, control_gravity_z
  use material_factory, only: material_from_name
  implicit none
  private
  public :: deck_t, part_properties, partition_default, engine_precision
  public :: store_deck_field, store_control_value, node_row, element_row

  !> The method when /control has no partition attribute (schema default; docs/performance.md).
  integer, parameter :: partition_default = nint(control_attributes(control_partition)%default)
  !> This engine's precision (precision_double or precision_mixed): the kind of its element kernel
  integer, parameter :: engine_precision = merge(precision_mixed, precision_double, ek /= wp)

  type :: deck_t
    integer :: n_nodes = 0, n_elements = 0, n_parts = 0, n_materials = 0
    integer :: n_loads = 0, n_tracked = 0, n_contacts = 0, n_rigid_walls = 0
    integer, allocatable :: node_ids(:)               !< the global nodes held, ascending (rows below)
    real(wp), allocatable :: coordinates(:, :)        !< (3, size(node_ids))
    real(wp), allocatable :: velocity(:, :)           !< (3, size(node_ids))
    real(wp), allocatable :: angular_velocity(:, :)   !< (3, size(node_ids))
    integer, allocatable :: fixed(:, :)               !< (6, size(node_ids)), 1 = fixed
    integer, allocatable :: node_part(:)              !< the part of each held node's lowest-numbered element
    integer, allocatable :: element_ids(:)            !< the global elements held, ascending (rows below)
    integer, allocatable :: connectivity(:, :)        !< (4, size(element_ids)), 1-based global nodes
    integer, allocatable :: element_part(:)           !< (size(element_ids)), 1-based
    logical :: any_fixed = .false.                    !< some node of the whole mesh has a fixed dof
    integer :: rows_read(2) = 0                       !< the mesh rows this rank read: elements, nodes
    real(wp), allocatable :: thickness(:), hourglass_coefficient(:)
    integer, allocatable :: part_material(:), integration_points(:), hourglass_form(:), warping_correction(:)
    integer, allocatable :: material_model(:)
    real(wp), allocatable :: density(:), young(:), poisson(:)
    real(wp), allocatable :: yield_stress(:), tangent_modulus(:), hardening_mixing(:)
    integer, allocatable :: load_node(:), load_dof(:)
    real(wp), allocatable :: load_value(:), load_ramp_time(:)
    integer, allocatable :: tracked_nodes(:)
    integer, allocatable :: contact_pairs(:, :)       !< (2, n_contacts), 1-based parts
    real(wp), allocatable :: contact_penalty_scale(:), contact_static_friction(:)
    real(wp), allocatable :: contact_dynamic_friction(:), contact_friction_decay(:)
    integer, allocatable :: contact_passes(:)         !< 2 both bodies slave every step, 1 alternate
    integer, allocatable :: contact_kind(:)           !< member of the contact family (schema enum contact_kind)
    integer, allocatable :: contact_initial_penetration(:)   !< schema enum initial_penetration: move or gap
    real(wp), allocatable :: rigid_wall_point(:, :)   !< (3, n_rigid_walls), a point of the plane at time 0
    real(wp), allocatable :: rigid_wall_normal(:, :)  !< (3, n_rigid_walls), towards the model, as given
    real(wp), allocatable :: rigid_wall_velocity(:, :)   !< (3, n_rigid_walls), constant
    real(wp), allocatable :: rigid_wall_penalty_scale(:)  !< k = scale m / dt^2
    real(wp) :: end_time = 0.0_wp, output_interval = 0.0_wp, history_interval = 0.0_wp
    real(wp) :: time_step = 0.0_wp, time_step_safety = 0.9_wp, mass_damping = 0.0_wp
    real(wp) :: progress_interval = 0.5_wp
    integer :: contact_sort_interval = 0              !< cycles between bucket sorts, 0 = automatic
    real(wp) :: checkpoint_interval = 0.0_wp          !< simulated seconds between checkpoints, 0 = none
    real(wp) :: energy_error_limit = 0.0_wp           !< stop once the energy balance error passes it, 0 = never
    real(wp) :: contact_travel_limit = 0.0_wp         !< most contact-node travel per step / thinner wall, 0 = off
    real(wp) :: time_step_floor = 1.0e-3_wp           !< stop once the step falls below this fraction of the first
    real(wp) :: mass_scaling_step = 0.0_wp            !< the least step wanted (s), 0 = no mass scaling
    real(wp) :: mass_scaling_limit = 0.05_wp          !< the most added mass, as a fraction of the model's
    integer :: partition = partition_default          !< partition_blocks or partition_rcb; 0 = unknown name
    integer :: contact_gather = contact_gather_near   !< which contact nodes are gathered between sorts
    integer :: precision = precision_double           !< the precision the deck asks for (/control precision)
    logical :: effect_on(n_effects) = .true.          !< false: the scene switched the effect off (/control effect_*)
    character(len=16), allocatable :: fingerprint_groups(:)   !< "nodes", ..., "control" (deck_fingerprint)
    real(wp), allocatable :: fingerprints(:)                  !< one 32-bit hash per group, held exactly
    ! loads: curves, pressure, prescribed velocity, gravity
    integer :: n_curves = 0, n_curve_points = 0, n_pressures = 0, n_prescribed = 0
    integer, allocatable :: curve_first_point(:)      !< (n_curves), 1-based index into curve_time
    real(wp), allocatable :: curve_time(:), curve_value(:)
    integer, allocatable :: pressure_part(:), pressure_curve(:)   !< 1-based
    real(wp), allocatable :: pressure_value(:)
    integer, allocatable :: prescribed_node(:), prescribed_dof(:), prescribed_curve(:)   !< 1-based node, curve
    real(wp), allocatable :: prescribed_value(:)
    real(wp) :: gravity(3) = 0.0_wp                   !< body acceleration, m/s^2
  end type deck_t

contains

  !> The section of a part and its material, made by the material family's factory.
  function part_properties(deck, part) result(props)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: part
    type(shell_properties_t) :: props
    integer :: m
    m = deck%part_material(part)
    props%thickness = deck%thickness(part)
    props%hourglass_coefficient = deck%hourglass_coefficient(part)
    props%integration_points = deck%integration_points(part)
    props%hourglass_form = deck%hourglass_form(part)
    props%warping_correction = deck%warping_correction(part) /= 0
    props%density = deck%density(m)
    props%young = deck%young(m)
    props%poisson = deck%poisson(m)
    if (material_is_plastic(deck%material_model(m))) props%hourglass_yield = deck%yield_stress(m)
    call material_from_name(enum_name(enum_material_model, deck%material_model(m)), deck%young(m), deck%poisson(m), &
                            deck%yield_stress(m), deck%tangent_modulus(m), deck%hardening_mixing(m), props%material)
  end function part_properties

  !> Puts one dataset, as read from the file ((max(columns, 1), rows), 0-based indices), into its
  !> field of deck_t; indices become 1-based. One line per dataset of the schema. A mesh dataset
  !> arrives as the rank's block of rows (the reader then sets n_nodes and n_elements to the
  !> file's counts and the ids of the rows, and deck_checks moves the rows to model_deck's layout).
  subroutine store_deck_field(d, id, values)
    type(deck_t), intent(inout) :: d
    integer, intent(in) :: id
    real(wp), intent(in) :: values(:, :)
    integer, allocatable :: indices(:, :)
    if (deck_datasets(id)%class == class_int) then   ! checked: every entry is a small whole number
      allocate (indices(size(values, 1), size(values, 2)))
      indices = nint(values)
      if (deck_datasets(id)%reference /= size_none) indices = indices + 1
    end if
    select case (id)
    case (dataset_nodes_coordinates)
      d%coordinates = values
      d%n_nodes = size(values, 2)
    case (dataset_nodes_initial_velocity)
      d%velocity = values
    case (dataset_nodes_initial_angular_velocity)
      d%angular_velocity = values
    case (dataset_nodes_fixed_dofs)
      d%fixed = indices
    case (dataset_elements_connectivity)
      d%connectivity = indices
      d%n_elements = size(values, 2)
    case (dataset_elements_part)
      d%element_part = indices(1, :)
    case (dataset_parts_thickness)
      d%thickness = values(1, :)
      d%n_parts = size(values, 2)
    case (dataset_parts_material)
      d%part_material = indices(1, :)
    case (dataset_parts_integration_points)
      d%integration_points = indices(1, :)
    case (dataset_parts_hourglass_coefficient)
      d%hourglass_coefficient = values(1, :)
    case (dataset_parts_hourglass_form)
      d%hourglass_form = indices(1, :)
    case (dataset_parts_warping_correction)
      d%warping_correction = indices(1, :)
    case (dataset_materials_model)
      d%material_model = indices(1, :)
      d%n_materials = size(values, 2)
    case (dataset_materials_density)
      d%density = values(1, :)
    case (dataset_materials_youngs_modulus)
      d%young = values(1, :)
    case (dataset_materials_poisson_ratio)
      d%poisson = values(1, :)
    case (dataset_materials_yield_stress)
      d%yield_stress = values(1, :)
    case (dataset_materials_tangent_modulus)
      d%tangent_modulus = values(1, :)
    case (dataset_materials_hardening_mixing)
      d%hardening_mixing = values(1, :)
    case (dataset_loads_node)
      d%load_node = indices(1, :)
      d%n_loads = size(values, 2)
    case (dataset_loads_dof)
      d%load_dof = indices(1, :)
    case (dataset_loads_value)
      d%load_value = values(1, :)
    case (dataset_loads_ramp_time)
      d%load_ramp_time = values(1, :)
    case (dataset_output_tracked_nodes)
      d%tracked_nodes = indices(1, :)
      d%n_tracked = size(values, 2)
    case (dataset_contact_pairs)
      d%contact_pairs = indices
      d%n_contacts = size(values, 2)
    case (dataset_contact_penalty_scale)
      d%contact_penalty_scale = values(1, :)
    case (dataset_contact_static_friction)
      d%contact_static_friction = values(1, :)
    case (dataset_contact_dynamic_friction)
      d%contact_dynamic_friction = values(1, :)
    case (dataset_contact_friction_decay)
      d%contact_friction_decay = values(1, :)
    case (dataset_contact_passes)
      d%contact_passes = indices(1, :)
    case (dataset_contact_kind)
      d%contact_kind = indices(1, :)
    case (dataset_contact_initial_penetration)
      d%contact_initial_penetration = indices(1, :)
    case (dataset_rigid_walls_point)
      d%rigid_wall_point = values
      d%n_rigid_walls = size(values, 2)
    case (dataset_rigid_walls_normal)
      d%rigid_wall_normal = values
    case (dataset_rigid_walls_velocity)
      d%rigid_wall_velocity = values
    case (dataset_rigid_walls_penalty_scale)
      d%rigid_wall_penalty_scale = values(1, :)
    case (dataset_curves_first_point)   ! an index without a reference: made 1-based here
      d%curve_first_point = indices(1, :) + 1
      d%n_curves = size(values, 2)
    case (dataset_curves_time)
      d%curve_time = values(1, :)
      d%n_curve_points = size(values, 2)
    case (dataset_curves_value)
      d%curve_value = values(1, :)
    case (dataset_pressure_part)
      d%pressure_part = indices(1, :)
      d%n_pressures = size(values, 2)
    case (dataset_pressure_value)
      d%pressure_value = values(1, :)
    case (dataset_pressure_curve)
      d%pressure_curve = indices(1, :)
    case (dataset_prescribed_node)
      d%prescribed_node = indices(1, :)
      d%n_prescribed = size(values, 2)
    case (dataset_prescribed_dof)
      d%prescribed_dof = indices(1, :)
    case (dataset_prescribed_value)
      d%prescribed_value = values(1, :)
    case (dataset_prescribed_curve)
      d%prescribed_curve = indices(1, :)
    end select
  end subroutine store_deck_field

  !> Puts one /control attribute into deck_t (a string attribute arrives as its enum code).
  subroutine store_control_value(d, id, value)
    type(deck_t), intent(inout) :: d
    integer, intent(in) :: id
    real(wp), intent(in) :: value
    select case (id)
    case (control_end_time)
      d%end_time = value
    case (control_output_interval)
      d%output_interval = value
    case (control_history_interval)
      d%history_interval = value
    case (control_time_step)
      d%time_step = value
    case (control_time_step_safety)
      d%time_step_safety = value
    case (control_mass_damping)
      d%mass_damping = value
    case (control_progress_interval)
      d%progress_interval = value
    case (control_contact_sort_interval)
      d%contact_sort_interval = nint(value)
    case (control_checkpoint_interval)
      d%checkpoint_interval = value
    case (control_energy_error_limit)
      d%energy_error_limit = value
    case (control_time_step_floor)
      d%time_step_floor = value
    case (control_contact_travel_limit)
      d%contact_travel_limit = value
    case (control_mass_scaling_step)
      d%mass_scaling_step = value
    case (control_mass_scaling_limit)
      d%mass_scaling_limit = value
    case (control_partition)
      d%partition = nint(value)
    case (control_contact_gather)
      d%contact_gather = nint(value)
    case (control_precision)
      d%precision = nint(value)
    case (control_gravity_x)
      d%gravity(1) = value
    case (control_gravity_y)
      d%gravity(2) = value
    case (control_gravity_z)
      d%gravity(3) = value
    case default   ! an effect's switch (schema/effects.toml)
      where (effect_switch == id) d%effect_on = nint(value) /= switch_off
    end select
  end subroutine store_control_value

  !> The row of global node `id` among the held nodes, 0 when this rank does not hold it.
  pure integer function node_row(d, id)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: id
    node_row = sorted_position(d%node_ids, id)
  end function node_row

  !> The row of global element `id` among the held elements, 0 when this rank does not hold it.
  pure integer function element_row(d, id)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: id
    element_row = sorted_position(d%element_ids, id)
  end function element_row

  !> Place of value in the ascending list ids (binary search), 0 when it is not there.
  pure integer function sorted_position(ids, value) result(place)
    integer, intent(in) :: ids(:), value
    integer :: lo, hi, mid
    place = 0
    lo = 1
    hi = size(ids)
    do while (lo <= hi)
      mid = (lo + hi) / 2
      if (ids(mid) == value) then
        place = mid
        return
      else if (ids(mid) < value) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function sorted_position

end module model_deck
