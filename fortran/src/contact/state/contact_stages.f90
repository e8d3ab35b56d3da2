!> The stages of a contact step after the sort, over the state of contact_interface: the global
!> search (each rank's cyclic share of the slaves finds its nearest master nodes), the candidates
!> in pass and slave order with this rank's block of them, the local search of the block (segment,
!> closest point, penalty force), the sum of the records in candidate order, and the exact sums of
!> the energy and the definitions' forces. No MPI here: the caller (contact_parallel) shares
!> candidates and records between the stages and adds the exact sums over the ranks.
module contact_stages
  use paradyn_kinds, only: wp, ip, i8
  use nearest_cache, only: nearest_master_listed
  use contact_search, only: segment_candidates, candidate_block, candidates_in_slave_order
  use contact_penalty, only: penalty_force, edge_tolerance
  use contact_pass, only: contact_pass_t, bound_segment
  use contact_laws, only: bound_force
  use tie_keys, only: tie_failed
  use edge_search, only: deepest_edge_crossing
  use edge_penalty, only: edge_edge_force, closest_points_of_edges
  use contact_interface, only: contact_t, clock_seconds
  use contact_slots, only: slot_of
  use contact_closing, only: closing_limited, touching_step, approach_step, closing_limit_step
  use exact_sum, only: exact_add, exact_value
  implicit none
  private
  public :: contact_global_search, contact_candidates, contact_local_search, contact_sum, contact_end, &
            contact_finish

  !> Below this slip speed friction falls linearly to zero (a viscous regularisation of stick
  !> that needs no history per contact; a body at rest on a slope creeps at most this fast).
  real(wp), parameter :: stick_speed = 1.0e-3_wp  ! m/s
  !> The penalty spring of a contact never exceeds this fraction of m / dt^2, m the lightest node
  !> of the slave and its segment: the contact frequency then stays below 0.63 / dt, so the
  !> contact cannot make the central-difference step unstable however stiff the penalty or light
  !> the node (docs/theory.md; LS-DYNA's soft-constraint stiffness has the same m / dt^2 form).
  real(wp), parameter :: stable_spring_fraction = 0.25_wp
  !> A slave keeps its list of nearby master nodes (nearest_cache) while it stays within this
  !> fraction of the bucket size of where the list was made. An automatic sort falls before any
  !> node has moved a tenth of the smallest bucket, so a list then lasts until the next sort.
  real(wp), parameter :: list_margin = 0.125_wp

contains

  !> The penalty spring of a contact pair: the segment's stiffness k0, at least the soft
  !> constraint's soft_scale m / (2 dt_soft^2) (LS-DYNA SOFT = 1: k = max(k0, SOFSCL k1), k1 the
  !> stiffness of a spring-mass pair whose period matches the step; dt_soft the largest step so
  !> far), never above the stable cap = stable_spring_fraction m / dt^2; m the pair's lightest
  !> node (an edge pair: its effective mass).
  pure real(wp) function spring(k0, soft_scale, m, soft_step, cap)
    real(wp), intent(in) :: k0, soft_scale, m, soft_step, cap
    if (soft_scale > 0.0_wp .and. soft_step > 0.0_wp) then
      spring = min(max(k0, 0.5_wp * soft_scale * m / soft_step**2), cap)
    else
      spring = min(k0, cap)
    end if
  end function spring

  !> Pass p runs this cycle: unless idle (contact_activity) or outside its definition's life
  !> (birth <= c%time <= death), always or every other cycle with the paper's swap.
  pure logical function contact_pass_active(c, p, cycle)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: p
    integer(i8), intent(in) :: cycle
    contact_pass_active = .not. c%passes(p)%idle .and. &
                          (c%passes(p)%every_cycle .or. modulo(cycle + c%passes(p)%swap_index, 2_i8) == 1) .and. &
                          c%time >= c%passes(p)%birth .and. c%time <= c%passes(p)%death
  end function contact_pass_active

  !> Add the records of the step (complete on this rank: the caller has shared them between
  !> ranks) to the contact forces, in candidate order (pass, then slave), the same for any layout.
  !> The records this rank counts (counted) also add their slave force to their definition's exact
  !> sum (c%sums) and their penetration to the deepest. A record's nodes that this rank does not
  !> hold (local contact: the record came for another of its nodes) take no force here.
  subroutine contact_sum(c, clock)
    type(contact_t), intent(inout) :: c
    procedure(clock_seconds) :: clock
    integer :: j, k, node, d
    real(wp) :: t0
    integer :: s
    logical :: counts
    t0 = clock()
    do j = 1, c%n_candidates
      if (c%record_nodes(1, j) == 0) cycle
      counts = .true.
      if (c%local) counts = counted(c, slot_of(c, c%record_nodes(1, j)))
      if (counts) then
        c%max_penetration = max(c%max_penetration, c%record_penetration(j))
        associate (pass => c%passes(c%candidates(3, j)))
        do k = 1, 3
          d = 1 + 3 * (pass%pair - 1) + k
          call exact_add(c%sums(:, d), pass%first_part_sign * c%record_force(k, 1, j))
          ! an edge record's slave is its first two nodes
          if (pass%edges) call exact_add(c%sums(:, d), pass%first_part_sign * c%record_force(k, 2, j))
        end do
        end associate
      end if
      do k = 1, 5
        node = c%record_nodes(k, j)
        s = slot_of(c, node)
        if (s == 0) cycle
        if (c%mark(s) /= c%stamp) then
          c%mark(s) = c%stamp
          c%n_touched = c%n_touched + 1
          c%touched(c%n_touched) = s
        end if
        c%force(:, s) = c%force(:, s) + c%record_force(:, k, j)
      end do
    end do
    c%time_force = c%time_force + clock() - t0
  end subroutine contact_sum

  !> Whether this rank adds the terms of a record (by its slave node) or of a node to the sums of
  !> the energy and the definitions: every one on one rank and in the replicated scheme, where
  !> every rank has every record; with local contact the ones of the nodes it owns, so that each
  !> term is added on exactly one rank. s: the node's slot (0: not held here).
  pure logical function counted(c, s)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: s
    counted = .true.
    if (.not. c%local) return
    counted = .false.
    if (s > 0) counted = c%own(s)
  end function counted

  !> The terms of the contact energy's step: minus the work of the mean contact force over the
  !> last step dt (the velocities are those of that step) is -dt / 2 times the sum, over the nodes
  !> touched in this step or the last (only they have a force; the lists hold slots), of
  !> v . (force_old + force). Each counted node's term goes to the exact sum c%sums(:, 1), so the sum is the same for any
  !> order, rank count and number of threads.
  subroutine contact_end(c, cycle)
    type(contact_t), intent(inout) :: c
    integer(i8), intent(in) :: cycle
    integer :: i, j
    if (cycle == 0) return
    do i = 1, c%n_touched
      j = c%touched(i)
      if (counted(c, j)) &
        call exact_add(c%sums(:, 1), dot_product(c%v(:, j), c%force_old(:, j) + c%force(:, j)))
    end do
    do i = 1, c%n_touched_old
      j = c%touched_old(i)
      if (c%mark(j) == c%stamp) cycle   ! in both lists: counted above
      if (counted(c, j)) call exact_add(c%sums(:, 1), dot_product(c%v(:, j), c%force_old(:, j)))
    end do
  end subroutine contact_end

  !> After the sums are complete (with local contact, added over the ranks): each rounded once,
  !> the contact energy advanced by -dt / 2 times the work's sum and the definitions' forces set,
  !> the same on every rank; the sums are cleared for the next step.
  subroutine contact_finish(c, cycle, dt)
    type(contact_t), intent(inout) :: c
    integer(i8), intent(in) :: cycle
    real(wp), intent(in) :: dt
    integer :: d
    if (cycle > 0) c%energy = c%energy - 0.5_wp * dt * exact_value(c%sums(:, 1))
    do d = 1, size(c%definition_force)
      c%definition_force(mod(d - 1, 3) + 1, (d - 1) / 3 + 1) = exact_value(c%sums(:, 1 + d))
    end do
    c%sums = 0
  end subroutine contact_finish

  !> Stage 1, the global search, for every pass active this cycle: this rank's share of the
  !> slaves that can be near (near_slaves; all slaves with a fixed sort interval), dealt
  !> node-wise cyclically to the ranks (the k-th to rank mod(k - 1, n_ranks)) and, one at a time,
  !> to the threads (schedule(static, 1)), as in the paper; the passes' shares run as one loop. A
  !> slave near the master box gets its nearest master node; the pairs (place in near_slaves,
  !> nearest master, pass) found are own_pairs(:, 1:n_own), by pass and ascending within one.
  subroutine contact_global_search(c, cycle, clock)
    type(contact_t), intent(inout) :: c
    integer(i8), intent(in) :: cycle
    procedure(clock_seconds) :: clock
    integer :: i, j, p, found, total, n_mine(size(c%passes)), offset(size(c%passes) + 1), rank, n_ranks
    real(wp) :: x(3), t0
    t0 = clock()
    ! local contact: near_slaves are this rank's own slaves, all searched here
    rank = merge(0, c%rank, c%local)
    n_ranks = merge(1, c%n_ranks, c%local)
    offset(1) = 0
    do p = 1, size(c%passes)
      n_mine(p) = 0
      if (contact_pass_active(c, p, cycle)) &
        n_mine(p) = max(0, (c%passes(p)%n_near - rank + n_ranks - 1) / n_ranks)
      offset(p + 1) = offset(p) + n_mine(p)
    end do
    total = offset(size(offset))
    ! cleared first, so the threads write only the few slaves near the box (writes to
    ! neighbouring slaves from different threads would fight over their cache line)
    c%nearest(1:total) = 0
    !$omp parallel do schedule(static, 1) default(shared) private(i, j, p, x, found)
    do i = 1, total
      p = pass_of(offset, i)
      associate (pass => c%passes(p))
      j = pass%near_slaves(rank + 1 + (i - offset(p) - 1) * n_ranks)
      x = c%x(:, pass%slave_at(j))
      if (pass%edges) x = 0.5_wp * (x + c%x(:, pass%slave_other_at(j)))   ! an edge: its midpoint
      if (near_box(x, pass) .and. live_slave(pass, j)) then
        if (pass%shares_nodes) then
          call nearest_master_listed(pass%near, j, pass%grid, pass%x_sorted, x, &
                                     pass%bucket_size + pass%t_slave + pass%t_master, list_margin * pass%bucket_size, &
                                     found, excluded=pass%excluded(pass%excluded_start(j):pass%excluded_start(j + 1) - 1))
        else
          call nearest_master_listed(pass%near, j, pass%grid, pass%x_sorted, x, &
                                     pass%bucket_size + pass%t_slave + pass%t_master, list_margin * pass%bucket_size, found)
        end if
        if (found > 0) c%nearest(i) = found
      end if
      end associate
    end do
    !$omp end parallel do
    c%n_own = 0
    do p = 1, size(c%passes)
      do i = offset(p) + 1, offset(p + 1)
        if (c%nearest(i) == 0) cycle
        c%n_own = c%n_own + 1
        c%own_pairs(:, c%n_own) = [rank + 1 + (i - offset(p) - 1) * n_ranks, c%nearest(i), p]
      end do
    end do
    c%time_search = c%time_search + clock() - t0
  end subroutine contact_global_search

  !> The pass whose share of the global search holds entry i (offset: where each pass starts).
  pure integer function pass_of(offset, i) result(p)
    integer, intent(in) :: offset(:), i
    p = 1
    do while (i > offset(p + 1))
      p = p + 1
    end do
  end function pass_of

  !> The candidates of the step's passes, pass after pass and in ascending slave order within a
  !> pass, and this rank's block of them. With one rank they are own_pairs; with more, the
  !> caller has gathered every rank's pairs in all_pairs(:, 1:n_all) (contact_exchange's
  !> share_contact_candidates). The pairs name a slave by its place in near_slaves, which is
  !> ascending, so ordering costs O(n_near) per pass, not O(n_slaves).
  subroutine contact_candidates(c, cycle, clock)
    type(contact_t), intent(inout) :: c
    integer(i8), intent(in) :: cycle
    procedure(clock_seconds) :: clock
    real(wp) :: t0
    integer :: k, p, n_pass, n_found, first
    t0 = clock()
    if (c%n_ranks == 1 .or. c%local) then   ! local contact: this rank's own candidates
      c%n_candidates = c%n_own
      c%candidates(:, 1:c%n_own) = c%own_pairs(:, 1:c%n_own)
    else
      c%n_candidates = 0
      do p = 1, size(c%passes)
        if (.not. contact_pass_active(c, p, cycle)) cycle
        n_pass = 0
        do k = 1, c%n_all
          if (c%all_pairs(3, k) /= p) cycle
          n_pass = n_pass + 1
          c%pass_pairs(:, n_pass) = c%all_pairs(1:2, k)
        end do
        first = c%n_candidates + 1
        call candidates_in_slave_order(int(c%passes(p)%n_near, ip), int(n_pass, ip), c%pass_pairs, &
                                       c%nearest, n_found, c%candidates(1:2, first:))
        c%candidates(3, first:first + n_found - 1) = p
        c%n_candidates = c%n_candidates + n_found
      end do
    end if
    do k = 1, c%n_candidates
      c%candidates(1, k) = c%passes(c%candidates(3, k))%near_slaves(c%candidates(1, k))
    end do
    call candidate_block(int(c%n_candidates, ip), int(merge(1, c%n_ranks, c%local), ip), &
                         int(merge(0, c%rank, c%local), ip), c%first, c%last)
    do p = 1, size(c%passes)
      if (contact_pass_active(c, p, cycle)) c%n_pass_steps = c%n_pass_steps + 1
    end do
    c%candidates_total = c%candidates_total + c%n_candidates
    c%candidates_searched = c%candidates_searched + max(0, c%last - c%first + 1)
    c%time_search = c%time_search + clock() - t0
  end subroutine contact_candidates

  !> Stage 2 on this rank's block of the candidates: the master segment around the nearest
  !> master node, the closest point on it and the penalty force. The candidates of the block
  !> cost about the same, and schedule(static, 1) deals them cyclically to the threads (measured
  !> against static and dynamic chunks: docs/performance.md). Every candidate outside the block
  !> gets an empty record, to be filled by the sharing of records between ranks.
  subroutine contact_local_search(c, clock)
    type(contact_t), intent(inout) :: c
    procedure(clock_seconds) :: clock
    integer :: k, node, segment, m, slot, at, seg_at(4)
    real(wp) :: x(3), xi, eta, xc(3), normal(3), xseg(3, 4), vseg(3, 4), f_slave(3), f_master(3, 4)
    real(wp) :: penetration, t0, stiffness, reach, lightest, clearance, failure, least
    logical :: touching, failed
    t0 = clock()
    least = huge(1.0_wp)
    c%record_nodes(1, 1:c%first - 1) = 0
    c%record_nodes(1, c%last + 1:c%n_candidates) = 0
    !$omp parallel do schedule(static, 1) default(shared) &
    !$omp private(k, node, segment, x, xi, eta, xc, normal, xseg, vseg, f_slave, f_master, &
    !$omp penetration, touching, stiffness, reach, lightest, m, clearance, slot, at, seg_at, failure, failed) &
    !$omp reduction(min: least)
    do k = c%first, c%last
      c%record_nodes(:, k) = 0
      c%record_failed(k) = .false.
      associate (pass => c%passes(c%candidates(3, k)))
      node = pass%slaves(c%candidates(1, k))
      at = pass%slave_at(c%candidates(1, k))
      x = c%x(:, at)
      slot = c%candidates(1, k)
      if (pass%edges) then   ! a slave edge: the deepest crossing of the master edges near it
        call edge_record(c, pass, k, least)
        cycle
      end if
      if (pass%bound) then   ! its binding names the segment and the point (contact_laws)
        segment = bound_segment(pass, slot)
      else
        ! a slave's initial overlap, kept as its gap, shortens its reach (0 unless asked for)
        reach = 0.5_wp * (pass%t_slave - 2.0_wp * pass%overlap(slot) + pass%t_master)
        if (still_clear(pass, slot, pass%masters(c%candidates(2, k)), c%n_sorts, c%moved)) then
          ! clear by at least its clearance at the search less twice the movement since
          if (closing_limited(c, pass)) &
            least = min(least, approach_step(c, pass, k, at, clear_bound(pass, slot, c%moved), reach))
          cycle
        end if
        if (pass%shares_nodes) then
          call segment_candidates(x, int(c%candidates(2, k), ip), int(size(pass%masters), ip), c%x, &
                                  int(size(pass%segments, 2), ip), pass%segment_at, pass%segment_start, &
                                  pass%segment_list, segment, xi, eta, xc, normal, skip_node=int(at, ip), reach=reach, &
                                  clearance=clearance)
        else
          call segment_candidates(x, int(c%candidates(2, k), ip), int(size(pass%masters), ip), c%x, &
                                  int(size(pass%segments, 2), ip), pass%segment_at, pass%segment_start, &
                                  pass%segment_list, segment, xi, eta, xc, normal, reach=reach, clearance=clearance)
        end if
        if (clearance > 0.0_wp .and. c%moved < huge(1.0_wp)) then   ! this slave's only: no other thread writes it
          pass%clear_master(slot) = pass%masters(c%candidates(2, k))
          pass%clear_sort(slot) = c%n_sorts
          pass%clear_gap(slot) = clearance
          pass%clear_moved(slot) = c%moved
        end if
        if (closing_limited(c, pass)) then
          if (segment > 0) then
            least = min(least, touching_step(c, pass, at, segment, xi, eta, xc, normal, reach))
          else if (clearance > 0.0_wp) then
            least = min(least, approach_step(c, pass, k, at, clearance, reach))
          end if
        end if
      end if
      if (segment > 0) then
        lightest = c%mass(at)
        do m = 1, 4                                ! explicit: array sections here cost a heap temporary
          seg_at(m) = pass%segment_at(m, segment)
          xseg(:, m) = c%x(:, seg_at(m))
          vseg(:, m) = c%v(:, seg_at(m))
          lightest = min(lightest, c%mass(seg_at(m)))
        end do
        stiffness = spring(pass%stiffness(segment), pass%soft_scale, lightest, c%soft_step, &
                           stable_spring_fraction / c%time_step**2 * lightest)
        failed = .false.
        if (pass%bound) failed = tie_failed(c%failed_ties, pass%pair, node)
        if (pass%bound .and. .not. failed) then   ! the binding's law (no penetration: a tie holds its offset)
          call bound_force(pass%kind, x, xseg, pass%bound_data(:, slot), stiffness, f_slave, f_master, failure)
          c%record_failed(k) = failure >= 1.0_wp   ! it fails at the end of this step (tie_failures)
          penetration = 0.0_wp
          touching = .true.
        else if (failed) then   ! a failed tie: penalty contact against the segment it was tied to
          call penalty_force(x, pass%t_slave, xseg, pass%t_master, stiffness, f_slave, f_master, penetration, &
                             touching, v_slave=c%v(:, at), v_master=vseg, mu_static=pass%mu_static, &
                             mu_dynamic=pass%mu_dynamic, decay=pass%decay, v_slip=stick_speed, rounded_edges=.true.)
        else
          call penalty_force(x, pass%t_slave - 2.0_wp * pass%overlap(slot), xseg, pass%t_master, &
                             stiffness, f_slave, &
                             f_master, penetration, touching, v_slave=c%v(:, at), v_master=vseg, &
                             mu_static=pass%mu_static, mu_dynamic=pass%mu_dynamic, decay=pass%decay, &
                             v_slip=stick_speed, rounded_edges=.true., closest=[xi, eta, xc, normal])
        end if
        if (touching) then
          c%record_penetration(k) = penetration
          c%record_nodes(1, k) = node
          c%record_nodes(2:5, k) = pass%segments(:, segment)
          c%record_force(:, 1, k) = f_slave
          c%record_force(:, 2:5, k) = f_master
        end if
      end if
      end associate
    end do
    !$omp end parallel do
    c%near_step = min(c%near_step, least)
    c%time_force = c%time_force + clock() - t0
  end subroutine contact_local_search

  !> The record of candidate k of an edge pass (edge_to_edge_contact): its slave edge against the
  !> edges of the segments around its nearest master (edge_search), the deepest crossing's force
  !> (edge_penalty) with the segment's penalty stiffness, capped so that the spring's frequency on
  !> the four nodes stays within the bound of a node's spring (below). The record names the slave edge's two nodes, the
  !> master edge's two and the last again with no force (record_nodes has five). No record where no
  !> edge crosses within reach; where every edge met is clear, the clearance is kept and spares the
  !> search while it holds (still_clear), as for a node. Called by one thread per candidate.
  subroutine edge_record(c, pass, k, least)
    type(contact_t), intent(inout) :: c
    type(contact_pass_t), intent(inout) :: pass
    integer, intent(in) :: k
    real(wp), intent(inout) :: least   !< the automatic step limit so far (contact_closing)
    integer :: j, m, a1, a2, b1, b2, segment, corner
    real(wp) :: penetration, stiffness, force(3, 4), s, u, inverse_mass, clearance, along(3)
    real(wp) :: speed
    logical :: touching, limited, clear
    j = c%candidates(1, k)
    m = c%candidates(2, k)
    a1 = pass%slave_at(j)
    a2 = pass%slave_other_at(j)
    limited = closing_limited(c, pass)
    speed = norm2(c%v(:, a1) - c%v(:, pass%master_at(m)))   ! relative to the nearest master node
    clear = still_clear(pass, j, pass%masters(m), c%n_sorts, c%moved)
    ! a still-clear edge is searched only where the automatic limit needs its clearance: its bound
    ! lets it close on the master edges within two steps (the search then writes no record)
    if (clear) then
      if (.not. limited) return
      if (clear_bound(pass, j, c%moved) > 2.0_wp * speed * c%time_step) return
    end if
    call deepest_edge_crossing(c%x, a1, a2, pass%segment_at, pass%segment_list, pass%segment_start(m), &
                               pass%segment_start(m + 1) - 1, pass%t_slave, pass%t_master, segment, corner, penetration, &
                               clearance)
    ! clear: the distance of two edges changes by at most the sum of their nodes' movements, which
    ! still_clear bounds as it does a node's (this slave's entry only: no other thread writes it)
    if (clearance > 0.0_wp .and. clearance < huge(1.0_wp) .and. c%moved < huge(1.0_wp)) then
      pass%clear_master(j) = pass%masters(m)
      pass%clear_sort(j) = c%n_sorts
      pass%clear_gap(j) = clearance
      pass%clear_moved(j) = c%moved
    end if
    ! clear of the master edges by less than twice its closing in a step: the automatic limit
    if (segment == 0 .or. clear) then
      if (limited .and. clearance < huge(1.0_wp) .and. clearance <= 2.0_wp * speed * c%time_step) &
        least = min(least, closing_limit_step(c, pass, speed))
      return
    end if
    b1 = pass%segment_at(corner, segment)
    b2 = pass%segment_at(mod(corner, 4) + 1, segment)
    ! the spring's frequency: omega^2 = k sum_I w_I^2 / m_I, w the four shares (1 - s, s, 1 - u, u);
    ! a node's spring (slave share 1, the segment's N_I) has sum w^2 / m <= 2 / m_lightest, so its cap
    ! holds omega^2 dt^2 <= 2 stable_spring_fraction: the edge's cap holds the same bound
    call closest_points_of_edges(c%x(:, a1), c%x(:, a2), c%x(:, b1), c%x(:, b2), s, u)
    if (limited) then   ! a crossing within reach: the closest points' relative speed along the line between them
      along = ((1.0_wp - s) * c%x(:, a1) + s * c%x(:, a2)) - ((1.0_wp - u) * c%x(:, b1) + u * c%x(:, b2))
      along = along / max(norm2(along), tiny(1.0_wp))
      least = min(least, closing_limit_step(c, pass, abs(dot_product(along, &
                  ((1.0_wp - s) * c%v(:, a1) + s * c%v(:, a2)) - ((1.0_wp - u) * c%v(:, b1) + u * c%v(:, b2))))))
    end if
    inverse_mass = (1.0_wp - s)**2 / c%mass(a1) + s**2 / c%mass(a2) + (1.0_wp - u)**2 / c%mass(b1) + u**2 / c%mass(b2)
    stiffness = spring(pass%stiffness(segment), pass%soft_scale, 2.0_wp / inverse_mass, c%soft_step, &
                       2.0_wp * stable_spring_fraction / (c%time_step**2 * inverse_mass))
    call edge_edge_force(c%x(:, a1), c%x(:, a2), c%x(:, b1), c%x(:, b2), pass%t_slave, pass%t_master, stiffness, &
                         force, penetration, touching)
    if (.not. touching) return
    c%record_penetration(k) = penetration
    c%record_nodes(:, k) = [pass%slaves(j), pass%slave_other(j), pass%segments(corner, segment), &
                            pass%segments(mod(corner, 4) + 1, segment), pass%segments(mod(corner, 4) + 1, segment)]
    c%record_force(:, 1:4, k) = force
    c%record_force(:, 5, k) = 0.0_wp
  end subroutine edge_record

  !> Slave j of the pass, whose nearest master is master (a contact-node id), still cannot touch: at an earlier step of
  !> the same sort (sort number n_sorts) the segments around the same master were all at least
  !> clear_gap farther from it than they could touch, and since then no node has moved more than
  !> clear_moved + moved (each at most that far from its place at the sort, then and now). A point
  !> of a segment moves as its nodes do, so the slave's distance to a segment has shrunk by at most
  !> twice that, and the offset the face test allows (edge_tolerance times the diagonal) has grown
  !> by at most edge_tolerance times twice that. The answer is the one the local search would give
  !> (no record), without its work.
  pure logical function still_clear(pass, j, master, n_sorts, moved)
    type(contact_pass_t), intent(in) :: pass
    integer, intent(in) :: j, master
    integer(i8), intent(in) :: n_sorts
    real(wp), intent(in) :: moved
    still_clear = .false.
    ! an unknown movement (huge) is never clear, and would overflow the bound below
    if (pass%clear_sort(j) /= n_sorts .or. pass%clear_master(j) /= master .or. moved >= huge(1.0_wp)) return
    still_clear = pass%clear_gap(j) > 2.0_wp * (1.0_wp + edge_tolerance) * (pass%clear_moved(j) + moved) &
                                      * (1.0_wp + 1.0e-9_wp)
  end function still_clear

  !> The least clearance slave j (a node or an edge) can have now: the clearance its search left
  !> less twice the most any node has moved since (still_clear's bound).
  pure real(wp) function clear_bound(pass, j, moved) result(gap)
    type(contact_pass_t), intent(in) :: pass
    integer, intent(in) :: j
    real(wp), intent(in) :: moved
    gap = pass%clear_gap(j) - 2.0_wp * (1.0_wp + edge_tolerance) * (pass%clear_moved(j) + moved)
  end function clear_bound

  !> Slave j of the pass is searched: not a node (or an edge) whose elements are all eroded.
  pure logical function live_slave(pass, j)
    type(contact_pass_t), intent(in) :: pass
    integer, intent(in) :: j
    live_slave = .true.
    if (pass%any_dead_slave) live_slave = .not. pass%slave_dead(j)
  end function live_slave

  !> Cheap rejection: a slave farther than a bucket from the master nodes' sorted bounding box
  !> cannot touch (an idle pair costs one box test per slave).
  pure logical function near_box(p, pass)
    real(wp), intent(in) :: p(3)
    type(contact_pass_t), intent(in) :: pass
    real(wp) :: margin
    margin = pass%bucket_size + pass%t_slave + pass%t_master
    near_box = all(p >= pass%grid%lower - margin .and. p <= pass%grid%upper + margin)
  end function near_box

end module contact_stages
