!> The whole model as read from a deck (global numbering, 1-based inside the engine): where each
!> dataset and /control attribute of the schema (paradyn_schema) goes in deck_t, and the checks
!> of relations between fields that the schema's per-field rules (deck_rules) cannot express.
module model_deck
  use paradyn_kinds, only: wp, ek
  use shell_section, only: shell_properties_t
  use paradyn_schema, only: material_j2_plasticity, contact_kind_single_surface, size_none, deck_datasets, &
                            class_float, class_int, &
                            enum_name, enum_material_model, control_attributes, control_partition, status_ok, &
                            status_bad_input, &
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
                            switch_off, control_precision, precision_double, precision_mixed, enum_precision, &
                            dataset_curves_first_point, dataset_curves_time, dataset_curves_value, &
                            dataset_pressure_part, dataset_pressure_value, dataset_pressure_curve, &
                            dataset_prescribed_node, dataset_prescribed_dof, dataset_prescribed_value, &
                            dataset_prescribed_curve, control_gravity_x, control_gravity_y, control_gravity_z
  use deck_rules, only: integer_text, number_text, index_list
  use material_factory, only: material_from_name
  use quad_shape, only: quad_shape_fault, shape_sound, shape_concave
  use integer_sort, only: sort_ascending
  implicit none
  private
  public :: deck_t, part_properties, partition_default, engine_precision
  public :: store_deck_field, store_control_value, check_deck_relations

  !> The method when /control has no partition attribute (schema default; docs/performance.md).
  integer, parameter :: partition_default = nint(control_attributes(control_partition)%default)
  !> This engine's precision (precision_double or precision_mixed): the kind of its element kernel
  integer, parameter :: engine_precision = merge(precision_mixed, precision_double, ek /= wp)

  type :: deck_t
    integer :: n_nodes = 0, n_elements = 0, n_parts = 0, n_materials = 0
    integer :: n_loads = 0, n_tracked = 0, n_contacts = 0, n_rigid_walls = 0
    real(wp), allocatable :: coordinates(:, :)        !< (3, n_nodes)
    real(wp), allocatable :: velocity(:, :)           !< (3, n_nodes)
    real(wp), allocatable :: angular_velocity(:, :)   !< (3, n_nodes)
    integer, allocatable :: fixed(:, :)               !< (6, n_nodes), 1 = fixed
    integer, allocatable :: connectivity(:, :)        !< (4, n_elements), 1-based nodes
    integer, allocatable :: element_part(:)           !< (n_elements), 1-based
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
    if (deck%material_model(m) == material_j2_plasticity) props%hourglass_yield = deck%yield_stress(m)
    call material_from_name(enum_name(enum_material_model, deck%material_model(m)), deck%young(m), deck%poisson(m), &
                            deck%yield_stress(m), deck%tangent_modulus(m), deck%hardening_mixing(m), props%material)
  end function part_properties

  !> Puts one dataset, as read from the file ((max(columns, 1), rows), 0-based indices), into its
  !> field of deck_t; indices become 1-based. One line per dataset of the schema.
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

  !> Relations between fields of a deck whose every field has passed its own rules (schema
  !> relations: distinct_element_nodes, distinct_elements, tangent_below_youngs, contact_parts_differ,
  !> node_in_element, then the rigid walls' and the load curves' (curve_first_points,
  !> curve_times_increase)). Returns status_ok, or status_bad_input with a message naming the
  !> dataset, the 0-based entry and the fix.
  subroutine check_deck_relations(d, status, message)
    type(deck_t), intent(in) :: d
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    logical, allocatable :: used(:)
    integer :: i, j, k

    status = status_bad_input
    message = ''
    if (d%precision /= engine_precision) then
      message = '/control precision = "'//enum_name(enum_precision, d%precision)//'" but this engine computes in '// &
                enum_name(enum_precision, engine_precision)//' precision; run paradyn-engine'//trim(merge('-mixed', &
                '      ', d%precision == precision_mixed))//' (paradyn-run picks it from the deck), or change [run] precision'
      return
    end if
    do i = 1, d%n_elements
      do k = 1, 4
        do j = k + 1, 4
          if (d%connectivity(k, i) == d%connectivity(j, i)) then
            message = '/elements/connectivity['//integer_text(i - 1)//'] = '//index_list(d%connectivity(:, i))// &
                      ' repeats a node; every quadrilateral needs four distinct nodes (remesh without '// &
                      'collapsed elements)'
            return
          end if
        end do
      end do
    end do
    call check_distinct_elements(d, message)
    if (message /= '') return
    call check_element_shapes(d, message)
    if (message /= '') return
    do i = 1, d%n_materials
      if (d%material_model(i) /= material_j2_plasticity) cycle
      if (.not. (d%tangent_modulus(i) < d%young(i))) then
        message = '/materials/tangent_modulus['//integer_text(i - 1)//'] = '// &
                  number_text(d%tangent_modulus(i), class_float)//' must be below /materials/youngs_modulus['// &
                  integer_text(i - 1)//'] = '//number_text(d%young(i), class_float)// &
                  ' for a j2_plasticity material; give the plastic tangent modulus in Pa below Young''s modulus'
        return
      end if
    end do
    do i = 1, d%n_contacts
      if (d%contact_kind(i) == contact_kind_single_surface .neqv. d%contact_pairs(1, i) == d%contact_pairs(2, i)) then
        if (d%contact_kind(i) == contact_kind_single_surface) then
          message = '/contact/pairs['//integer_text(i - 1)//'] = '//index_list(d%contact_pairs(:, i))// &
                    ' names two parts for a single_surface contact; name its one part twice'
        else
          message = '/contact/pairs['//integer_text(i - 1)//'] = '//index_list(d%contact_pairs(:, i))// &
                    ' pairs a part with itself; name two different parts, or make the contact single_surface'
        end if
        return
      end if
    end do
    allocate (used(d%n_nodes), source=.false.)
    used(reshape(d%connectivity, [4 * d%n_elements])) = .true.
    if (.not. all(used)) then
      k = findloc(used, .false., dim=1)
      message = '/nodes/coordinates['//integer_text(k - 1)//'] belongs to no element ('// &
                integer_text(count(.not. used))//' such nodes); a node without elements has no mass, '// &
                'remove unused nodes'
      return
    end if
    call check_rigid_walls(d, message)
    if (len_trim(message) > 0) return
    call check_curve_relations(d, message)
    if (len_trim(message) > 0) return
    status = status_ok
  end subroutine check_deck_relations

  !> The schema relations rigid_wall_normal_nonzero and rigid_wall_nodes_in_front: message stays
  !> blank when they hold. A node counts as behind a wall below a distance of 1e-9 of the model's
  !> size, so that nodes placed on the plane are not refused for a rounding error.
  subroutine check_rigid_walls(d, message)
    type(deck_t), intent(in) :: d
    character(len=*), intent(inout) :: message
    real(wp) :: length, tolerance, lowest, distance
    integer :: w, j, k
    tolerance = 1.0e-9_wp * maxval(abs(d%coordinates))
    do w = 1, d%n_rigid_walls
      length = norm2(d%rigid_wall_normal(:, w))
      if (.not. (length > 0.0_wp)) then
        message = '/rigid_walls/normal['//integer_text(w - 1)//'] is the zero vector; give a nonzero normal '// &
                  'pointing from the wall towards the model'
        return
      end if
      k = 1
      lowest = huge(1.0_wp)
      do j = 1, d%n_nodes
        distance = dot_product(d%coordinates(:, j) - d%rigid_wall_point(:, w), d%rigid_wall_normal(:, w)) / length
        if (distance < lowest) then
          lowest = distance
          k = j
        end if
      end do
      if (lowest < -tolerance) then
        message = '/rigid_walls/point['//integer_text(w - 1)//'] puts node '//integer_text(k - 1)// &
                  ' behind the wall at the start (signed distance '//number_text(lowest, class_float)// &
                  ' m along /rigid_walls/normal); move the point or flip the normal so that the model starts '// &
                  'on the side the normal points to'
        return
      end if
    end do
  end subroutine check_rigid_walls

  !> No two elements with the same four nodes (in any order). Elements are bucketed by their
  !> smallest node, so only elements that share it are compared: linear in the elements.
  subroutine check_distinct_elements(d, message)
    type(deck_t), intent(in) :: d
    character(len=*), intent(inout) :: message
    integer, allocatable :: start(:), members(:), sorted(:, :), fill(:)
    integer :: i, j, k, low
    allocate (sorted(4, d%n_elements), start(d%n_nodes + 1), fill(d%n_nodes), source=0)
    do i = 1, d%n_elements
      sorted(:, i) = d%connectivity(:, i)
      call sort_ascending(sorted(:, i))
      start(sorted(1, i) + 1) = start(sorted(1, i) + 1) + 1
    end do
    start(1) = 1
    do j = 1, d%n_nodes
      start(j + 1) = start(j + 1) + start(j)
    end do
    allocate (members(d%n_elements))
    do i = 1, d%n_elements
      low = sorted(1, i)
      members(start(low) + fill(low)) = i
      fill(low) = fill(low) + 1
    end do
    do j = 1, d%n_nodes
      do k = start(j) + 1, start(j + 1) - 1   ! each later member against the earlier ones
        do i = start(j), k - 1
          if (all(sorted(:, members(i)) == sorted(:, members(k)))) then
            message = '/elements/connectivity['//integer_text(max(members(i), members(k)) - 1)//'] = '// &
                      index_list(d%connectivity(:, max(members(i), members(k))))//' has the same nodes as element '// &
                      integer_text(min(members(i), members(k)) - 1)//'; a duplicated element doubles its mass '// &
                      'and stiffness, remove it'
            return
          end if
        end do
      end do
    end do
  end subroutine check_distinct_elements

  !> Every element convex, without coincident or collinear corners (quad_shape).
  subroutine check_element_shapes(d, message)
    type(deck_t), intent(in) :: d
    character(len=*), intent(inout) :: message
    integer :: i, fault, corner, node
    do i = 1, d%n_elements
      call quad_shape_fault(d%coordinates(:, d%connectivity(:, i)), fault, corner)
      if (fault == shape_sound) cycle
      node = d%connectivity(corner, i)
      if (fault == shape_concave) then
        message = '/nodes/coordinates: element '//integer_text(i - 1)//' (part '//integer_text(d%element_part(i) - 1)// &
                  ', nodes '//index_list(d%connectivity(:, i))//') is concave or twisted at node '// &
                  integer_text(node - 1)//'; remesh it (a concave quadrilateral turns inside out at the first step)'
      else
        message = '/nodes/coordinates: element '//integer_text(i - 1)//' (part '//integer_text(d%element_part(i) - 1)// &
                  ', nodes '//index_list(d%connectivity(:, i))//') is collapsed or crossed at node '// &
                  integer_text(node - 1)//' (coincident or collinear corners, or sides that cross); remesh it'
      end if
      return
    end do
  end subroutine check_element_shapes

  !> The load curves' relations (curve_first_points, curve_times_increase); message '' when they hold.
  subroutine check_curve_relations(d, message)
    type(deck_t), intent(in) :: d
    character(len=*), intent(out) :: message
    integer :: i, k, last
    message = ''
    do i = 1, d%n_curves
      if (i == 1) then
        if (d%curve_first_point(1) == 1 .and. d%n_curve_points >= 1) cycle
      else if (d%curve_first_point(i) > d%curve_first_point(i - 1) .and. d%curve_first_point(i) <= d%n_curve_points) then
        cycle
      end if
      message = '/curves/first_point['//integer_text(i - 1)//'] = '//integer_text(d%curve_first_point(i) - 1)// &
                ' breaks the order of the curves; the first curve starts at point 0 and each next one later, '// &
                'below the number of curve points ('//integer_text(d%n_curve_points)//')'
      return
    end do
    do i = 1, d%n_curves
      last = d%n_curve_points
      if (i < d%n_curves) last = d%curve_first_point(i + 1) - 1
      do k = d%curve_first_point(i) + 1, last
        if (d%curve_time(k) > d%curve_time(k - 1)) cycle
        message = '/curves/time['//integer_text(k - 1)//'] = '//number_text(d%curve_time(k), class_float)// &
                  ' does not follow /curves/time['//integer_text(k - 2)//'] = '// &
                  number_text(d%curve_time(k - 1), class_float)//' of curve '//integer_text(i - 1)// &
                  '; give the times of each curve strictly increasing'
        return
      end do
    end do
  end subroutine check_curve_relations

end module model_deck
