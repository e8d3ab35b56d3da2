! Thin explicit-shape wrappers that expose the engine's pure kernels to Python through f2py
! (module paradyn._kernels; the material kernels' are in material_f2py.f90). f2py cannot pass
! derived types, so properties come as scalars.

subroutine thickness_points(n, zeta, weight)
  use paradyn_kinds, only: wp
  use shell_section, only: thickness_rule
  implicit none
  integer, intent(in) :: n
  real(wp), intent(out) :: zeta(n), weight(n)
  call thickness_rule(n, zeta, weight)
end subroutine thickness_points

subroutine blt_forces(n, nip, x, v, w, thickness, density, young, poisson, yield_stress, tangent, &
                      beta, hourglass_coefficient, model, dt, stress, back, eps_p, hourglass, force, &
                      e_internal, e_hourglass, inverted, hourglass_form, warping_correction, failure_strain)
  use paradyn_kinds, only: wp
  use shell_section, only: shell_properties_t
  use shell_blt, only: blt_internal_forces
  use material_factory, only: material_from_deck
  use deck_fields, only: deck_fields_t
  implicit none
  integer, intent(in) :: n, nip, model
  integer, intent(in) :: hourglass_form  ! 1 viscous, 2 stiffness, 3 physical
  !f2py integer optional, intent(in) :: hourglass_form = 2
  integer, intent(in) :: warping_correction  ! 1 on, 0 off
  !f2py integer optional, intent(in) :: warping_correction = 1
  real(wp), intent(in) :: failure_strain  ! 0: no point fails (element_erosion)
  !f2py double precision optional, intent(in) :: failure_strain = 0.0
  real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
  real(wp), intent(in) :: thickness, density, young, poisson, yield_stress, tangent, beta
  real(wp), intent(in) :: hourglass_coefficient, dt
  real(wp), intent(inout) :: stress(n, 5, nip), back(n, 3, nip), eps_p(n, nip), hourglass(n, 10)
  real(wp), intent(out) :: force(n, 6, 4)
  real(wp), intent(inout) :: e_internal(n), e_hourglass(n)
  integer, intent(out) :: inverted
  type(shell_properties_t) :: props
  type(deck_fields_t) :: material   ! a deck of this one material
  real(wp) :: dt_element(n), corner_force(6, 4, n)
  real(wp), allocatable :: state(:, :, :)   ! the material member's own state (none for elastic and J2)
  props = shell_properties_t(thickness=thickness, density=density, young=young, poisson=poisson, &
                             hourglass_coefficient=hourglass_coefficient, integration_points=nip, &
                             hourglass_form=hourglass_form, warping_correction=warping_correction /= 0, &
                             failure_strain=failure_strain)
  material = deck_fields_t(material_model=[model], young=[young], poisson=[poisson], yield_stress=[yield_stress], &
                           tangent_modulus=[tangent], hardening_mixing=[beta])
  call material_from_deck(material, 1, props%material)
  if (props%material%has_history()) props%hourglass_yield = yield_stress
  inverted = 0
  allocate (state(n, props%material%state_width(), nip), source=0.0_wp)
  call blt_internal_forces(n, x, v, w, props, dt, stress, back, eps_p, state, hourglass, corner_force, &
                           e_internal, e_hourglass, inverted, dt_element)
  force = reshape(corner_force, [n, 6, 4], order=[2, 3, 1])   ! (component, corner, element) -> (i, c, k)
end subroutine blt_forces

subroutine blt_mass(n, x, thickness, density, node_mass, node_inertia)
  use paradyn_kinds, only: wp
  use shell_measures, only: blt_lumped_mass
  use paradyn_schema, only: rotary_inertia_scaled
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x(n, 3, 4), thickness, density
  real(wp), intent(out) :: node_mass(n), node_inertia(n)
  call blt_lumped_mass(n, x, thickness, density, rotary_inertia_scaled, node_mass, node_inertia)
end subroutine blt_mass

subroutine blt_time_step(n, x, thickness, density, young, poisson, dt_element)
  use paradyn_kinds, only: wp
  use shell_section, only: shell_properties_t
  use shell_measures, only: blt_stable_time_step
  use material_factory, only: material_from_deck
  use deck_fields, only: deck_fields_t
  use paradyn_schema, only: material_elastic
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x(n, 3, 4), thickness, density, young, poisson
  real(wp), intent(out) :: dt_element(n)
  type(shell_properties_t) :: props
  props%thickness = thickness
  props%density = density
  props%young = young
  props%poisson = poisson
  ! the step follows the material's wave speed: an elastic material of these constants
  call material_from_deck(deck_fields_t(material_model=[material_elastic], young=[young], poisson=[poisson]), 1, &
                          props%material)
  call blt_stable_time_step(n, x, props, dt_element)
end subroutine blt_time_step

subroutine block_partition(n_elements, n_ranks, owner)
  use domain_decomposition, only: block_owner
  implicit none
  integer, intent(in) :: n_elements, n_ranks
  integer, intent(out) :: owner(n_elements)
  integer :: e
  do e = 1, n_elements
    owner(e) = block_owner(e, n_elements, n_ranks)
  end do
end subroutine block_partition

! Recursive coordinate bisection of element centroids (3, n_elements); owner is 0-based.
subroutine rcb_partition(n_elements, centroids, n_ranks, owner)
  use paradyn_kinds, only: wp
  use domain_decomposition, only: rcb_partition_kernel => rcb_partition
  implicit none
  integer, intent(in) :: n_elements, n_ranks
  real(wp), intent(in) :: centroids(3, n_elements)
  integer, intent(out) :: owner(n_elements)
  !f2py integer intent(in), required :: n_elements
  call rcb_partition_kernel(n_elements, centroids, n_ranks, owner)
end subroutine rcb_partition

! Owners as the engine computes them for a deck: method 1 blocks, 2 rcb (centroids of the elements).
! connectivity: 1-based node ids.
subroutine partition_elements(method, n_nodes, n_elements, coordinates, connectivity, n_ranks, owner)
  use paradyn_kinds, only: wp
  use domain_decomposition, only: partition_kernel => partition_elements
  implicit none
  integer, intent(in) :: method, n_nodes, n_elements, n_ranks
  real(wp), intent(in) :: coordinates(3, n_nodes)
  integer, intent(in) :: connectivity(4, n_elements)
  integer, intent(out) :: owner(n_elements)
  call partition_kernel(method, coordinates, connectivity, n_ranks, owner)
end subroutine partition_elements

! Every rank's domain from decompose for one owner array, and the corner exchange and fixed-order
! nodal sum of the engine played out between them without MPI: rank q sends corner(:, send_slot)
! of neighbour k to that neighbour, which stores it at its recv_slot for q.
! values(:, c, e): the value of corner c of global element e (1-based connectivity, 0-based owner).
! Returns, per global element, how many ranks hold it as a local element and which one; per global
! node, how many ranks hold it and how many claim to own it; each rank's neighbour count and send
! size; node_sum(:, n, r + 1), the nodal sum of rank r (0 where r does not hold node n); status 0,
! or 1 if a send list and the matching receive list differ in length or a neighbour is one-sided.
subroutine decomposition_check(n_nodes, n_elements, connectivity, element_part, owner, n_ranks, width, values, &
                               element_holders, element_rank, node_holders, node_owners, n_neighbours, &
                               n_sent, node_sum, status)
  use paradyn_kinds, only: wp
  use domain_decomposition, only: domain_t, decompose
  use nodal_assembly, only: assemble_nodes
  implicit none
  integer, intent(in) :: n_nodes, n_elements, n_ranks, width
  integer, intent(in) :: connectivity(4, n_elements), element_part(n_elements), owner(n_elements)
  real(wp), intent(in) :: values(width, 4, n_elements)
  integer, intent(out) :: element_holders(n_elements), element_rank(n_elements)
  integer, intent(out) :: node_holders(n_nodes), node_owners(n_nodes), n_neighbours(n_ranks), n_sent(n_ranks)
  real(wp), intent(out) :: node_sum(width, n_nodes, n_ranks)
  integer, intent(out) :: status
  type(domain_t), allocatable :: dom(:)
  real(wp), allocatable :: corner(:, :), nodal(:, :)
  integer, allocatable :: at(:)   ! each rank's corner array is corner(:, at(r) + 1 : at(r + 1))
  integer :: r, q, k, kq, le, first, last, first_q

  status = 0
  element_holders = 0
  element_rank = -1
  node_holders = 0
  node_owners = 0
  node_sum = 0.0_wp
  allocate (dom(0:n_ranks - 1), at(0:n_ranks))
  at(0) = 0
  do r = 0, n_ranks - 1
    call decompose(n_nodes, n_elements, connectivity, element_part, owner, n_ranks, r, dom(r))
    n_neighbours(r + 1) = dom(r)%n_neighbours
    n_sent(r + 1) = size(dom(r)%send_slot)
    element_holders(dom(r)%elements) = element_holders(dom(r)%elements) + 1
    element_rank(dom(r)%elements) = r
    node_holders(dom(r)%nodes) = node_holders(dom(r)%nodes) + 1
    node_owners(dom(r)%nodes) = node_owners(dom(r)%nodes) + dom(r)%node_owned
    at(r + 1) = at(r) + 4 * dom(r)%n_elements + dom(r)%n_ghost_slots
  end do
  allocate (corner(width, at(n_ranks)), source=0.0_wp)
  do r = 0, n_ranks - 1
    do le = 1, dom(r)%n_elements
      corner(:, at(r) + 4 * le - 3:at(r) + 4 * le) = values(:, :, dom(r)%elements(le))
    end do
  end do
  ! the exchange: what q sends to r lands in r's receive slots for q
  do r = 0, n_ranks - 1
    do k = 1, dom(r)%n_neighbours
      q = dom(r)%neighbour(k)
      kq = findloc(dom(q)%neighbour, r, dim=1)
      first = dom(r)%recv_start(k)
      last = dom(r)%recv_start(k + 1) - 1
      if (kq == 0) then
        status = 1
        return
      end if
      first_q = dom(q)%send_start(kq)
      if (dom(q)%send_start(kq + 1) - first_q /= last - first + 1) then
        status = 1
        return
      end if
      corner(:, at(r) + dom(r)%recv_slot(first:last)) = &
        corner(:, at(q) + dom(q)%send_slot(first_q:first_q + last - first))
    end do
  end do
  do r = 0, n_ranks - 1
    allocate (nodal(width, dom(r)%n_nodes))
    call assemble_nodes(dom(r)%n_nodes, dom(r)%assembly_start, dom(r)%assembly_slot, &
                        corner(:, at(r) + 1:at(r + 1)), nodal)
    node_sum(:, dom(r)%nodes, r + 1) = nodal
    deallocate (nodal)
  end do
end subroutine decomposition_check

! ------------------------------------------------------------------------------------------------
! Contact kernels (contact_buckets, contact_search, segment_projection, contact_penalty). Node and
! segment numbers are 1-based.

! Bucket sort of n_master master nodes and the nearest master node of each of n_points points
! (build and query in one call; 0 = none). n_buckets: buckets per axis of the grid that was built.
! max_distance > 0 limits the search radius (default 0: unlimited).
subroutine contact_nearest_nodes(n_master, master, bucket_size, n_points, points, nearest, n_buckets, &
                                 max_distance)
  use paradyn_kinds, only: wp
  use contact_buckets, only: bucket_grid_t, bucket_grid_build, nearest_master_nodes
  implicit none
  integer, intent(in) :: n_master, n_points
  real(wp), intent(in) :: master(3, n_master), bucket_size, points(3, n_points)
  integer, intent(out) :: nearest(n_points), n_buckets(3)
  real(wp), intent(in) :: max_distance
  !f2py real(wp) optional, intent(in) :: max_distance = 0.0
  type(bucket_grid_t) :: grid
  call bucket_grid_build(n_master, master, bucket_size, grid)
  if (max_distance > 0.0_wp) then
    call nearest_master_nodes(grid, master, n_points, points, nearest, max_distance)
  else
    call nearest_master_nodes(grid, master, n_points, points, nearest)
  end if
  n_buckets = grid%n_buckets
end subroutine contact_nearest_nodes

! One slave walking through points(:, 1:n_points): its nearest master node within max_distance at
! each point (0 = none) through its list of nearby masters (nearest_cache, list kept while the slave
! stays within margin), and listed(k) = 1 where the answer came from a list made at an earlier point.
! Before point rebuild_at (0: never) the masters move by shift and the grid is built again.
subroutine contact_nearest_listed(n_master, master, bucket_size, n_points, points, max_distance, margin, &
                                  rebuild_at, shift, nearest, listed)
  use paradyn_kinds, only: wp
  use contact_buckets, only: bucket_grid_t, bucket_grid_build
  use nearest_cache, only: near_lists_t, near_lists_setup, nearest_master_listed, near_list_room
  implicit none
  integer, intent(in) :: n_master, n_points, rebuild_at
  real(wp), intent(in) :: master(3, n_master), bucket_size, points(3, n_points), max_distance, margin, shift(3)
  integer, intent(out) :: nearest(n_points), listed(n_points)
  type(bucket_grid_t) :: grid
  type(near_lists_t) :: lists
  real(wp) :: coords(3, n_master)
  integer :: k, built
  coords = master
  call bucket_grid_build(n_master, coords, bucket_size, grid)
  call near_lists_setup(1, lists)
  do k = 1, n_points
    if (k == rebuild_at) then
      coords = master + spread(shift, 2, n_master)
      call bucket_grid_build(n_master, coords, bucket_size, grid)
    end if
    built = lists%built(1)
    listed(k) = 0
    if (built == grid%builds .and. lists%count(1) <= near_list_room .and. &
        sum((points(:, k) - lists%centre(:, 1))**2) <= margin**2) listed(k) = 1
    call nearest_master_listed(lists, 1, grid, coords, points(:, k), max_distance, margin, nearest(k))
  end do
end subroutine contact_nearest_listed

subroutine contact_closest_point(xseg, p, xi, eta, xc, normal)
  use paradyn_kinds, only: wp
  use segment_projection, only: closest_point_on_segment
  implicit none
  real(wp), intent(in) :: xseg(3, 4), p(3)
  real(wp), intent(out) :: xi, eta, xc(3), normal(3)
  call closest_point_on_segment(xseg, p, xi, eta, xc, normal)
end subroutine contact_closest_point

subroutine contact_node_segments(n_nodes, n_segments, segment_nodes, segment_start, segment_list, n_entries)
  use contact_search, only: node_segment_map
  implicit none
  integer, intent(in) :: n_nodes, n_segments
  integer, intent(in) :: segment_nodes(4, n_segments)
  integer, intent(out) :: segment_start(n_nodes + 1), segment_list(4 * n_segments), n_entries
  call node_segment_map(n_nodes, n_segments, segment_nodes, segment_start, segment_list, n_entries)
end subroutine contact_node_segments

subroutine contact_segment_candidates(p, node, n_nodes, coords, n_segments, segment_nodes, segment_start, &
                                      n_list, segment_list, segment, xi, eta, xc, normal, reach)
  ! reach < 0 (the default): segment_candidates without reach (every segment around the node counts)
  use paradyn_kinds, only: wp
  use contact_search, only: segment_candidates
  implicit none
  integer, intent(in) :: node, n_nodes, n_segments, n_list
  real(wp), intent(in) :: p(3), coords(3, n_nodes)
  integer, intent(in) :: segment_nodes(4, n_segments), segment_start(n_nodes + 1), segment_list(n_list)
  integer, intent(out) :: segment
  real(wp), intent(out) :: xi, eta, xc(3), normal(3)
  real(wp), intent(in) :: reach
  !f2py real(wp) optional, intent(in) :: reach = -1.0
  if (reach >= 0.0_wp) then
    call segment_candidates(p, node, n_nodes, coords, n_segments, segment_nodes, &
                            segment_start, segment_list, segment, xi, eta, xc, normal, reach=reach)
  else
    call segment_candidates(p, node, n_nodes, coords, n_segments, segment_nodes, &
                            segment_start, segment_list, segment, xi, eta, xc, normal)
  end if
end subroutine contact_segment_candidates

! segment_candidates' clearance with the given reach: how much farther than it could touch the
! nearest segment around node lies at least (0 where a segment may touch).
subroutine contact_segment_clearance(p, node, n_nodes, coords, n_segments, segment_nodes, segment_start, &
                                     n_list, segment_list, reach, clearance)
  use paradyn_kinds, only: wp
  use contact_search, only: segment_candidates
  implicit none
  integer, intent(in) :: node, n_nodes, n_segments, n_list
  real(wp), intent(in) :: p(3), coords(3, n_nodes), reach
  integer, intent(in) :: segment_nodes(4, n_segments), segment_start(n_nodes + 1), segment_list(n_list)
  real(wp), intent(out) :: clearance
  integer :: segment
  real(wp) :: xi, eta, xc(3), normal(3)
  call segment_candidates(p, node, n_nodes, coords, n_segments, segment_nodes, &
                          segment_start, segment_list, segment, xi, eta, xc, normal, reach=reach, clearance=clearance)
end subroutine contact_segment_clearance

subroutine contact_segment_distance_bound(xseg, p, bound)
  use paradyn_kinds, only: wp
  use segment_projection, only: segment_distance_bound
  implicit none
  real(wp), intent(in) :: xseg(3, 4), p(3)
  real(wp), intent(out) :: bound
  bound = segment_distance_bound(xseg, p)
end subroutine contact_segment_distance_bound

subroutine contact_penalty_stiffness(xseg, young, poisson, scale, k)
  use paradyn_kinds, only: wp
  use contact_penalty, only: shell_penalty_stiffness
  implicit none
  real(wp), intent(in) :: xseg(3, 4), young, poisson, scale
  real(wp), intent(out) :: k
  k = shell_penalty_stiffness(xseg, young, poisson, scale)
end subroutine contact_penalty_stiffness

! Penalty (and optional friction) force between a slave node and a master segment. Friction is
! off with mu_static = mu_dynamic = 0 (the defaults). rounded_edges: 0 (default) or 1.
subroutine contact_penalty_force(p, t_slave, xseg, t_master, k, f_slave, f_master, penetration, in_contact, &
                                 v_slave, v_master, mu_static, mu_dynamic, decay, v_slip, rounded_edges)
  use paradyn_kinds, only: wp
  use contact_penalty, only: penalty_force
  implicit none
  real(wp), intent(in) :: p(3), t_slave, xseg(3, 4), t_master, k
  real(wp), intent(out) :: f_slave(3), f_master(3, 4), penetration
  integer, intent(out) :: in_contact
  real(wp), intent(in) :: v_slave(3), v_master(3, 4)
  real(wp), intent(in) :: mu_static, mu_dynamic, decay, v_slip
  integer, intent(in) :: rounded_edges
  !f2py real(wp) optional, intent(in) :: mu_static = 0.0, mu_dynamic = 0.0, decay = 0.0, v_slip = 0.0
  !f2py integer optional, intent(in) :: rounded_edges = 0
  !f2py real(wp) optional, intent(in) :: v_slave, v_master
  logical :: contact
  call penalty_force(p, t_slave, xseg, t_master, k, f_slave, f_master, penetration, contact, &
                     v_slave, v_master, mu_static, mu_dynamic, decay, v_slip, rounded_edges /= 0)
  in_contact = merge(1, 0, contact)
end subroutine contact_penalty_force

! Candidate pairs (slave, nearest master) as they arrive from all ranks, in ascending slave order
! (the first n_candidates columns of candidates; slaves are 1..n_slaves, each at most once).
subroutine contact_candidates_in_order(n_slaves, n_pairs, pairs, n_candidates, candidates)
  use contact_search, only: candidates_in_slave_order
  implicit none
  integer, intent(in) :: n_slaves, n_pairs
  integer, intent(in) :: pairs(2, n_pairs)
  integer, intent(out) :: n_candidates, candidates(2, n_slaves)
  integer :: nearest(n_slaves)
  candidates = 0
  call candidates_in_slave_order(n_slaves, n_pairs, pairs, nearest, n_candidates, candidates)
end subroutine contact_candidates_in_order

! Block first(r + 1)..last(r + 1) of the candidate list for each rank r = 0..n_ranks-1.
subroutine contact_candidate_blocks(n_candidates, n_ranks, first, last)
  use contact_search, only: candidate_block
  implicit none
  integer, intent(in) :: n_candidates, n_ranks
  integer, intent(out) :: first(n_ranks), last(n_ranks)
  integer :: r
  do r = 0, n_ranks - 1
    call candidate_block(n_candidates, n_ranks, r, first(r + 1), last(r + 1))
  end do
end subroutine contact_candidate_blocks

! The threads' work sharing (work_queues) on a loop of n_items trivial items with n_threads
! threads: times(i) counts how often item i was handed out, taken_by(i) is the thread (1-based)
! that took it. hold_first = 1 keeps thread 1 out of the loop until every other thread has run out
! of items, so that they must take thread 1's range.
subroutine share_items(n_items, n_threads, hold_first, times, taken_by)
  use work_queues, only: work_queues_t, queues_start, queues_take
  use omp_lib, only: omp_get_thread_num, omp_get_num_threads
  implicit none
  integer, intent(in) :: n_items, n_threads, hold_first
  integer, intent(out) :: times(n_items), taken_by(n_items)
  type(work_queues_t) :: queues
  integer :: me, item, emptied, finished, seen
  times = 0
  taken_by = 0
  finished = 0
  call queues_start(queues, n_items, n_threads)
  !$omp parallel num_threads(n_threads) default(shared) private(me, item, emptied, seen)
  me = omp_get_thread_num() + 1
  emptied = 0
  if (me == 1 .and. hold_first == 1) then
    do
      !$omp atomic read
      seen = finished
      if (seen == omp_get_num_threads() - 1) exit
    end do
  end if
  do
    item = queues_take(queues, me, emptied)
    if (item == 0) exit
    !$omp atomic update
    times(item) = times(item) + 1
    taken_by(item) = me
  end do
  !$omp atomic update
  finished = finished + 1
  !$omp end parallel
end subroutine share_items

! Load curves (nodal_effects/load_curves.f90): curve k (1-based) of the deck's curves at each of the times t.
subroutine load_curve_values(n_curves, n_points, first_point, time, value, k, n_t, t, y)
  use paradyn_kinds, only: wp
  use load_curves, only: load_curves_t, load_curves_from, curve_value
  implicit none
  integer, intent(in) :: n_curves, n_points, first_point(n_curves), k, n_t
  real(wp), intent(in) :: time(n_points), value(n_points), t(n_t)
  real(wp), intent(out) :: y(n_t)
  type(load_curves_t) :: c
  integer :: i
  c = load_curves_from(first_point, time, value)
  do i = 1, n_t
    y(i) = curve_value(c, k, t(i))
  end do
end subroutine load_curve_values

! Pressure on one element (nodal_effects/pressure_kernels.f90): its four corner forces at x (internal-force
! sign) under p_end, and the work since the element was at x_start under p_start.
subroutine pressure_element(x_start, x, p_start, p_end, corner, work)
  use paradyn_kinds, only: wp
  use pressure_kernels, only: pressure_corner_forces
  implicit none
  real(wp), intent(in) :: x_start(3, 4), x(3, 4), p_start, p_end
  real(wp), intent(out) :: corner(6, 4), work
  real(wp) :: f_previous(3, 1), x_sum_previous(3, 1)
  corner = 0.0_wp
  work = 0.0_wp
  call pressure_corner_forces([1], reshape([1, 2, 3, 4], [4, 1]), x_start, p_start, corner, f_previous, &
                              x_sum_previous, .false., work)
  corner = 0.0_wp
  call pressure_corner_forces([1], reshape([1, 2, 3, 4], [4, 1]), x, p_end, corner, f_previous, &
                              x_sum_previous, .true., work)
end subroutine pressure_element

! The exact sum of x (core/exact_sum) as the engine takes it over ranks: the terms dealt cyclically
! to `parts` accumulators (parts = 1: one accumulator), each normalised, the accumulators added
! limb by limb (what MPI_Allreduce with MPI_SUM does), the total rounded once to nearest.
subroutine exact_sum_split(n, x, parts, total)
  use paradyn_kinds, only: wp, i8
  use exact_sum, only: exact_width, exact_add, exact_normalise, exact_value
  implicit none
  integer, intent(in) :: n, parts
  real(wp), intent(in) :: x(n)
  real(wp), intent(out) :: total
  integer(i8) :: acc(exact_width, max(parts, 1)), whole(exact_width)
  integer :: i
  acc = 0
  do i = 1, n
    call exact_add(acc(:, mod(i - 1, max(parts, 1)) + 1), x(i))
  end do
  whole = 0
  do i = 1, max(parts, 1)
    call exact_normalise(acc(:, i))
    whole = whole + acc(:, i)
  end do
  total = exact_value(whole)
end subroutine exact_sum_split
