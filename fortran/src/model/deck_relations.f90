!> The relations between fields of a deck that the schema's per-field rules (deck_rules) cannot
!> express, as messages over the rows one rank holds (model_deck's layout); io/deck_checks applies
!> them in order across the ranks, so every rank reaches the verdict one rank holding the whole
!> deck would. Pure: no MPI.
module deck_relations
  use paradyn_kinds, only: wp
  use paradyn_schema, only: material_is_plastic, material_is_rigid, contact_kind_is_self_contact, class_float, &
                            enum_name, enum_precision, precision_mixed, material_is_hardening_curve, &
                            material_piecewise_linear, element_kind_is_truss, shell_element_full
  use deck_rules, only: integer_text, number_text, index_list
  use quad_shape, only: quad_shape_fault, triangle_shape_fault, shape_sound, shape_concave
  use model_deck, only: deck_t, node_row, engine_precision
  use rigid_wall, only: wall_requirement
  implicit none
  private
  public :: precision_message, repeated_node_message, duplicate_element_message, shape_message, &
            thickness_update_message, &
            small_table_message, rigid_node_message, unused_node_message, wall_normal_message, wall_behind_message, &
            wall_rows_message, check_curve_relations

contains

  ! The relations between fields of a deck whose every field has passed its own rules, in the
  ! order io/deck_checks applies them (schema relations: precision, distinct_element_nodes,
  ! distinct_elements, element shapes, thickness_update_elements, tangent_below_youngs, contact_parts_differ,
  ! node_in_element, the rigid walls' and the load curves' (curve_first_points,
  ! curve_times_increase, then the materials' curves: material_curves)). Each message names the dataset, the 0-based entry and the fix; ''
  ! when the relation holds.

  !> The deck's precision against this engine's.
  function precision_message(d) result(message)
    type(deck_t), intent(in) :: d
    character(len=:), allocatable :: message
    message = ''
    if (d%precision == engine_precision) return
    message = '/control precision = "'//enum_name(enum_precision, d%precision)//'" but this engine computes in '// &
              enum_name(enum_precision, engine_precision)//' precision; run paradyn-engine'//trim(merge('-mixed', &
              '      ', d%precision == precision_mixed))//' (paradyn-run picks it from the deck), or change [run] precision'
  end function precision_message

  !> Held element row `row` names a node twice, other than a triangle's third node as its fourth.
  function repeated_node_message(d, row) result(message)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: row
    character(len=:), allocatable :: message
    integer :: j, k
    message = ''
    if (element_kind_is_truss(d%element_kind(d%element_part(row)))) then
      associate (c => d%connectivity(:, row))
        if (c(1) /= c(2) .and. c(2) == c(3) .and. c(3) == c(4)) return
      end associate
      message = '/elements/connectivity['//integer_text(d%element_ids(row) - 1)//'] = '// &
                index_list(d%connectivity(:, row))//' is an element of truss part '// &
                integer_text(d%element_part(row) - 1)//'; a truss names two distinct nodes, the second repeated '// &
                'as the third and fourth (N1 N2 N2 N2)'
      return
    end if
    do k = 1, 4
      do j = k + 1, 4
        if (d%connectivity(k, row) /= d%connectivity(j, row) .or. (k == 3 .and. j == 4)) cycle
        message = '/elements/connectivity['//integer_text(d%element_ids(row) - 1)//'] = '// &
                  index_list(d%connectivity(:, row))//' repeats a node; every quadrilateral needs four distinct '// &
                  'nodes, a triangle three with the third repeated as the fourth (remesh without collapsed elements)'
        return
      end do
    end do
  end function repeated_node_message

  !> Held element row `row` belongs to a part with /parts/thickness_update = 1 that cannot update its
  !> thickness: the update is the one-point quadrilateral's (shell_blt), not a triangle's, the fully
  !> integrated element's, a truss's or a rigid part's.
  function thickness_update_message(d, row) result(message)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: row
    character(len=:), allocatable :: message
    character(len=:), allocatable :: why
    integer :: part
    message = ''
    part = d%element_part(row)
    if (d%thickness_update(part) == 0) return
    if (element_kind_is_truss(d%element_kind(part))) then
      why = 'it is a truss part'
    else if (material_is_rigid(d%material_model(d%part_material(part)))) then
      why = 'its material is rigid'
    else if (d%shell_element(part) == shell_element_full) then
      why = 'its element is the fully integrated one (/parts/shell_element = 2)'
    else if (d%connectivity(3, row) == d%connectivity(4, row)) then
      why = 'its element '//integer_text(d%element_ids(row) - 1)//' is a triangle'
    else
      return
    end if
    message = '/parts/thickness_update['//integer_text(part - 1)//'] = 1, but '//why// &
              '; the thickness update is the one-point quadrilateral''s: set it to 0, or give the part '// &
              'one-point quadrilaterals only'
  end function thickness_update_message

  !> Element `later` (1-based, its nodes later_nodes) has the nodes of element `earlier`.
  function duplicate_element_message(later, earlier, later_nodes) result(message)
    integer, intent(in) :: later, earlier, later_nodes(4)
    character(len=:), allocatable :: message
    message = '/elements/connectivity['//integer_text(later - 1)//'] = '//index_list(later_nodes)// &
              ' has the same nodes as element '//integer_text(earlier - 1)//'; a duplicated element doubles its '// &
              'mass and stiffness, remove it'
  end function duplicate_element_message

  !> Held element row `row` convex, without coincident or collinear corners (quad_shape; a triangle:
  !> with an area).
  function shape_message(d, row) result(message)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: row
    character(len=:), allocatable :: message
    integer :: fault, corner, node, k
    real(wp) :: x(3, 4)
    message = ''
    x = d%coordinates(:, [(node_row(d, d%connectivity(k, row)), k = 1, 4)])
    if (element_kind_is_truss(d%element_kind(d%element_part(row)))) then
      if (norm2(x(:, 2) - x(:, 1)) > 0.0_wp) return
      message = '/nodes/coordinates: element '//integer_text(d%element_ids(row) - 1)//' (truss part '// &
                integer_text(d%element_part(row) - 1)//', nodes '//index_list(d%connectivity(:, row))// &
                ') has zero length (its two nodes coincide); move a node or remove the truss'
      return
    end if
    if (d%connectivity(3, row) == d%connectivity(4, row)) then
      call triangle_shape_fault(x(:, 1:3), fault, corner)
    else
      call quad_shape_fault(x, fault, corner)
    end if
    if (fault == shape_sound) return
    node = d%connectivity(corner, row)
    associate (i => d%element_ids(row))
      if (fault == shape_concave) then
        message = '/nodes/coordinates: element '//integer_text(i - 1)//' (part '//integer_text(d%element_part(row) - 1)// &
                  ', nodes '//index_list(d%connectivity(:, row))//') is concave or twisted at node '// &
                  integer_text(node - 1)//'; remesh it (a concave quadrilateral turns inside out at the first step)'
      else
        message = '/nodes/coordinates: element '//integer_text(i - 1)//' (part '//integer_text(d%element_part(row) - 1)// &
                  ', nodes '//index_list(d%connectivity(:, row))//') is collapsed or crossed at node '// &
                  integer_text(node - 1)//' (coincident or collinear corners, or sides that cross); remesh it'
      end if
    end associate
  end function shape_message

  !> The relations of the tables every rank holds whole that come before the nodes' (the J2
  !> tangent modulus, the contact pairs).
  function small_table_message(d) result(message)
    type(deck_t), intent(in) :: d
    character(len=:), allocatable :: message
    integer :: i
    message = ''
    do i = 1, d%n_materials
      if (.not. material_is_plastic(d%material_model(i))) cycle
      if (.not. (d%tangent_modulus(i) < d%young(i))) then
        message = '/materials/tangent_modulus['//integer_text(i - 1)//'] = '// &
                  number_text(d%tangent_modulus(i), class_float)//' must be below /materials/youngs_modulus['// &
                  integer_text(i - 1)//'] = '//number_text(d%young(i), class_float)// &
                  ' for a plastic material; give the plastic tangent modulus in Pa below Young''s modulus'
        return
      end if
    end do
    do i = 1, d%n_contacts
      if (contact_kind_is_self_contact(d%contact_kind(i)) .neqv. d%contact_pairs(1, i) == d%contact_pairs(2, i)) then
        if (contact_kind_is_self_contact(d%contact_kind(i))) then
          message = '/contact/pairs['//integer_text(i - 1)//'] = '//index_list(d%contact_pairs(:, i))// &
                    ' names two parts for a single_surface contact; name its one part twice'
        else
          message = '/contact/pairs['//integer_text(i - 1)//'] = '//index_list(d%contact_pairs(:, i))// &
                    ' pairs a part with itself; name two different parts, or make the contact single_surface'
        end if
        return
      end if
      if (any(element_kind_is_truss(d%element_kind(d%contact_pairs(:, i))))) then
        message = '/contact/pairs['//integer_text(i - 1)//'] = '//index_list(d%contact_pairs(:, i))// &
                  ' names a truss part; trusses have no contact surface, name shell parts only'
        return
      end if
    end do
    do i = 1, d%n_rigid_bodies
      if (d%rigid_body_part(i) == 0) cycle   ! a body of nodes alone
      if (material_is_rigid(d%material_model(d%part_material(d%rigid_body_part(i))))) cycle
      message = '/rigid_bodies/part['//integer_text(i - 1)//'] = '//integer_text(d%rigid_body_part(i) - 1)// &
                ' names a part whose material is not rigid; give the part a rigid material, or remove the body'
      return
    end do
  end function small_table_message

  !> The schema relation rigid_bodies_whole on held element row `row`: if its part is rigid, each
  !> of its nodes is in a rigid body.
  function rigid_node_message(d, row) result(message)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: row
    character(len=:), allocatable :: message
    integer :: k, node
    message = ''
    if (.not. material_is_rigid(d%material_model(d%part_material(d%element_part(row))))) return
    do k = 1, 4
      node = d%connectivity(k, row)
      if (d%node_rigid_body(node_row(d, node)) > 0) cycle
      message = '/nodes/rigid_body['//integer_text(node - 1)//'] = -1 but the node is on element '// &
                integer_text(d%element_ids(row) - 1)//' of part '//integer_text(d%element_part(row) - 1)// &
                ', whose material is rigid; give every node of a rigid part''s elements the row of its body '// &
                'in /rigid_bodies'
      return
    end do
  end function rigid_node_message

  !> Node `first` (1-based), the lowest of `unused` nodes, belongs to no element.
  function unused_node_message(first, unused) result(message)
    integer, intent(in) :: first, unused
    character(len=:), allocatable :: message
    message = '/nodes/coordinates['//integer_text(first - 1)//'] belongs to no element ('// &
              integer_text(unused)//' such nodes); a node without elements has no mass, remove unused nodes'
  end function unused_node_message

  !> The schema relations rigid_wall_normal_nonzero and rigid_wall_geometry for wall w.
  function wall_normal_message(d, w) result(message)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: w
    character(len=:), allocatable :: message
    message = ''
    if (.not. norm2(d%rigid_wall_normal(:, w)) > 0.0_wp) then
      message = '/rigid_walls/normal['//integer_text(w - 1)//'] is the zero vector; give a nonzero normal '// &
                'pointing from the wall towards the model (a cylinder: its axis)'
      return
    end if
    message = wall_requirement(d%rigid_wall_shape(w), d%rigid_wall_normal(:, w), d%rigid_wall_edge(:, w), &
                               d%rigid_wall_size(:, w), d%rigid_wall_radius(w))
    if (message /= '') message = '/rigid_walls/shape['//integer_text(w - 1)//'] = '//message// &
                                 '; give the wall its /rigid_walls/edge, size or radius'
  end function wall_normal_message

  !> The schema relation rigid_wall_nodes_in_front broken: node (1-based) is `distance` inside wall w.
  function wall_behind_message(w, node, distance) result(message)
    integer, intent(in) :: w, node
    real(wp), intent(in) :: distance
    character(len=:), allocatable :: message
    message = '/rigid_walls/point['//integer_text(w - 1)//'] puts node '//integer_text(node - 1)// &
              ' behind the wall at the start (signed distance '//number_text(distance, class_float)// &
              ' m to its surface, inside it); move the wall or flip its normal so that the model starts on its outer side'
  end function wall_behind_message

  !> The schema relation rigid_wall_nodes_wall: every row names a wall (1-based, n_walls of them).
  function wall_rows_message(d, n_walls) result(message)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: n_walls
    character(len=:), allocatable :: message
    integer :: k
    message = ''
    do k = 1, d%n_rigid_wall_nodes
      if (d%rigid_wall_node_wall(k) <= n_walls) cycle
      message = '/rigid_wall_nodes/wall['//integer_text(k - 1)//'] = '//integer_text(d%rigid_wall_node_wall(k) - 1)// &
                ' names no rigid wall (the deck has '//integer_text(n_walls)//'); give the 0-based index of a wall'
      return
    end do
  end function wall_rows_message

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
    do i = 1, d%n_materials
      message = material_curve_message(d, i)
      if (message /= '') return
    end do
  end subroutine check_curve_relations

  !> material_curves for material i: its hardening curve starts at (0, yield_stress) and never
  !> decreases; its rate curve's rates are >= 0 and its factors > 0 (the curves' order and times
  !> already checked).
  function material_curve_message(d, i) result(message)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: i
    character(len=:), allocatable :: message
    character(len=*), parameter :: hardening = '/materials/hardening_curve[', rate = '/materials/rate_curve['
    integer :: c, first, last, k
    message = ''
    c = 0
    if (material_is_hardening_curve(d%material_model(i))) c = d%hardening_curve(i)
    if (c > 0) then
      call curve_range(d, c, first, last)
      if (d%curve_time(first) /= 0.0_wp .or. d%curve_value(first) /= d%yield_stress(i)) then
        message = hardening//integer_text(i - 1)//'] = '//integer_text(c - 1)//': the curve starts at ('// &
                  number_text(d%curve_time(first), class_float)//', '//number_text(d%curve_value(first), class_float)// &
                  '), not at zero plastic strain with /materials/yield_stress = '// &
                  number_text(d%yield_stress(i), class_float)//'; start the curve at (0, yield_stress)'
        return
      end if
      do k = first + 1, last
        if (d%curve_value(k) >= d%curve_value(k - 1)) cycle
        message = hardening//integer_text(i - 1)//'] = '//integer_text(c - 1)//': the yield stress decreases to '// &
                  number_text(d%curve_value(k), class_float)//' at plastic strain '// &
                  number_text(d%curve_time(k), class_float)//'; give a curve that never decreases (no softening)'
        return
      end do
    end if
    c = 0
    if (d%material_model(i) == material_piecewise_linear) c = d%rate_curve(i)
    if (c > 0) then
      call curve_range(d, c, first, last)
      if (d%curve_time(first) < 0.0_wp .or. any(d%curve_value(first:last) <= 0.0_wp)) then
        message = rate//integer_text(i - 1)//'] = '//integer_text(c - 1)//': a rate curve has strain rates '// &
                  '>= 0 and factors > 0, this one starts at rate '//number_text(d%curve_time(first), class_float)// &
                  ' with least factor '//number_text(minval(d%curve_value(first:last)), class_float)// &
                  '; give rates >= 0 and factors > 0'
      end if
    end if
  end function material_curve_message

  !> First and last point of curve c (1-based)
  pure subroutine curve_range(d, c, first, last)
    type(deck_t), intent(in) :: d
    integer, intent(in) :: c
    integer, intent(out) :: first, last
    first = d%curve_first_point(c)
    last = d%n_curve_points
    if (c < d%n_curves) last = d%curve_first_point(c + 1) - 1
  end subroutine curve_range

end module deck_relations
