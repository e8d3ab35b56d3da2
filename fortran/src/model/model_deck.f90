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
  use paradyn_schema, only: material_is_plastic, material_is_rigid, control_attributes, control_partition, &
                            precision_double, precision_mixed, element_kind_is_truss, shell_element_full
  use deck_fields, only: deck_fields_t, store_dataset, store_control
  use material_factory, only: material_from_deck
  use element_erosion, only: failed_layers_needed
  implicit none
  private
  public :: deck_t, part_properties, partition_default, engine_precision
  public :: store_dataset, store_control, node_row, element_row, deck_gravity

  !> The method when /control has no partition attribute (schema default; docs/performance.md).
  integer, parameter :: partition_default = nint(control_attributes(control_partition)%default)
  !> This engine's precision (precision_double or precision_mixed): the kind of its element kernel
  integer, parameter :: engine_precision = merge(precision_mixed, precision_double, ek /= wp)

  !> The deck: the schema's fields (deck_fields, generated: one per dataset and /control
  !> attribute, the row counts n_<symbol>) and the rows of the mesh this rank holds.
  type, extends(deck_fields_t) :: deck_t
    integer, allocatable :: node_ids(:)               !< the global nodes held, ascending (mesh rows)
    integer, allocatable :: node_part(:)              !< the part of each held node's lowest-numbered element
    integer, allocatable :: element_ids(:)            !< the global elements held, ascending (mesh rows)
    logical :: any_fixed = .false.                    !< some node of the whole mesh has a fixed dof
    integer :: rows_read(2) = 0                       !< the mesh rows this rank read: elements, nodes
    character(len=16), allocatable :: fingerprint_groups(:)   !< "nodes", ..., "control" (deck_fingerprint)
    real(wp), allocatable :: fingerprints(:)                  !< one 32-bit hash per group, held exactly
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
    props%rotary_inertia = deck%rotary_inertia(part)
    props%fully_integrated = deck%shell_element(part) == shell_element_full
    props%thickness_update = deck%thickness_update(part) /= 0
    props%rigid = material_is_rigid(deck%material_model(m))
    props%surface_only = deck%surface_only(part) /= 0
    props%truss = element_kind_is_truss(deck%element_kind(part))
    if (props%truss) then   ! one stress point, the axial stress; the thickness is a nominal diameter
      props%area = deck%area(part)
      props%integration_points = 1
    end if
    props%density = deck%density(m)
    props%young = deck%young(m)
    props%poisson = deck%poisson(m)
    if (material_is_plastic(deck%material_model(m))) then
      props%hourglass_yield = deck%yield_stress(m)
      props%failure_strain = deck%failure_strain(m)
      props%failure_layers = failed_layers_needed(deck%failure_points(m), props%integration_points)
    end if
    call material_from_deck(deck, m, props%material)
  end function part_properties

  !> The body acceleration of the deck's /control gravity_x, gravity_y, gravity_z (m/s^2).
  pure function deck_gravity(d) result(g)
    type(deck_t), intent(in) :: d
    real(wp) :: g(3)
    g = [d%gravity_x, d%gravity_y, d%gravity_z]
  end function deck_gravity

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
