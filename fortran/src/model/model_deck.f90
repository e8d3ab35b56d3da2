!> The whole model as read from a deck (global numbering, 1-based inside the engine), and the
!> checks of its values that do not depend on how it was read.
module model_deck
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use paradyn_kinds, only: wp
  use shell_blt, only: shell_properties_t, material_elastic, material_j2_plastic, &
                       max_integration_points, hourglass_viscous, hourglass_stiffness
  use domain_decomposition, only: partition_blocks, partition_rcb
  use material_factory, only: material_from_name, material_name_of_code
  implicit none
  private
  public :: deck_t, part_properties, check_deck_values, partition_code, partition_label, partition_default

  !> The method when /control has no partition attribute (measured: docs/performance.md).
  integer, parameter :: partition_default = partition_blocks

  type :: deck_t
    integer :: n_nodes = 0, n_elements = 0, n_parts = 0, n_materials = 0
    integer :: n_loads = 0, n_tracked = 0, n_contacts = 0
    real(wp), allocatable :: coordinates(:, :)        !< (3, n_nodes)
    real(wp), allocatable :: velocity(:, :)           !< (3, n_nodes)
    real(wp), allocatable :: angular_velocity(:, :)   !< (3, n_nodes)
    integer, allocatable :: fixed(:, :)               !< (6, n_nodes), 1 = fixed
    integer, allocatable :: connectivity(:, :)        !< (4, n_elements), 1-based nodes
    integer, allocatable :: element_part(:)           !< (n_elements), 1-based
    real(wp), allocatable :: thickness(:), hourglass_coefficient(:)
    integer, allocatable :: part_material(:), integration_points(:), hourglass_form(:)
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
    real(wp) :: end_time = 0.0_wp, output_interval = 0.0_wp, history_interval = 0.0_wp
    real(wp) :: time_step = 0.0_wp, time_step_safety = 0.9_wp, mass_damping = 0.0_wp
    real(wp) :: progress_interval = 0.5_wp
    integer :: contact_sort_interval = 0              !< cycles between bucket sorts, 0 = automatic
    real(wp) :: checkpoint_interval = 0.0_wp          !< simulated seconds between checkpoints, 0 = none
    integer :: partition = partition_default          !< partition_blocks or partition_rcb; 0 = unknown name
    character(len=:), allocatable :: partition_name   !< /control partition as written, for messages
  end type deck_t

contains

  !> Method code of a /control partition name: partition_blocks, partition_rcb, or 0 if unknown.
  pure integer function partition_code(name) result(code)
    character(len=*), intent(in) :: name
    select case (name)
    case ('blocks')
      code = partition_blocks
    case ('rcb')
      code = partition_rcb
    case default
      code = 0
    end select
  end function partition_code

  !> The /control name of a partition method code.
  pure function partition_label(code) result(name)
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    select case (code)
    case (partition_blocks)
      name = 'blocks'
    case (partition_rcb)
      name = 'rcb'
    case default
      name = 'unknown'
    end select
  end function partition_label

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
    props%density = deck%density(m)
    props%young = deck%young(m)
    props%poisson = deck%poisson(m)
    call material_from_name(material_name_of_code(deck%material_model(m)), deck%young(m), deck%poisson(m), &
                            deck%yield_stress(m), deck%tangent_modulus(m), deck%hardening_mixing(m), props%material)
  end function part_properties

  !> Check every value of a deck whose arrays have the right shapes. Returns 0, or 2 with a
  !> message naming the dataset (0-based indices, as in the file) and the fix.
  subroutine check_deck_values(d, status, message)
    type(deck_t), intent(in) :: d
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer :: i, j, k

    status = 2
    do i = 1, d%n_nodes
      do k = 1, 3
        if (.not. finite(d%coordinates(k, i))) then
          write (message, '(a,i0,a,i0,a)') '/nodes/coordinates[', i - 1, ', ', k - 1, &
            '] is not a finite number; give every node a real position in metres'
          return
        end if
        if (.not. (finite(d%velocity(k, i)) .and. finite(d%angular_velocity(k, i)))) then
          write (message, '(a,i0,a)') '/nodes/initial_velocity or initial_angular_velocity of node ', &
            i - 1, ' is not finite; give finite initial velocities'
          return
        end if
      end do
      if (any(d%fixed(:, i) /= 0 .and. d%fixed(:, i) /= 1)) then
        write (message, '(a,i0,a)') '/nodes/fixed_dofs[', i - 1, '] holds a value other than 0 or 1'
        return
      end if
    end do
    do i = 1, d%n_elements
      do k = 1, 4
        if (d%connectivity(k, i) < 1 .or. d%connectivity(k, i) > d%n_nodes) then
          write (message, '(a,i0,a,i0,a,i0,a,i0,a)') '/elements/connectivity[', i - 1, ', ', k - 1, &
            '] = ', d%connectivity(k, i) - 1, ' is not a node index in 0..', d%n_nodes - 1, &
            '; node indices are 0-based'
          return
        end if
        do j = k + 1, 4
          if (d%connectivity(k, i) == d%connectivity(j, i)) then
            write (message, '(a,i0,a)') '/elements/connectivity[', i - 1, &
              '] repeats a node; every shell needs four distinct nodes (no triangles)'
            return
          end if
        end do
      end do
      if (d%element_part(i) < 1 .or. d%element_part(i) > d%n_parts) then
        write (message, '(a,i0,a,i0,a,i0)') '/elements/part[', i - 1, '] = ', d%element_part(i) - 1, &
          ' is not a part index in 0..', d%n_parts - 1
        return
      end if
    end do
    do i = 1, d%n_parts
      if (.not. (d%thickness(i) > 0.0_wp) .or. .not. finite(d%thickness(i))) then
        write (message, '(a,i0,a,es12.4,a)') '/parts/thickness[', i - 1, '] = ', d%thickness(i), &
          ' must be > 0; set a positive shell thickness in metres'
        return
      end if
      if (d%part_material(i) < 1 .or. d%part_material(i) > d%n_materials) then
        write (message, '(a,i0,a,i0)') '/parts/material[', i - 1, '] is not a material index in 0..', &
          d%n_materials - 1
        return
      end if
      if (d%integration_points(i) < 1 .or. d%integration_points(i) > max_integration_points) then
        write (message, '(a,i0,a,i0,a)') '/parts/integration_points[', i - 1, '] = ', &
          d%integration_points(i), ' must be between 1 and 9'
        return
      end if
      if (d%hourglass_form(i) /= hourglass_viscous .and. d%hourglass_form(i) /= hourglass_stiffness) then
        write (message, '(a,i0,a,i0,a)') '/parts/hourglass_form[', i - 1, '] = ', d%hourglass_form(i), &
          ' is unknown; use 1 (viscous) or 2 (stiffness)'
        return
      end if
      if (.not. (d%hourglass_coefficient(i) >= 0.0_wp)) then
        write (message, '(a,i0,a)') '/parts/hourglass_coefficient[', i - 1, '] must be >= 0'
        return
      end if
    end do
    do i = 1, d%n_materials
      if (d%material_model(i) /= material_elastic .and. d%material_model(i) /= material_j2_plastic) then
        write (message, '(a,i0,a,i0,a)') '/materials/model[', i - 1, '] = ', d%material_model(i), &
          ' is unknown; use 1 (linear elastic) or 2 (J2 plasticity)'
        return
      end if
      if (.not. (d%density(i) > 0.0_wp .and. d%young(i) > 0.0_wp)) then
        write (message, '(a,i0,a)') '/materials/density and youngs_modulus of material ', i - 1, &
          ' must be > 0 (kg/m^3 and Pa)'
        return
      end if
      if (.not. (d%poisson(i) > -1.0_wp .and. d%poisson(i) < 0.5_wp)) then
        write (message, '(a,i0,a,f8.4,a)') '/materials/poisson_ratio[', i - 1, '] = ', d%poisson(i), &
          ' must lie in (-1, 0.5)'
        return
      end if
      if (d%material_model(i) == material_j2_plastic) then
        if (.not. (d%yield_stress(i) > 0.0_wp)) then
          write (message, '(a,i0,a)') '/materials/yield_stress[', i - 1, '] must be > 0 for J2 plasticity'
          return
        end if
        if (.not. (d%tangent_modulus(i) >= 0.0_wp .and. d%tangent_modulus(i) < d%young(i))) then
          write (message, '(a,i0,a)') '/materials/tangent_modulus[', i - 1, &
            '] must satisfy 0 <= Et < E'
          return
        end if
        if (.not. (d%hardening_mixing(i) >= 0.0_wp .and. d%hardening_mixing(i) <= 1.0_wp)) then
          write (message, '(a,i0,a)') '/materials/hardening_mixing[', i - 1, '] must lie in [0, 1]'
          return
        end if
      end if
    end do
    do i = 1, d%n_loads
      if (d%load_node(i) < 1 .or. d%load_node(i) > d%n_nodes) then
        write (message, '(a,i0,a)') '/loads/node[', i - 1, '] is not a node index'
        return
      end if
      if (d%load_dof(i) < 1 .or. d%load_dof(i) > 6) then
        write (message, '(a,i0,a)') '/loads/dof[', i - 1, '] must be 1..6 (forces x, y, z; moments x, y, z)'
        return
      end if
      if (.not. (finite(d%load_value(i)) .and. d%load_ramp_time(i) >= 0.0_wp)) then
        write (message, '(a,i0,a)') '/loads/value or ramp_time[', i - 1, '] is not finite or ramp_time < 0'
        return
      end if
    end do
    do i = 1, d%n_contacts
      if (any(d%contact_pairs(:, i) < 1 .or. d%contact_pairs(:, i) > d%n_parts) .or. &
          d%contact_pairs(1, i) == d%contact_pairs(2, i)) then
        write (message, '(a,i0,a,i0)') '/contact/pairs[', i - 1, &
          '] must name two different parts in 0..', d%n_parts - 1
        return
      end if
      if (.not. (d%contact_penalty_scale(i) > 0.0_wp .and. d%contact_static_friction(i) >= 0.0_wp &
                 .and. d%contact_dynamic_friction(i) >= 0.0_wp .and. d%contact_friction_decay(i) >= 0.0_wp)) then
        write (message, '(a,i0,a)') '/contact/penalty_scale[', i - 1, &
          '] must be > 0 and the friction coefficients and decay >= 0'
        return
      end if
      if (d%contact_passes(i) /= 1 .and. d%contact_passes(i) /= 2) then
        write (message, '(a,i0,a)') '/contact/passes[', i - 1, '] must be 1 (alternate) or 2 (both)'
        return
      end if
    end do
    if (d%partition /= partition_blocks .and. d%partition /= partition_rcb) then
      message = '/control attribute partition = "'//partition_shown(d)//'" is unknown; use "blocks" '// &
        '(contiguous element blocks) or "rcb" (recursive coordinate bisection), or leave it out for the default'
      return
    end if
    if (d%contact_sort_interval < 0) then
      message = '/control attribute contact_sort_interval must be >= 0 (0 = automatic)'
      return
    end if
    if (.not. (d%checkpoint_interval >= 0.0_wp)) then
      message = '/control attribute checkpoint_interval must be >= 0 (seconds of simulated time, 0 = none)'
      return
    end if
    do i = 1, d%n_tracked
      if (d%tracked_nodes(i) < 1 .or. d%tracked_nodes(i) > d%n_nodes) then
        write (message, '(a,i0,a)') '/output/tracked_nodes[', i - 1, '] is not a node index'
        return
      end if
    end do
    if (.not. (d%end_time > 0.0_wp)) then
      message = '/control attribute end_time must be > 0 (seconds)'
      return
    end if
    if (.not. (d%output_interval > 0.0_wp .and. d%history_interval > 0.0_wp)) then
      message = '/control attributes output_interval and history_interval must be > 0 (seconds)'
      return
    end if
    if (.not. (d%time_step >= 0.0_wp)) then
      message = '/control attribute time_step must be >= 0 (0 = automatic)'
      return
    end if
    if (.not. (d%time_step_safety > 0.0_wp .and. d%time_step_safety <= 1.0_wp)) then
      message = '/control attribute time_step_safety must lie in (0, 1]'
      return
    end if
    if (.not. (d%mass_damping >= 0.0_wp)) then
      message = '/control attribute mass_damping must be >= 0'
      return
    end if
    status = 0
    message = ''
  end subroutine check_deck_values

  pure function partition_shown(d) result(name)
    type(deck_t), intent(in) :: d
    character(len=:), allocatable :: name
    name = ''
    if (allocated(d%partition_name)) name = d%partition_name
  end function partition_shown

  elemental logical function finite(x)
    real(wp), intent(in) :: x
    finite = ieee_is_finite(x)
  end function finite

end module model_deck
