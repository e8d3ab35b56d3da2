!> The members of the nodal effect family that a deck declares and the scene did not switch off,
!> in the order of schema/effects.toml (the order of the step: the loop runs over its ids, so the
!> order is stated there alone). A new member adds its case here.
module effect_factory
  use paradyn_kinds, only: wp
  use paradyn_schema, only: n_effects, effect_point_loads, effect_gravity, effect_pressure, effect_rigid_wall, &
                            effect_prescribed_velocity, effect_base_acceleration, effect_rigid_bodies, &
                            effect_rotation_ties
  use mpi_f08, only: MPI_Comm
  use model_deck, only: deck_t, node_row, deck_gravity
  use domain_decomposition, only: domain_t, local_node
  use effect_table, only: effect_table_t
  use nodal_effect, only: nodal_effect_holder_t
  use point_load_effect, only: point_load_effect_make
  use rigid_wall_effect, only: rigid_wall_effect_make
  use load_curves, only: load_curves_t, load_curves_from
  use gravity_effect, only: gravity_effect_make
  use pressure_effect, only: pressure_effect_make
  use prescribed_velocity, only: prescribed_velocity_make
  use base_acceleration_effect, only: base_acceleration_effect_make
  use rigid_body_effect, only: rigid_body_effect_make
  use weld_failure, only: weld_make
  use rotation_tie_effect, only: rotation_tie_effect_make
  use nodal_state, only: nodal_state_t
  implicit none
  private
  public :: make_nodal_effects

contains

  !> The running nodal effects of the table, built from the deck for this rank's domain and a
  !> run of step dt (the rigid walls' penalty stiffness is scaled to it). Collective over comm (the
  !> rigid bodies sum their masses over the ranks, and set their nodes' initial velocities in ns).
  subroutine make_nodal_effects(deck, dom, table, dt, ns, comm, effects)
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    type(effect_table_t), intent(in) :: table
    real(wp), intent(in) :: dt
    type(nodal_state_t), intent(inout) :: ns
    type(MPI_Comm), intent(in) :: comm
    type(nodal_effect_holder_t), allocatable, intent(out) :: effects(:)
    type(load_curves_t) :: curves
    integer :: k, id
    allocate (effects(0))
    curves = load_curves_from(deck%curve_first_point(1:deck%n_curves), deck%curve_time(1:deck%n_curve_points), &
                              deck%curve_value(1:deck%n_curve_points))
    do id = 1, n_effects   ! the order of schema/effects.toml is the order of the step
      if (.not. table%running(id)) cycle
      select case (id)
      case (effect_point_loads)
        call append(effects)
        allocate (effects(size(effects))%effect, source=point_load_effect_make( &
          [(local_node(dom, deck%load_node(k)), k = 1, deck%n_loads)], deck%load_dof(1:deck%n_loads), &
          deck%load_value(1:deck%n_loads), deck%load_ramp_time(1:deck%n_loads)))
      case (effect_gravity)
        call append(effects)
        allocate (effects(size(effects))%effect, source=gravity_effect_make(deck_gravity(deck)))
      case (effect_base_acceleration)
        call append(effects)
        allocate (effects(size(effects))%effect, source=base_acceleration_effect_make(curves, &
          deck%base_acceleration_direction, deck%base_acceleration_value, deck%base_acceleration_curve))
      case (effect_pressure)
        call append(effects)
        allocate (effects(size(effects))%effect, source=pressure_effect_make(curves, deck%pressure_part, &
          deck%pressure_value, deck%pressure_curve, deck%element_part))   ! the held elements: the domain's
      case (effect_rigid_wall)
        call append(effects)
        allocate (effects(size(effects))%effect, source=rigid_wall_effect_make(deck%rigid_wall_shape, &
          deck%rigid_wall_point, deck%rigid_wall_normal, deck%rigid_wall_edge, deck%rigid_wall_size, &
          deck%rigid_wall_radius, deck%rigid_wall_length, deck%rigid_wall_velocity, deck%rigid_wall_penalty_scale, &
          deck%rigid_wall_friction, deck%rigid_wall_birth_time, deck%rigid_wall_death_time, &
          deck%rigid_wall_node_wall(1:deck%n_rigid_wall_nodes), &
          [(local_node(dom, deck%rigid_wall_node(k)), k = 1, deck%n_rigid_wall_nodes)], dom%n_nodes, dt))
      case (effect_prescribed_velocity)
        call append(effects)
        allocate (effects(size(effects))%effect, source=prescribed_velocity_make(curves, &
          [(local_node(dom, deck%prescribed_node(k)), k = 1, deck%n_prescribed)], deck%prescribed_dof, &
          deck%prescribed_value, deck%prescribed_curve, [(initial_velocity(deck, k), k = 1, deck%n_prescribed)], &
          deck%prescribed_birth_time, deck%prescribed_death_time))
      case (effect_rigid_bodies)
        call append(effects)
        allocate (effects(size(effects))%effect, source=rigid_body_effect_make( &
          [(deck%node_rigid_body(node_row(deck, dom%nodes(k))), k = 1, dom%n_nodes)], deck%rigid_body_fixed_dofs, &
          deck%rigid_body_prescribed, deck%rigid_body_velocity, deck%rigid_body_curve, curves, &
          [(weld_make(deck%rigid_body_failure_force(:, k), deck%rigid_body_failure_exponent(:, k), &
                      deck%rigid_body_failure_time(k), deck%rigid_body_failure_normal(:, k), &
                      deck%rigid_body_failure_plastic_strain(k)), k = 1, deck%n_rigid_bodies)], &
          [(local_node(dom, deck%rigid_body_failure_node(k)), k = 1, deck%n_rigid_bodies)], &
          deck%rigid_body_given_mass, deck%rigid_body_given_centre, deck%rigid_body_given_inertia, ns, comm))
      case (effect_rotation_ties)
        call append(effects)
        allocate (effects(size(effects))%effect, source=rotation_tie_effect_make(deck%rotation_tie_node, &
          deck%rotation_tie_masters, deck%rotation_tie_weights, dom, comm))
      end select   ! effects that are not nodal (elements, contact, integration) are built elsewhere
    end do
  end subroutine make_nodal_effects

  !> The deck's initial velocity of prescribed motion k's dof (the velocity before the first step);
  !> 0 where this rank does not hold the node (the effect keeps only the rows of its nodes).
  pure real(wp) function initial_velocity(deck, k)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: k
    integer :: row
    initial_velocity = 0.0_wp
    row = node_row(deck, deck%prescribed_node(k))
    if (row == 0) return
    if (deck%prescribed_dof(k) <= 3) then
      initial_velocity = deck%velocity(deck%prescribed_dof(k), row)
    else
      initial_velocity = deck%angular_velocity(deck%prescribed_dof(k) - 3, row)
    end if
  end function initial_velocity

  !> One more (empty) holder at the end of the list.
  subroutine append(effects)
    type(nodal_effect_holder_t), allocatable, intent(inout) :: effects(:)
    type(nodal_effect_holder_t), allocatable :: longer(:)
    integer :: k
    allocate (longer(size(effects) + 1))
    do k = 1, size(effects)
      call move_alloc(effects(k)%effect, longer(k)%effect)
    end do
    call move_alloc(longer, effects)
  end subroutine append

end module effect_factory
