!> The forces of one step on the nodes of a rank: element forces by groups on the OpenMP threads,
!> the corner exchange with neighbour ranks, the fixed-order nodal sum, then the contact. Also the
!> lumped masses (mass scaling included), which go through the same corners at set-up.
module internal_forces
  use omp_lib, only: omp_get_thread_num
  use paradyn_kinds, only: wp
  use element_groups, only: group_size
  use shell_blt, only: blt_internal_forces
  use shell_full, only: full_internal_forces
  use shell_c0_triangle, only: c0_triangle_internal_forces
  use shell_measures, only: blt_lumped_mass, triangle_lumped_mass
  use element_erosion, only: erosion_before, erosion_after
  use truss_element, only: truss_internal_forces, truss_lumped_mass
  use work_queues, only: queues_start, queues_take
  use halo_exchange, only: exchange_corners
  use nodal_assembly, only: gather_group, assemble_nodes
  use phase_timers, only: wall_clock
  use contact_parallel, only: parallel_contact_step, parallel_contact_worked
  use contact_node_forces, only: contact_apply_forces
  use eroded_contact, only: eroded_contact_step
  use paradyn_schema, only: effect_elastic_shells, effect_plastic_shells, effect_contact, effect_friction
  use effect_table, only: effect_count, effect_time
  use effect_pipeline, only: apply_corner_loads
  use solver_state, only: solver_t
  implicit none
  private
  public :: forces_at_current_state, lumped_masses, workspace_per_group

  !> doubles of one thread's workspace: a group's x, v, w (3 x 4 each); the kernel writes the
  !> corner forces straight into the corner array
  integer, parameter :: workspace_per_group = group_size * 3 * 4 * 3

contains

  !> Internal (and contact) forces at the current positions, for the step dt_strain that ended there.
  !> The element phase's wall time goes to the effect table's shell rows in proportion to the
  !> threads' busy time on each material family.
  subroutine forces_at_current_state(s, dt_strain)
    type(solver_t), intent(inout) :: s
    real(wp), intent(in) :: dt_strain
    real(wp) :: t0, elements_s, busy(2)
    t0 = wall_clock()
    call element_forces(s, dt_strain, busy)
    elements_s = wall_clock() - t0
    if (s%has_corner_loads) call apply_corner_loads(s)
    t0 = wall_clock()
    call exchange_corners(s%dom, s%halo, s%corner)
    s%timers%communication = s%timers%communication + wall_clock() - t0
    t0 = wall_clock()
    call assemble_forces(s)
    elements_s = elements_s + wall_clock() - t0
    s%timers%elements = s%timers%elements + elements_s
    busy = busy / max(sum(busy), tiny(1.0_wp))
    call effect_time(s%effects, effect_elastic_shells, elements_s * busy(1))
    call effect_time(s%effects, effect_plastic_shells, elements_s * busy(2))
    if (s%has_contact) then
      t0 = wall_clock()
      s%contact%c%time = s%clock%time
      if (s%contact_erodes) call eroded_contact_step(s)   ! eroded elements leave the contact
      call parallel_contact_step(s%contact, s%nodes%x, s%nodes%v, s%clock%cycles, dt_strain, s%timers)
      call contact_apply_forces(s%contact%c, s%nodes%f_int)
      call effect_time(s%effects, effect_contact, wall_clock() - t0)
      if (s%started) then   ! the forces at the start are not a cycle; idle pairs skip their stages
        call effect_count(s%effects, effect_contact, parallel_contact_worked(s%contact))
        if (s%effects%running(effect_friction)) &
          call effect_count(s%effects, effect_friction, parallel_contact_worked(s%contact))
      end if
    end if
  end subroutine forces_at_current_state

  !> Element forces of every group for the step that ends at the current positions. The threads
  !> start on their own ranges of groups and then steal (work_queues); a group's forces go to its
  !> own corners, so the thread that computes it does not matter. busy: the threads' seconds on
  !> the groups of elastic (1) and plastic (2) parts.
  subroutine element_forces(s, dt_strain, busy)
    type(solver_t), intent(inout) :: s
    real(wp), intent(in) :: dt_strain
    real(wp), intent(out) :: busy(2)
    integer :: g, n, first, p, tid, emptied, inverted, ox, ov, ow, family
    real(wp) :: t0, e_kept(2, group_size)
    logical :: erodes
    inverted = 0
    busy = 0.0_wp
    ox = 1
    ov = ox + 12 * group_size
    ow = ov + 12 * group_size
    call queues_start(s%group_queues, s%dom%n_groups, s%threads)
    !$omp parallel private(g, n, first, p, tid, emptied, t0, family, e_kept, erodes) reduction(+:inverted, busy)
    tid = omp_get_thread_num() + 1
    emptied = 0
    do
      g = queues_take(s%group_queues, tid, emptied)
      if (g == 0) exit
      n = s%dom%group_count(g)
      first = s%dom%group_first(g)
      p = s%dom%group_part(g)
      if (s%props(p)%rigid) then   ! a rigid body's elements: no forces (a corner load may have added some)
        s%corner(:, 4 * first - 3:4 * (first + n - 1)) = 0.0_wp
        cycle
      end if
      t0 = wall_clock()
      call gather_group(n, first, s%dom%connectivity, s%nodes%x, s%workspace(ox, tid))
      call gather_group(n, first, s%dom%connectivity, s%nodes%v, s%workspace(ov, tid))
      call gather_group(n, first, s%dom%connectivity, s%nodes%w, s%workspace(ow, tid))
      erodes = s%props(p)%failure_strain > 0.0_wp   ! element_erosion: a part whose material fails
      associate (gs => s%elements%groups(g))
        if (erodes) call erosion_before(n, gs%eps_p, s%props(p)%failure_strain, s%props(p)%integration_points, &
                                        s%props(p)%failure_layers, s%dom%group_triangle(g), &
                                        s%workspace(ox, tid), s%workspace(ov, tid), s%workspace(ow, tid), &
                                        s%elements%e_internal(first), s%elements%e_hourglass(first), e_kept)
        if (s%props(p)%truss) then
          call truss_internal_forces(n, s%workspace(ox, tid), s%workspace(ov, tid), s%props(p), dt_strain, gs%stress, &
                                     gs%back, gs%eps_p, gs%state, s%corner(1, 4 * first - 3), &
                                     s%elements%e_internal(first), s%elements%dt_element(first))
        else if (s%dom%group_triangle(g)) then
          call c0_triangle_internal_forces(n, s%workspace(ox, tid), s%workspace(ov, tid), s%workspace(ow, tid), &
                                           s%props(p), dt_strain, gs%stress, gs%back, gs%eps_p, gs%state, gs%hourglass, &
                                           s%corner(1, 4 * first - 3), s%elements%e_internal(first), &
                                           s%elements%e_hourglass(first), inverted, s%elements%dt_element(first))
        else if (s%props(p)%fully_integrated) then   ! no hourglass control: its hourglass energy stays 0
          ! (gs%hourglass holds its drilling moments)
          call full_internal_forces(n, s%workspace(ox, tid), s%workspace(ov, tid), s%workspace(ow, tid), &
                                    s%props(p), dt_strain, gs%stress, gs%back, gs%eps_p, gs%state, gs%hourglass, &
                                    s%corner(1, 4 * first - 3), s%elements%e_internal(first), inverted, &
                                    s%elements%dt_element(first))
        else if (s%props(p)%thickness_update) then   ! the element's current thickness (gs%thickness)
          call blt_internal_forces(n, s%workspace(ox, tid), s%workspace(ov, tid), s%workspace(ow, tid), &
                                   s%props(p), dt_strain, gs%stress, gs%back, gs%eps_p, gs%state, gs%hourglass, &
                                   s%corner(1, 4 * first - 3), s%elements%e_internal(first), s%elements%e_hourglass(first), &
                                   inverted, s%elements%dt_element(first), gs%thickness)
        else
          call blt_internal_forces(n, s%workspace(ox, tid), s%workspace(ov, tid), s%workspace(ow, tid), &
                                   s%props(p), dt_strain, gs%stress, gs%back, gs%eps_p, gs%state, gs%hourglass, &
                                   s%corner(1, 4 * first - 3), s%elements%e_internal(first), s%elements%e_hourglass(first), &
                                   inverted, s%elements%dt_element(first))
        end if
        if (erodes) call erosion_after(n, gs%eps_p, s%props(p)%failure_strain, s%props(p)%integration_points, &
                                       s%props(p)%failure_layers, e_kept, gs%stress, gs%back, &
                                       gs%hourglass, s%corner(1, 4 * first - 3), s%elements%e_internal(first), &
                                       s%elements%e_hourglass(first), s%elements%dt_element(first))
      end associate
      family = merge(2, 1, s%part_effect(p) == effect_plastic_shells)
      busy(family) = busy(family) + wall_clock() - t0
    end do
    !$omp end parallel
    s%elements%inverted = s%elements%inverted + inverted
  end subroutine element_forces

  !> Fixed-order nodal sum of the corner forces, nodes split into one contiguous range per thread.
  !> (Static: stealing node blocks here, as the element groups do, moved the forces between the
  !> cores' caches and cost more in the node update than it saved: docs/performance.md.)
  subroutine assemble_forces(s)
    type(solver_t), intent(inout) :: s
    integer :: chunk, j0, nj, nl
    nl = s%dom%n_nodes
    chunk = max(1, (nl + s%threads - 1) / s%threads)
    !$omp parallel do schedule(static) private(j0, nj)
    do j0 = 1, nl, chunk
      nj = min(chunk, nl - j0 + 1)
      call assemble_nodes(nj, s%dom%assembly_start(j0:j0 + nj), s%dom%assembly_slot, s%corner, &
                          s%nodes%f_int(:, j0:j0 + nj - 1))
    end do
    !$omp end parallel do
  end subroutine assemble_forces

  !> Lumped masses and inertias of the local nodes through the same corner exchange and fixed-order
  !> sum as the forces; an element scaled by mass scaling adds its density's factor, the square of
  !> its step's (s%elements%step_scale).
  subroutine lumped_masses(s)
    type(solver_t), intent(inout) :: s
    integer :: g, n, first, p, j
    real(wp) :: node_mass(group_size), node_inertia(group_size), factor
    real(wp), allocatable :: xg(:, :, :)
    allocate (xg(group_size, 3, 4))
    do g = 1, s%dom%n_groups
      n = s%dom%group_count(g)
      first = s%dom%group_first(g)
      p = s%dom%group_part(g)
      call gather_group(n, first, s%dom%connectivity, s%nodes%x, xg)
      if (s%props(p)%truss) then
        call truss_lumped_mass(n, xg, s%props(p), node_mass, node_inertia)
      else if (s%dom%group_triangle(g)) then
        call triangle_lumped_mass(n, xg, s%props(p)%thickness, s%props(p)%density, s%props(p)%rotary_inertia, &
                                 node_mass, node_inertia)
      else
        call blt_lumped_mass(n, xg, s%props(p)%thickness, s%props(p)%density, s%props(p)%rotary_inertia, &
                            node_mass, node_inertia)
      end if
      if (s%props(p)%surface_only) then   ! a rigid solid's faces: its mass is on the nodes (added_mass)
        node_mass = 0.0_wp
        node_inertia = 0.0_wp
      else if (s%props(p)%rigid) then   ! no rotations to keep stable: the section's own rotary inertia
        node_inertia = node_mass * s%props(p)%thickness**2 / 12.0_wp
      end if
      do j = 1, n
        factor = s%elements%step_scale(first + j - 1)**2
        s%corner(1:3, 4 * (first + j - 2) + 1:4 * (first + j - 1)) = node_mass(j) * factor
        s%corner(4:6, 4 * (first + j - 2) + 1:4 * (first + j - 1)) = node_inertia(j) * factor
        if (s%props(p)%truss) then
          ! ends 1 and 2 only; the rod's rotary inertia in slot 5 alone, for nodes of trusses alone
          s%corner(:, 4 * (first + j - 1) - 1:4 * (first + j - 1)) = 0.0_wp
          s%corner(4, 4 * (first + j - 2) + 1:4 * (first + j - 2) + 2) = 0.0_wp
          s%corner(6, 4 * (first + j - 2) + 1:4 * (first + j - 2) + 2) = 0.0_wp
        else if (s%dom%group_triangle(g)) then   ! a triangle's fourth corner is its third node again
          s%corner(:, 4 * (first + j - 1)) = 0.0_wp
        end if
      end do
    end do
    call exchange_corners(s%dom, s%halo, s%corner)
    call assemble_nodes(s%nodes%n, s%dom%assembly_start, s%dom%assembly_slot, s%corner, s%nodes%f_int)
    s%nodes%mass = s%nodes%f_int(1, :)
    s%nodes%inertia = s%nodes%f_int(4, :)
    ! a node of trusses alone has no rotary inertia from shells: its rods' (slot 5, which equals
    ! slot 4 for shells, so a shell model's inertias are untouched); no moment ever turns it
    where (s%nodes%inertia == 0.0_wp) s%nodes%inertia = s%nodes%f_int(5, :)
    s%nodes%f_int = 0.0_wp
  end subroutine lumped_masses

end module internal_forces
