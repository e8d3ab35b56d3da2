!> One contact pass: the slave nodes of one part against the shell segments of another (or of the
!> same part, a single-surface contact), with the pass's bucket grid, penalty stiffnesses,
!> thicknesses and friction. The members of the contact family (contact_kind) build their
!> definitions' passes from these.
!>
!> Where a slave node is itself a node of master segments (always in a single-surface pass), it
!> must not meet its own surface: its nearest-master search skips the nodes of the master segments
!> that contain it (its own node and its neighbours), and its local search skips those segments.
module contact_pass
  use paradyn_kinds, only: wp, ip, i8
  use model_deck, only: deck_t
  use contact_buckets, only: bucket_grid_t
  use nearest_cache, only: near_lists_t, near_lists_setup
  use contact_search, only: node_segment_map
  use contact_penalty, only: shell_penalty_stiffness
  use initial_penetration, only: slave_penetrations
  use integer_sort, only: distinct_ascending, sorted_position
  use contact_surfaces, only: part_nodes, contact_thickness
  use paradyn_schema, only: initial_penetration_gap, contact_kind_is_tied
  implicit none
  private
  public :: contact_pass_t, pass_between_parts, pass_near_lists, pass_hold_segments, bound_segment
  public :: pass_mark_dead_slaves

  type :: contact_pass_t
    integer :: pair = 0                        !< the contact definition (deck entry) it comes from
    integer :: slave_part = 0, master_part = 0 !< the parts of its slaves and of its segments
    logical :: every_cycle = .true.            !< runs every cycle, or (the paper's swap) every other one
    integer :: swap_index = 1                  !< with every_cycle false: runs when cycle + swap_index is odd
    !> the slave force's share of the definition's force on its first part: 1 (the slave is the first
    !> part), -1 (the master is: it takes the reactions), 0 (single surface: within one part)
    real(wp) :: first_part_sign = 0
    ! the pass's lists (docs/theory.md, "Dividing the contact state": passes per rank): every slave,
    ! master and segment on one rank and in the replicated scheme; under local contact the slaves
    ! this rank owns, and the segments it holds (its domain's and the ghost segments of the last
    ! refresh) with their nodes, the masters held, renewed at each refresh (pass_hold_segments)
    integer, allocatable :: slaves(:)          !< contact-node ids of the slaves, ascending
    integer, allocatable :: masters(:)         !< contact-node ids of the masters held, ascending
    integer, allocatable :: own_masters(:)     !< the masters this rank owns (its activity extents)
    integer, allocatable :: segments(:, :)     !< (4, n) master segments held, contact-node ids
    integer, allocatable :: segment_element(:) !< the global element of each, ascending
    integer, allocatable :: segment_start(:), segment_list(:)  !< master index -> its segments
    integer, allocatable :: segment_corner(:, :)  !< (4, n) each segment's nodes as master indices
    real(wp), allocatable :: stiffness(:)      !< penalty stiffness per segment (initial geometry)
    !> local contact: the segments of this rank's elements (the domain's part of segments above)
    integer, allocatable :: own_segments(:, :), own_element(:)
    ! the held slots (contact_slots) of the slaves, the masters, the segments' nodes and the own
    ! segments' nodes, renewed whenever the slots are (contact_pass_slots)
    integer, allocatable :: slave_at(:), master_at(:), segment_at(:, :), own_segment_at(:, :)
    !> the local columns on this rank of the slaves and masters it owns (the activity extents)
    integer, allocatable :: slave_columns(:), master_columns(:)
    real(wp), allocatable :: own_stiffness(:)
    !> slave s is a node of master segments: its search skips their nodes, master indices
    !> excluded(excluded_start(s) : excluded_start(s + 1) - 1), and the segments
    logical :: shares_nodes = .false.
    integer, allocatable :: excluded_start(:), excluded(:)
    !> each slave's overlap at the start, taken as its gap (/contact/initial_penetration = gap), else 0;
    !> gap_at_birth: a gap definition born later takes them at its birth (contact_birth_gaps)
    real(wp), allocatable :: overlap(:)
    logical :: gap_at_birth = .false.
    !> the definition's contact kind (schema enum contact_kind); a kind with the trait tied binds
    !> each slave to a master segment at the start (contact_laws): the binding, kept for the run,
    !> replaces the search and the penalty law: each slave's segment (its global element, 0: the
    !> slave is free) and the law's data for it (a tie: the point's xi, eta and the slave's offset)
    integer :: kind = 0
    logical :: bound = .false.
    !> an edge pass (edge_to_edge_contact): slave j is the element edge from slaves(j) to
    !> slave_other(j) (contact-node ids; a node that begins several edges is listed once for each),
    !> met by the edges of the master segments; slave_other_at: the held slots of the other ends
    logical :: edges = .false.
    integer, allocatable :: slave_other(:), slave_other_at(:)
    integer, allocatable :: bound_element(:)
    real(wp), allocatable :: bound_data(:, :)   !< (the law's width, slaves)
    real(wp), allocatable :: x_sorted(:, :)    !< master positions when last sorted
    integer, allocatable :: near_slaves(:)     !< slaves that can come near the master box before the next sort
    integer :: n_near = 0
    ! idle: cannot touch before the next activity check, so the pass runs no stage; stale: a
    ! sort fell while it was idle, so its grid is rebuilt from the positions of that sort on waking
    logical :: idle = .false., stale = .false.
    type(bucket_grid_t) :: grid
    type(near_lists_t) :: near                 !< nearby master nodes (nearest_cache) of each slave
    !> each slave's clearance (contact_stages): at sort number clear_sort, when the contact moved
    !> clear_moved since that sort, every segment around master clear_master (a contact-node id)
    !> was at least clear_gap farther from the slave than it could touch
    integer, allocatable :: clear_master(:)
    integer(i8), allocatable :: clear_sort(:)
    real(wp), allocatable :: clear_gap(:), clear_moved(:)
    real(wp) :: bucket_size = 0, t_slave = 0, t_master = 0, mu_static = 0, mu_dynamic = 0, decay = 0
    real(wp) :: t_wall = huge(1.0_wp)          !< the thinner contact thickness of its shell sides (a rigid solid's faces are no wall)
    !> the definition's life (/contact/birth_time, death_time): the pass runs while birth <= t <= death
    real(wp) :: birth = 0, death = huge(1.0_wp)
    !> the soft-constraint scale (/contact/soft_constraint; 0 = off): the spring is at least
    !> soft_scale m / (2 dt^2) (contact_stages)
    real(wp) :: soft_scale = 0
    !> eroded elements (element_erosion) leave the contact: a held segment whose element is eroded
    !> is dead (no slave meets it, a tie to it is released), a master whose held segments are all
    !> dead is left out of the bucket grid, and a slave whose elements are all eroded (an edge:
    !> one of its ends) is not searched. Allocated only once something has eroded.
    logical :: any_dead_segment = .false., any_dead_slave = .false.
    logical, allocatable :: segment_dead(:), master_dead(:), slave_dead(:)
    !> a tiebreak definition's failure stresses NFLS, SFLS (/contact/normal_failure_stress, shear_...)
    real(wp) :: strength(2) = 0
  end type contact_pass_t

contains

  !> The pass of contact definition `pair` with the nodes of slave_part against the shell
  !> segments of master_part (contact_id: the contact-node id of each global node, 0 if none):
  !> every slave, master and segment (a rank under local contact keeps its own: contact_neighbours).
  subroutine pass_between_parts(deck, pair, slave_part, master_part, contact_id, pass)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: pair, slave_part, master_part, contact_id(:)
    type(contact_pass_t), intent(out) :: pass
    integer, allocatable :: elements(:), slave_nodes(:), master_nodes(:), slave_elements(:)
    real(wp), allocatable :: push(:, :)
    integer :: e, s
    real(wp) :: xseg(3, 4), young, poisson
    pass%pair = pair
    pass%kind = deck%contact_kind(pair)
    pass%bound = contact_kind_is_tied(pass%kind)
    pass%slave_part = slave_part
    pass%master_part = master_part
    if (slave_part /= master_part) pass%first_part_sign = merge(1.0_wp, -1.0_wp, slave_part == deck%contact_pairs(1, pair))
    call part_nodes(deck, slave_part, slave_nodes, slave_elements)
    pass%slaves = contact_id(slave_nodes)
    call part_nodes(deck, master_part, master_nodes, elements)
    allocate (pass%segments(4, size(elements)), pass%stiffness(size(elements)))
    pass%segment_element = elements
    young = deck%young(deck%part_material(master_part))
    poisson = deck%poisson(deck%part_material(master_part))
    pass%bucket_size = 0.0_wp
    do s = 1, size(elements)
      pass%segments(:, s) = contact_id(deck%connectivity(:, elements(s)))
      xseg = deck%coordinates(:, deck%connectivity(:, elements(s)))
      pass%stiffness(s) = shell_penalty_stiffness(xseg, young, poisson, deck%contact_penalty_scale(pair))
      pass%bucket_size = max(pass%bucket_size, norm2(xseg(:, 3) - xseg(:, 1)), norm2(xseg(:, 4) - xseg(:, 2)))
    end do
    call pass_hold_segments(pass)
    pass%own_masters = pass%masters
    allocate (pass%x_sorted(3, 0))   ! each sort gives it the masters it sorts (contact_sort_pass)
    pass%near_slaves = [(e, e = 1, size(pass%slaves))]
    pass%n_near = size(pass%slaves)
    pass%t_slave = contact_thickness(deck, pair, slave_part)
    pass%t_master = contact_thickness(deck, pair, master_part)
    if (deck%surface_only(slave_part) == 0) pass%t_wall = pass%t_slave
    if (deck%surface_only(master_part) == 0) pass%t_wall = min(pass%t_wall, pass%t_master)
    pass%mu_static = deck%contact_static_friction(pair)
    pass%mu_dynamic = deck%contact_dynamic_friction(pair)
    pass%decay = deck%contact_friction_decay(pair)
    pass%soft_scale = deck%contact_soft_constraint(pair)
    pass%birth = deck%contact_birth_time(pair)
    pass%death = deck%contact_death_time(pair)
    pass%strength = [deck%contact_normal_failure_stress(pair), deck%contact_shear_failure_stress(pair)]
    allocate (pass%overlap(size(slave_nodes)), source=0.0_wp)
    ! a definition born later is not checked at the start: its overlaps then are not its gaps, those
    ! at its birth are
    pass%gap_at_birth = deck%contact_initial_penetration(pair) == initial_penetration_gap .and. &
                        deck%contact_birth_time(pair) > 0.0_wp .and. .not. pass%bound
    if (deck%contact_initial_penetration(pair) == initial_penetration_gap .and. deck%contact_birth_time(pair) == 0.0_wp) then
      allocate (push(3, size(slave_nodes)))
      call slave_penetrations(deck%coordinates, slave_nodes, deck%connectivity(:, elements), pass%t_slave, &
                              pass%t_master, pass%overlap, push)
    end if
  end subroutine pass_between_parts

  !> The held segment of slave j's binding in a bound pass (its place in segment_element), 0 for a
  !> free slave, a segment this rank does not hold or an eroded one (the tie is released).
  pure integer function bound_segment(pass, j) result(segment)
    type(contact_pass_t), intent(in) :: pass
    integer, intent(in) :: j
    integer :: i
    segment = 0
    if (pass%bound_element(j) == 0 .or. size(pass%segment_element) == 0) return
    i = sorted_position(pass%segment_element, pass%bound_element(j))
    if (pass%segment_element(i) == pass%bound_element(j)) segment = i
    if (segment > 0 .and. pass%any_dead_segment) then   ! a tie to an eroded segment is released
      if (pass%segment_dead(segment)) segment = 0
    end if
  end function bound_segment

  !> The lists of nearby master nodes and the clearances of the pass's slaves.
  subroutine pass_near_lists(pass)
    type(contact_pass_t), intent(inout) :: pass
    integer :: n
    n = size(pass%slaves)
    call near_lists_setup(n, pass%near)
    allocate (pass%clear_master(n), source=0)
    allocate (pass%clear_sort(n), source=-1_i8)
    allocate (pass%clear_gap(n), pass%clear_moved(n), source=0.0_wp)
  end subroutine pass_near_lists

  !> From the segments held (segments, segment_element ascending, stiffness): the masters held
  !> (their nodes, ascending), each master's segments (ascending, so in the global order) and, for
  !> each slave that is a node of master segments, the master indices of their nodes (exclusions).
  !> The segments around a slave are held with it (they have a node, the slave, within reach of
  !> this rank's slaves), so its exclusions are the ones of the whole model. With eroded (the
  !> global ids of the eroded elements, ascending), the segments of eroded elements are dead: they
  !> leave each master's list (the exclusions stay those of the whole mesh), and a master left
  !> with no live segment is dead.
  subroutine pass_hold_segments(pass, eroded)
    type(contact_pass_t), intent(inout) :: pass
    integer, intent(in), optional :: eroded(:)
    integer, allocatable :: corners(:, :), live_corners(:, :)
    integer :: s, m, n_entries
    pass%masters = distinct_ascending(reshape(pass%segments, [size(pass%segments)]))
    allocate (corners(4, size(pass%segments, 2)))
    do s = 1, size(pass%segments, 2)
      do m = 1, 4
        corners(m, s) = sorted_position(pass%masters, pass%segments(m, s))
      end do
    end do
    if (allocated(pass%segment_start)) deallocate (pass%segment_start, pass%segment_list)
    allocate (pass%segment_start(size(pass%masters) + 1), pass%segment_list(4 * size(pass%segments, 2)))
    call node_segment_map(int(size(pass%masters), ip), int(size(pass%segments, 2), ip), corners, pass%segment_start, &
                          pass%segment_list, n_entries)
    call exclusions(pass, corners)
    pass%any_dead_segment = .false.
    if (present(eroded)) then
      if (size(eroded) > 0) call mark_dead_segments(pass, eroded)
    end if
    if (pass%any_dead_segment) then   ! each master's live segments only (a dead one's corners are out of range)
      live_corners = corners
      do s = 1, size(pass%segments, 2)
        if (pass%segment_dead(s)) live_corners(:, s) = 0
      end do
      call node_segment_map(int(size(pass%masters), ip), int(size(pass%segments, 2), ip), live_corners, &
                            pass%segment_start, pass%segment_list, n_entries)
      pass%master_dead = [(pass%segment_start(m + 1) == pass%segment_start(m), m = 1, size(pass%masters))]
    end if
    call move_alloc(corners, pass%segment_corner)
  end subroutine pass_hold_segments

  !> segment_dead: the held segments whose element is in eroded (ascending global ids).
  subroutine mark_dead_segments(pass, eroded)
    type(contact_pass_t), intent(inout) :: pass
    integer, intent(in) :: eroded(:)
    integer :: s, i
    if (allocated(pass%segment_dead)) deallocate (pass%segment_dead)
    allocate (pass%segment_dead(size(pass%segment_element)), source=.false.)
    do s = 1, size(pass%segment_element)
      i = sorted_position(eroded, pass%segment_element(s))
      if (i < 1 .or. i > size(eroded)) cycle
      pass%segment_dead(s) = eroded(i) == pass%segment_element(s)
    end do
    pass%any_dead_segment = any(pass%segment_dead)
  end subroutine mark_dead_segments

  !> slave_dead: the slaves among dead (contact-node ids of nodes whose elements are all eroded,
  !> ascending); an edge slave is dead with either end (every element along it is then eroded).
  subroutine pass_mark_dead_slaves(pass, dead)
    type(contact_pass_t), intent(inout) :: pass
    integer, intent(in) :: dead(:)
    integer :: j
    if (allocated(pass%slave_dead)) deallocate (pass%slave_dead)
    allocate (pass%slave_dead(size(pass%slaves)), source=.false.)
    if (size(dead) == 0) then
      pass%any_dead_slave = .false.
      return
    end if
    do j = 1, size(pass%slaves)
      pass%slave_dead(j) = listed(pass%slaves(j))
      if (pass%edges) pass%slave_dead(j) = pass%slave_dead(j) .or. listed(pass%slave_other(j))
    end do
    pass%any_dead_slave = any(pass%slave_dead)
  contains
    logical function listed(node)
      integer, intent(in) :: node
      integer :: i
      i = sorted_position(dead, node)
      listed = .false.
      if (i >= 1 .and. i <= size(dead)) listed = dead(i) == node
    end function listed
  end subroutine pass_mark_dead_slaves

  !> For each slave, the master indices of the nodes of the master segments that contain it (none
  !> where the slave and master parts share no node); corners: the segments' nodes as master indices.
  subroutine exclusions(pass, corners)
    type(contact_pass_t), intent(inout) :: pass
    integer, intent(in) :: corners(:, :)
    integer, allocatable :: list(:), at(:)
    integer :: s, j, i, n, m
    allocate (at(size(pass%slaves)), source=0)
    ! at most the 4 nodes of each segment around each slave (none where the parts share no node)
    n = 0
    do s = 1, size(pass%slaves)
      i = sorted_position(pass%masters, pass%slaves(s))
      if (i < 1 .or. i > size(pass%masters)) cycle
      if (pass%masters(i) /= pass%slaves(s)) cycle
      at(s) = i
      n = n + 4 * (pass%segment_start(i + 1) - pass%segment_start(i))
    end do
    if (allocated(pass%excluded_start)) deallocate (pass%excluded_start)
    allocate (pass%excluded_start(size(pass%slaves) + 1), list(n))
    n = 0
    do s = 1, size(pass%slaves)
      pass%excluded_start(s) = n + 1
      i = at(s)
      if (i == 0) cycle
      do j = pass%segment_start(i), pass%segment_start(i + 1) - 1
        do m = 1, 4
          if (any(list(pass%excluded_start(s):n) == corners(m, pass%segment_list(j)))) cycle
          n = n + 1
          list(n) = corners(m, pass%segment_list(j))
        end do
      end do
    end do
    pass%excluded_start(size(pass%slaves) + 1) = n + 1
    pass%excluded = list(1:n)
    pass%shares_nodes = n > 0
  end subroutine exclusions

end module contact_pass
