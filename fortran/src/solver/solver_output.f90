!> What the time loop writes: history records (energies, tracked nodes, and the checks for NaN and
!> inverted elements), field frames, progress lines, and the run record of the /run attributes.
module solver_output
  use mpi_f08
  use paradyn_kinds, only: wp, ek, i8
  use paradyn_schema, only: status_ok, status_numerical, n_history_scalars, history_kinetic_energy, &
                            history_internal_energy, history_hourglass_energy, history_contact_energy, &
                            history_external_work, history_contact_penetration, effect_time_integration, &
                            history_dt, history_dt_element, history_dt_stable, history_eroded_elements, &
                            history_failed_welds, history_failed_ties
  use element_erosion, only: eroded_count
  use element_groups, only: group_size
  use shell_measures, only: blt_element_results
  use shell_section, only: thickness_rule
  use paradyn_schema, only: max_integration_points
  use vector_algebra, only: cross
  use halo_exchange, only: sum_to_root
  use time_integration, only: kinetic_energy, kinetic_energy_by_part, add_constraint_reactions
  use step_clock, only: half_step
  use nodal_assembly, only: gather_group
  use contact_node_forces, only: contact_add_nodal_forces
  use shell_field_measures, only: layer_stresses, membrane_green_strain, surface_strains, initial_volumes, n_layers, &
                                  in_plane_means, current_thicknesses
  use shell_section, only: stress_components
  use results_writer, only: results_file_t, results_write_frame, results_write_history, run_record_t
  use solver_state, only: solver_t
  use phase_timers, only: wall_clock
  use exact_sum, only: exact_width, exact_normalise, exact_value
  implicit none
  private
  public :: write_record, write_frame, write_progress, run_record, write_phase_line

contains

  !> Energies and tracked nodes at the current time. Each tracked node is reported by its owner
  !> alone, so the sum over ranks is that owner's value. status 3 with a message when an element
  !> turned inside out or the solution became NaN.
  subroutine write_record(s, rf, status, message)
    type(solver_t), intent(inout) :: s
    type(results_file_t), intent(inout) :: rf
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    ! the scalar histories by their schema ids, two checks, the tracked nodes' values, then the
    ! per-part energies (kinetic, internal, hourglass, plastic work), each contact definition's force
    ! and each rigid wall's
    integer, parameter :: inverted_at = n_history_scalars + 1, nan_at = n_history_scalars + 2
    real(wp) :: sums(nan_at + 6 * s%control%n_tracked + 4 * s%n_parts + 3 * s%n_contacts + 3 * s%n_walls + 6)
    integer :: bad, bad_total, k, j, parts_at, walls_at, reaction_at
    real(wp) :: walls(3, s%n_walls)
    associate (ns => s%nodes)
      sums(history_kinetic_energy) = kinetic_energy(ns%n, ns%mass, ns%inertia, ns%v_old, ns%w_old, ns%v, ns%w, &
                                                    ns%weight)
      sums(history_internal_energy) = sum(s%elements%e_internal)
      sums(history_hourglass_energy) = sum(s%elements%e_hourglass)
      ! every rank computes the same contact, so rank 0 alone reports it
      sums(history_contact_energy) = merge(s%contact%c%energy, 0.0_wp, s%rank == 0)
      sums(history_external_work) = s%external_work - s%damping_work
      sums(history_contact_penetration) = merge(s%contact%c%max_penetration, 0.0_wp, s%rank == 0)
      ! the step from this record on and the element that sets it: the same on every rank
      sums(history_dt) = merge(s%clock%dt, 0.0_wp, s%rank == 0)
      sums(history_dt_stable) = merge(s%clock%dt_stable, 0.0_wp, s%rank == 0)
      sums(history_dt_element) = merge(real(s%clock%controlling, wp), 0.0_wp, s%rank == 0)
      sums(history_eroded_elements) = real(eroded_elements(s), wp)
      ! the same on every rank: rank 0 reports it
      sums(history_failed_welds) = merge(real(failed_welds(s), wp), 0.0_wp, s%rank == 0)
      sums(history_failed_ties) = 0.0_wp   ! (tie_failures: the same on every rank)
      if (s%has_contact .and. s%rank == 0) sums(history_failed_ties) = real(size(s%contact%c%failed_ties), wp)
      sums(inverted_at) = real(s%elements%inverted, wp)
      sums(nan_at) = merge(1.0_wp, 0.0_wp, any(ns%v /= ns%v) .or. any(ns%f_int /= ns%f_int))
      parts_at = nan_at + 6 * s%control%n_tracked
      sums(parts_at + 1:parts_at + s%n_parts) = kinetic_energy_by_part(ns%n, ns%mass, ns%inertia, ns%v_old, &
                                                  ns%w_old, ns%v, ns%w, ns%weight, s%node_part, s%n_parts)
      call part_energies(s, sums(parts_at + s%n_parts + 1:parts_at + 4 * s%n_parts))
      sums(parts_at + 4 * s%n_parts + 1:) = 0.0_wp
      walls_at = parts_at + 4 * s%n_parts + 3 * s%n_contacts
      if (s%has_contact .and. s%rank == 0) &
        sums(parts_at + 4 * s%n_parts + 1:walls_at) = reshape(s%contact%c%definition_force, [3 * s%n_contacts])
      call wall_forces(s, walls)   ! the same on every rank: rank 0 reports them
      reaction_at = walls_at + 3 * s%n_walls
      if (s%rank == 0) sums(walls_at + 1:reaction_at) = reshape(walls, [3 * s%n_walls])
      call constraint_reaction(s)   ! the same on every rank: rank 0 reports it
      if (s%rank == 0) sums(reaction_at + 1:reaction_at + 6) = s%reaction
      s%tracked_out = 0.0_wp
      do k = 1, s%control%n_tracked
        j = s%control%tracked_local(k)
        if (j == 0) cycle
        s%tracked_out(1:3, k) = ns%x(:, j) - ns%x0(:, j)
        s%tracked_out(4:6, k) = 0.5_wp * (ns%v(:, j) + ns%v_old(:, j))
      end do
    end associate
    sums(nan_at + 1:parts_at) = reshape(s%tracked_out, [6 * s%control%n_tracked])
    call sum_to_root(s%halo, sums)
    s%tracked_out = reshape(sums(nan_at + 1:parts_at), [6, s%control%n_tracked])
    call results_write_history(rf, s%clock%time, sums(1:n_history_scalars), s%tracked_out(1:3, :), &
                               s%tracked_out(4:6, :), sums(parts_at + 1:))
    status = status_ok
    message = ''
    bad = 0
    if (s%rank == 0) then
      if (energy_error(s, sums) > s%control%energy_error_limit .and. s%control%energy_error_limit > 0.0_wp) bad = 3
      if (sums(inverted_at) > 0.0_wp) bad = 1
      if (sums(nan_at) > 0.0_wp .or. sums(history_kinetic_energy) /= sums(history_kinetic_energy)) bad = 2
    end if
    call MPI_Allreduce(bad, bad_total, 1, MPI_INTEGER, MPI_MAX, s%halo%comm)
    if (bad_total == 3) then
      status = status_numerical
      s%energy_stop = .true.
      write (message, '(a,es10.3,a,es10.3,a,i0,a,es12.5,a)') 'the energy balance error reached ', &
        energy_error(s, sums), ' (over /control energy_error_limit = ', s%control%energy_error_limit, &
        ') by cycle ', s%clock%cycles, ', time ', s%clock%time, ' s; see the energies in the history '// &
        '(hourglass, contact and external work) for where it went, then reduce the time step or refine the mesh'
    else if (bad_total == 1) then
      status = status_numerical
      write (message, '(a,i0,a,es12.5,a)') 'an element turned inside out (zero or negative area) by cycle ', &
        s%clock%cycles, ', time ', s%clock%time, ' s; reduce the time step or the loading, or refine the mesh'
    else if (bad_total == 2) then
      status = status_numerical
      write (message, '(a,i0,a,es12.5,a)') 'the solution became NaN by cycle ', s%clock%cycles, ', time ', &
        s%clock%time, ' s; the run is unstable (time step too large or a bad material constant)'
    end if
  end subroutine write_record

  !> How many of this rank's elements are eroded (element_erosion).
  integer function eroded_elements(s) result(count)
    type(solver_t), intent(in) :: s
    integer :: g
    count = 0
    do g = 1, s%dom%n_groups
      associate (props => s%props(s%dom%group_part(g)))
        count = count + eroded_count(s%dom%group_count(g), s%elements%groups(g)%eps_p, props%failure_strain, &
                                     props%integration_points, props%failure_layers)
      end associate
    end do
  end function eroded_elements

  !> How many welds (rigid bodies of the nodal effects) have let their nodes go so far.
  integer function failed_welds(s) result(count)
    type(solver_t), intent(in) :: s
    integer :: k
    count = 0
    do k = 1, size(s%nodal_effects)
      count = count + s%nodal_effects(k)%effect%failures()
    end do
  end function failed_welds

  !> Each rigid wall's force on the model in the last step, (3, n_walls): the exact sums of the
  !> members that report forces (history_sums) added over the ranks as integers, so the value is
  !> the same on every rank and on any layout. Collective when the model has walls.
  subroutine wall_forces(s, forces)
    type(solver_t), intent(inout) :: s
    real(wp), intent(out) :: forces(:, :)
    integer(i8), allocatable :: sums(:, :, :)
    integer :: k, w, i, n_ranks
    forces = 0.0_wp
    if (s%n_walls == 0) return
    allocate (sums(exact_width, 3, 0))
    do k = 1, size(s%nodal_effects)
      sums = s%nodal_effects(k)%effect%history_sums()
      if (size(sums, 3) > 0) exit
    end do
    if (size(sums, 3) /= s%n_walls) return   ! the walls were switched off
    do w = 1, s%n_walls
      do i = 1, 3
        call exact_normalise(sums(:, i, w))
      end do
    end do
    call MPI_Comm_size(s%halo%comm, n_ranks)
    if (n_ranks > 1) call MPI_Allreduce(MPI_IN_PLACE, sums, size(sums), MPI_INTEGER8, MPI_SUM, s%halo%comm)
    do w = 1, s%n_walls
      do i = 1, 3
        forces(i, w) = exact_value(sums(:, i, w))
      end do
    end do
  end subroutine wall_forces

  !> The resultant force of the constraints in the velocity update before this record and its
  !> moment about the origin (s%reaction: time_integration's add_constraint_reactions over the
  !> owned nodes), exact sums added over the ranks as integers, so it is the same on every rank and
  !> on any layout. Collective.
  subroutine constraint_reaction(s)
    type(solver_t), intent(inout) :: s
    integer(i8) :: acc(exact_width, 6)
    integer :: k
    acc = 0
    associate (ns => s%nodes)
      call add_constraint_reactions(ns%n, half_step(s%clock), s%control%mass_damping, ns%x, ns%mass, ns%inertia, &
                                    ns%fixed, ns%f_int, ns%f_ext, s%v_free, ns%v, s%w_free, ns%w, ns%weight, acc)
    end associate
    do k = 1, 6
      call exact_normalise(acc(:, k))
    end do
    if (s%n_ranks > 1) call MPI_Allreduce(MPI_IN_PLACE, acc, size(acc), MPI_INTEGER8, MPI_SUM, s%halo%comm)
    do k = 1, 6
      s%reaction(k) = exact_value(acc(:, k))
    end do
  end subroutine constraint_reaction

  !> This rank's internal energy, hourglass energy and plastic work of each part, in turn (n_parts
  !> each). The plastic work of an element: its current area times thickness times the
  !> through-thickness mean of the material's dissipated work per unit volume (a truss: A L times
  !> that of its one point). The elements' terms
  !> are computed on the threads (a material call per element) and summed in element order, so
  !> the sums are the same for any number of threads.
  subroutine part_energies(s, energies)
    type(solver_t), intent(inout) :: s
    real(wp), intent(out) :: energies(:)
    integer, parameter :: most = 4 * max_integration_points   !< stored points: a fully integrated part's 4 in-plane
    real(wp) :: zeta(max_integration_points), wgt(most), x(3, 4), area
    real(wp) :: eps_p(group_size, most), work(group_size, most)
    real(wp) :: point_work(most)
    integer :: g, p, first, last, i, n, nip, np, pts, k
    np = s%n_parts
    ! one material call per group: a call per element made two temporaries each (docs/performance.md)
    !$omp parallel do schedule(static) private(p, first, last, n, nip, pts, k, zeta, wgt, i, x, area, eps_p, work, &
    !$omp point_work)
    do g = 1, s%dom%n_groups
      p = s%dom%group_part(g)
      if (.not. s%props(p)%material%has_history()) cycle
      first = s%dom%group_first(g)
      n = s%dom%group_count(g)
      last = first + n - 1
      nip = s%props(p)%integration_points
      pts = size(s%elements%groups(g)%eps_p, 2)   ! nip, or 4 nip in-plane point by in-plane point
      call thickness_rule(nip, zeta(1:nip), wgt(1:nip))
      do k = nip + 1, pts   ! each in-plane point's layers weigh their share of the element
        wgt(k) = wgt(k - nip)
      end do
      if (pts > nip) wgt(1:pts) = wgt(1:pts) / real(pts / nip, wp)
      eps_p(1:n, 1:pts) = real(s%elements%groups(g)%eps_p(1:n, 1:pts), wp)
      call s%props(p)%material%dissipated_work(eps_p(1:n, 1:pts), work(1:n, 1:pts))
      do i = 1, n
        x = s%nodes%x(:, s%dom%connectivity(:, first + i - 1))
        area = 0.5_wp * norm2(cross(x(:, 3) - x(:, 1), x(:, 4) - x(:, 2)))
        point_work(1:pts) = work(i, 1:pts)   ! contiguous: the sum's order as before this batch call
        s%element_work(first + i - 1) = area * s%props(p)%thickness * 0.5_wp * sum(wgt(1:pts) * point_work(1:pts))
        ! a truss: its volume A L times the work at its one point
        if (s%props(p)%truss) s%element_work(first + i - 1) = s%props(p)%area * norm2(x(:, 2) - x(:, 1)) * point_work(1)
      end do
    end do
    !$omp end parallel do
    energies = 0.0_wp
    do g = 1, s%dom%n_groups
      p = s%dom%group_part(g)
      first = s%dom%group_first(g)
      last = first + s%dom%group_count(g) - 1
      energies(p) = energies(p) + sum(s%elements%e_internal(first:last))
      energies(np + p) = energies(np + p) + sum(s%elements%e_hourglass(first:last))
      if (.not. s%props(p)%material%has_history()) cycle
      do i = first, last
        energies(2 * np + p) = energies(2 * np + p) + s%element_work(i)
      end do
    end do
  end subroutine part_energies

  !> Rank 0, one record: the energy balance error |E_total - E_total(first)| / the largest of KE,
  !> IE and |W_ext| so far (docs/outputs.md, energy report; the first record of this process is
  !> the reference, so a restart starts a new one).
  real(wp) function energy_error(s, sums) result(error)
    type(solver_t), intent(inout) :: s
    real(wp), intent(in) :: sums(:)
    real(wp) :: total
    total = sums(history_kinetic_energy) + sums(history_internal_energy) + sums(history_hourglass_energy) &
            + sums(history_contact_energy) - sums(history_external_work)
    if (.not. s%have_energy_first) then
      s%energy_first = total
      s%have_energy_first = .true.
    end if
    s%energy_scale = max(s%energy_scale, sums(history_kinetic_energy), sums(history_internal_energy), &
                         abs(sums(history_external_work)))
    error = 0.0_wp
    if (s%energy_scale > 0.0_wp) error = abs(total - s%energy_first) / s%energy_scale
  end function energy_error

  !> Every rank writes its owned nodes and its elements into the frame (collective), in
  !> results_write_frame's layouts.
  subroutine write_frame(s, rf)
    type(solver_t), intent(inout) :: s
    type(results_file_t), intent(inout) :: rf
    integer :: g, n, first, last, nip, k, j, part
    real(wp) :: membrane(group_size, 3), von_mises(group_size), plastic(group_size), h
    real(wp) :: layers(stress_components, n_layers, group_size), volume(group_size)
    real(wp) :: x0(group_size, 3, 4), x(group_size, 3, 4), q(group_size, 4, 4), surface(3, 2, group_size)
    real(ek) :: mean_stress(group_size, stress_components, max_integration_points)
    real(ek) :: most_eps_p(group_size, max_integration_points)
    real(wp), allocatable :: contact_force(:, :)
    ! threads share the frame's arithmetic; the writes that follow are collective, one call
    !$omp parallel do schedule(static) private(n, first, last, nip, membrane, von_mises, plastic, layers, volume, x0, x, &
    !$omp mean_stress, most_eps_p, q, surface, part)
    do g = 1, s%dom%n_groups
      n = s%dom%group_count(g)
      first = s%dom%group_first(g)
      last = first + n - 1
      nip = s%props(s%dom%group_part(g))%integration_points
      if (size(s%elements%groups(g)%eps_p, 2) > nip) then   ! a fully integrated part: 4 in-plane points
        call in_plane_means(n, nip, s%elements%groups(g)%stress, s%elements%groups(g)%eps_p, &
                            mean_stress(1:n, :, 1:nip), most_eps_p(1:n, 1:nip))
        call blt_element_results(n, nip, mean_stress(1:n, :, 1:nip), most_eps_p(1:n, 1:nip), &
                                 membrane(1:n, :), von_mises(1:n), plastic(1:n))
        call layer_stresses(n, nip, mean_stress(1:n, :, 1:nip), layers(:, :, 1:n))
      else
        call blt_element_results(n, nip, s%elements%groups(g)%stress, s%elements%groups(g)%eps_p, &
                                 membrane(1:n, :), von_mises(1:n), plastic(1:n))
        call layer_stresses(n, nip, s%elements%groups(g)%stress, layers(:, :, 1:n))
      end if
      s%element_out(1:3, first:last) = transpose(membrane(1:n, :))
      s%element_out(4, first:last) = von_mises(1:n)
      s%element_out(5, first:last) = plastic(1:n)
      s%element_out(6:20, first:last) = reshape(layers(:, :, 1:n), [stress_components * n_layers, n])
      call gather_group(n, first, s%dom%connectivity, s%nodes%x0, x0(1:n, :, :))
      call gather_group(n, first, s%dom%connectivity, s%nodes%x, x(1:n, :, :))
      call membrane_green_strain(n, x0(1:n, :, :), x(1:n, :, :), s%element_out(21:23, first:last))
      if (s%props(s%dom%group_part(g))%truss) then   ! no bending: both surfaces strain as the axis
        s%element_out(25:27, first:last) = s%element_out(21:23, first:last)
        s%element_out(28:30, first:last) = s%element_out(21:23, first:last)
      else
        call gather_group(n, first, s%dom%connectivity, s%nodes%q, q(1:n, :, :))
        call surface_strains(n, x0(1:n, :, :), x(1:n, :, :), q(1:n, :, :), s%props(s%dom%group_part(g))%thickness, &
                             s%element_out(21:23, first:last), surface(:, :, 1:n))
        s%element_out(25:30, first:last) = reshape(surface(:, :, 1:n), [6, n])
      end if
      call initial_volumes(n, x0(1:n, :, :), s%props(s%dom%group_part(g))%thickness, volume(1:n))
      s%element_out(24, first:last) = s%elements%e_internal(first:last) / volume(1:n)
      part = s%dom%group_part(g)
      if (s%props(part)%rigid .or. s%props(part)%truss) then   ! a rigid body's shells, a truss's nominal diameter: t0
        s%element_out(31, first:last) = s%props(part)%thickness
      else if (s%props(part)%thickness_update) then   ! the thickness the element's forces use
        s%element_out(31, first:last) = real(s%elements%groups(g)%thickness(1:n), wp)
      else   ! from the middle layer's sxx + syy
        call current_thicknesses(n, x0(1:n, :, :), x(1:n, :, :), s%props(part)%thickness, s%props(part)%young, &
                                 s%props(part)%poisson, layers(1, 2, 1:n) + layers(2, 2, 1:n), &
                                 s%element_out(31, first:last))
      end if
    end do
    !$omp end parallel do
    allocate (contact_force(3, s%nodes%n), source=0.0_wp)
    if (s%has_contact) call contact_add_nodal_forces(s%contact%c, contact_force)
    h = half_step(s%clock)
    !$omp parallel do schedule(static) private(j)
    do k = 1, size(s%halo%owned_local)
      j = s%halo%owned_local(k)
      s%node_out(1:3, k) = s%nodes%x(:, j) - s%nodes%x0(:, j)
      s%node_out(4:6, k) = 0.5_wp * (s%nodes%v(:, j) + s%nodes%v_old(:, j))
      s%node_out(7:9, k) = 0.0_wp
      if (h > 0.0_wp) s%node_out(7:9, k) = (s%nodes%v(:, j) - s%nodes%v_old(:, j)) / h
      s%node_out(10:12, k) = contact_force(:, j)
    end do
    !$omp end parallel do
    call results_write_frame(rf, s%clock%time, s%node_out, s%element_out)
  end subroutine write_frame

  !> A progress line from rank 0 every progress_interval of wall time.
  subroutine write_progress(s)
    type(solver_t), intent(inout) :: s
    if (s%rank /= 0) return
    if (wall_clock() - s%last_progress < s%control%progress_interval) return
    s%last_progress = wall_clock()
    write (*, '(a,i0,a,es13.6,a,es11.4,a,es11.4,a,f0.3)') 'PARADYN-PROGRESS cycle=', s%clock%cycles, &
      ' time=', s%clock%time, ' dt=', s%clock%dt, ' end_time=', s%clock%end_time, ' wall_s=', &
      s%last_progress - s%wall_start
    flush (6)
  end subroutine write_progress

  !> One line per rank for the log: the load balance behind the communication phase.
  subroutine write_phase_line(s)
    type(solver_t), intent(in) :: s
    write (*, '(a,i0,5(a,f0.4))') 'PARADYN-PHASES rank=', s%rank, ' elements_s=', s%timers%elements, &
      ' contact_s=', s%timers%contact, ' communication_s=', s%timers%communication, ' output_s=', &
      s%timers%output, ' nodes_s=', s%timers%nodes
    flush (6)
  end subroutine write_phase_line

  !> The /run attributes of where the solver stands. They are written collectively and must
  !> agree: every rank takes rank 0's timings.
  function run_record(s) result(run)
    type(solver_t), intent(in) :: s
    type(run_record_t) :: run
    real(wp) :: t(10)
    run%cycles = s%clock%cycles
    run%ranks = s%n_ranks
    run%threads = s%threads
    run%elements = s%control%n_elements
    run%nodes = s%control%n_nodes
    run%dt_s = s%clock%dt
    run%dt_stable_s = s%clock%dt_stable
    run%dt_first_s = s%clock%dt_first
    run%dt_stable_min_s = merge(s%dt_min, s%clock%dt_stable, s%dt_max > 0.0_wp)
    run%dt_stable_max_s = merge(s%dt_max, s%clock%dt_stable, s%dt_max > 0.0_wp)
    run%added_mass_kg = s%added_mass
    run%model_mass_kg = s%model_mass
    run%part_added_mass_kg = s%added_mass_part
    run%wall_s = wall_clock() - s%wall_start
    run%element_cycles_per_s = real(s%control%n_elements, wp) * (s%clock%cycles - s%clock%first_cycle) &
                               / max(run%wall_s, 1.0e-12_wp)
    run%load_imbalance = load_imbalance(s%halo%comm, s%timers%elements + s%timers%contact, s%n_ranks)
    call traffic_per_step(s, run)
    t = [run%wall_s, run%element_cycles_per_s, s%timers%elements, s%timers%contact, s%timers%communication, &
         s%timers%output, max(run%wall_s - (s%timers%elements + s%timers%contact + s%timers%communication &
                                            + s%timers%output), 0.0_wp), &
         s%contact%c%time_sort, s%contact%c%time_search, s%contact%c%time_force]
    call MPI_Bcast(t, size(t), MPI_DOUBLE_PRECISION, 0, s%halo%comm)
    run%precision = s%control%precision
    run%effects = s%effects
    run%effects%seconds(effect_time_integration) = run%effects%seconds(effect_time_integration) + s%timers%nodes
    ! rank 0's counts too: a member that holds nothing on a rank may skip there (attributes must agree)
    call MPI_Bcast(run%effects%seconds, size(run%effects%seconds), MPI_DOUBLE_PRECISION, 0, s%halo%comm)
    call MPI_Bcast(run%effects%active, size(run%effects%active), MPI_INTEGER8, 0, s%halo%comm)
    call MPI_Bcast(run%effects%skipped, size(run%effects%skipped), MPI_INTEGER8, 0, s%halo%comm)
    if (s%has_contact) then   ! the contact state, and so its counters, are the same on every rank
      run%pair_parts = int(reshape(s%control%contact_pairs - 1, [size(s%control%contact_pairs)]), i8)
      run%pair_active_cycles = s%contact%c%pair_active_cycles
      run%pair_skipped_cycles = s%contact%c%pair_skipped_cycles
    end if
    run%wall_s = t(1)
    run%element_cycles_per_s = t(2)
    run%phase_elements_s = t(3)
    run%phase_contact_s = t(4)
    run%phase_communication_s = t(5)
    run%phase_output_s = t(6)
    run%phase_other_s = t(7)
    run%phase_contact_sort_s = t(8)
    run%phase_contact_search_s = t(9)
    run%phase_contact_force_s = t(10)
  end function run_record

  !> The busiest rank's element and contact time over the mean of all ranks (1 = balanced).
  !> The messages and bytes of the corner exchange, the contact's sharing and the step's reductions
  !> (traffic_counter) per cycle of this call, the largest of any rank.
  subroutine traffic_per_step(s, run)
    type(solver_t), intent(in) :: s
    type(run_record_t), intent(inout) :: run
    real(wp) :: mine(3), most(3)
    mine = real([s%halo%traffic%messages, s%halo%traffic%bytes_sent, s%halo%traffic%bytes_received], wp)
    if (s%has_contact) mine = mine + real([s%contact%traffic%messages, s%contact%traffic%bytes_sent, &
                                           s%contact%traffic%bytes_received], wp)
    mine = mine / real(max(s%clock%cycles - s%clock%first_cycle, 1_i8), wp)
    call MPI_Allreduce(mine, most, 3, MPI_DOUBLE_PRECISION, MPI_MAX, s%halo%comm)
    run%messages_per_step = most(1)
    run%bytes_sent_per_step = most(2)
    run%bytes_received_per_step = most(3)
  end subroutine traffic_per_step

  real(wp) function load_imbalance(comm, busy, n_ranks)
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: busy
    integer, intent(in) :: n_ranks
    real(wp) :: most, total
    call MPI_Allreduce(busy, most, 1, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
    call MPI_Allreduce(busy, total, 1, MPI_DOUBLE_PRECISION, MPI_SUM, comm)
    load_imbalance = most / max(total / n_ranks, tiny(1.0_wp))
  end function load_imbalance

end module solver_output
