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
  use contact_search, only: node_segment_map, shell_penalty_stiffness
  use initial_penetration, only: slave_penetrations
  use contact_surfaces, only: part_nodes, contact_thickness
  use paradyn_schema, only: initial_penetration_gap
  implicit none
  private
  public :: contact_pass_t, pass_between_parts, pass_near_lists, slave_slot

  type :: contact_pass_t
    integer :: pair = 0                        !< the contact definition (deck entry) it comes from
    logical :: every_cycle = .true.            !< runs every cycle, or (the paper's swap) every other one
    integer :: swap_index = 1                  !< with every_cycle false: runs when cycle + swap_index is odd
    !> the slave force's share of the definition's force on its first part: 1 (the slave is the first
    !> part), -1 (the master is: it takes the reactions), 0 (single surface: within one part)
    real(wp) :: first_part_sign = 0
    integer, allocatable :: slaves(:)          !< contact-node ids of the slave part's nodes
    integer, allocatable :: masters(:)         !< contact-node ids of the master part's nodes
    integer, allocatable :: segments(:, :)     !< (4, n) master segments, contact-node ids
    integer, allocatable :: segment_element(:) !< the global element of each segment
    ! local contact (contact_neighbours): the masters whose positions this rank holds, ascending,
    ! which alone are sorted into the grid (held_index: a master's place among them, 0 if not held)
    logical :: held_only = .false.
    integer, allocatable :: held_masters(:), held_index(:)
    integer, allocatable :: own_slaves(:)      !< local contact: the slaves (indices) this rank owns
    integer, allocatable :: segment_start(:), segment_list(:)  !< contact node -> its segments
    real(wp), allocatable :: stiffness(:)      !< penalty stiffness per segment (initial geometry)
    !> slave s is a node of master segments: its search skips their nodes, master indices
    !> excluded(excluded_start(s) : excluded_start(s + 1) - 1), and the segments
    logical :: shares_nodes = .false.
    integer, allocatable :: excluded_start(:), excluded(:)
    !> each slave's overlap at the start, taken as its gap (/contact/initial_penetration = gap), else
    !> 0; at its slave_slot (local contact: the rank's own slaves only, from pass_near_lists)
    real(wp), allocatable :: overlap(:)
    real(wp), allocatable :: x_sorted(:, :)    !< master positions when last sorted
    integer, allocatable :: near_slaves(:)     !< slaves that can come near the master box before the next sort
    integer :: n_near = 0
    ! idle: cannot touch before the next activity check, so the pass runs no stage; stale: a
    ! sort fell while it was idle, so its grid is rebuilt from the positions of that sort on waking
    logical :: idle = .false., stale = .false.
    type(bucket_grid_t) :: grid
    type(near_lists_t) :: near                 !< nearby master nodes (nearest_cache) of each slave searched here
    !> local contact: each slave's list in near, its place among own_slaves (0: not own, no list);
    !> elsewhere (not allocated) slave j has list j
    integer, allocatable :: near_slot(:)
    !> each slave's clearance (contact_stages): at sort number clear_sort, when the contact moved
    !> clear_moved since that sort, every segment around master clear_master was at least clear_gap
    !> farther from the slave than it could touch; like overlap, at the slave's slave_slot
    integer, allocatable :: clear_master(:)
    integer(i8), allocatable :: clear_sort(:)
    real(wp), allocatable :: clear_gap(:), clear_moved(:)
    real(wp) :: bucket_size = 0, t_slave = 0, t_master = 0, mu_static = 0, mu_dynamic = 0, decay = 0
  end type contact_pass_t

contains

  !> The pass of contact definition `pair` with the nodes of slave_part against the shell
  !> segments of master_part (contact_id: the contact-node id of each global node, 0 if none).
  subroutine pass_between_parts(deck, pair, slave_part, master_part, contact_id, n_contact, pass)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: pair, slave_part, master_part, contact_id(:), n_contact
    type(contact_pass_t), intent(out) :: pass
    integer, allocatable :: elements(:), slave_nodes(:), master_nodes(:), slave_elements(:)
    real(wp), allocatable :: push(:, :)
    integer :: e, s, n_entries
    real(wp) :: xseg(3, 4), young, poisson
    pass%pair = pair
    if (slave_part /= master_part) pass%first_part_sign = merge(1.0_wp, -1.0_wp, slave_part == deck%contact_pairs(1, pair))
    call part_nodes(deck, slave_part, slave_nodes, slave_elements)
    pass%slaves = contact_id(slave_nodes)
    call part_nodes(deck, master_part, master_nodes, elements)
    pass%masters = contact_id(master_nodes)
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
    allocate (pass%segment_start(n_contact + 1), pass%segment_list(4 * size(elements)))
    call node_segment_map(int(n_contact, ip), int(size(elements), ip), pass%segments, pass%segment_start, &
                          pass%segment_list, n_entries)
    allocate (pass%x_sorted(3, 0))   ! each sort gives it the masters it sorts (contact_sort_pass)
    pass%near_slaves = [(e, e = 1, size(pass%slaves))]
    pass%n_near = size(pass%slaves)
    pass%t_slave = contact_thickness(deck, pair, slave_part)
    pass%t_master = contact_thickness(deck, pair, master_part)
    call exclusions(pass, contact_id, master_nodes, n_contact)
    pass%mu_static = deck%contact_static_friction(pair)
    pass%mu_dynamic = deck%contact_dynamic_friction(pair)
    pass%decay = deck%contact_friction_decay(pair)
    allocate (pass%overlap(size(slave_nodes)), source=0.0_wp)
    if (deck%contact_initial_penetration(pair) == initial_penetration_gap) then
      allocate (push(3, size(slave_nodes)))
      call slave_penetrations(deck%coordinates, slave_nodes, deck%connectivity(:, elements), pass%t_slave, &
                              pass%t_master, pass%overlap, push)
    end if
  end subroutine pass_between_parts

  !> The lists of nearby master nodes and the clearances of the slaves this rank searches: every
  !> slave, or (own, local contact) the slaves it owns, own_slaves, alone, whose overlaps are then
  !> kept alone too (each at its place among them, near_slot).
  subroutine pass_near_lists(pass, own)
    type(contact_pass_t), intent(inout) :: pass
    logical, intent(in) :: own
    integer :: i, n
    if (own) then
      allocate (pass%near_slot(size(pass%slaves)), source=0)
      pass%near_slot(pass%own_slaves) = [(i, i = 1, size(pass%own_slaves))]
      pass%overlap = pass%overlap(pass%own_slaves)
      n = size(pass%own_slaves)
    else
      n = size(pass%slaves)
    end if
    call near_lists_setup(n, pass%near)
    allocate (pass%clear_master(n), source=0)
    allocate (pass%clear_sort(n), source=-1_i8)
    allocate (pass%clear_gap(n), pass%clear_moved(n), source=0.0_wp)
  end subroutine pass_near_lists

  !> The place of slave j's clearance and overlap: its place among the rank's own slaves under
  !> local contact (near_slot), else j.
  pure integer function slave_slot(pass, j) result(slot)
    type(contact_pass_t), intent(in) :: pass
    integer, intent(in) :: j
    if (allocated(pass%near_slot)) then
      slot = pass%near_slot(j)
    else
      slot = j
    end if
  end function slave_slot

  !> For each slave, the master indices of the nodes of the master segments that contain it (none
  !> where the slave and master parts share no node).
  subroutine exclusions(pass, contact_id, master_nodes, n_contact)
    type(contact_pass_t), intent(inout) :: pass
    integer, intent(in) :: contact_id(:), master_nodes(:), n_contact
    integer, allocatable :: master_index(:), list(:)
    integer :: s, j, node, n, m
    allocate (master_index(n_contact), source=0)
    master_index(contact_id(master_nodes)) = [(j, j = 1, size(master_nodes))]
    ! at most the 4 nodes of each segment around each slave (none where the parts share no node)
    n = 0
    do s = 1, size(pass%slaves)
      n = n + 4 * (pass%segment_start(pass%slaves(s) + 1) - pass%segment_start(pass%slaves(s)))
    end do
    allocate (pass%excluded_start(size(pass%slaves) + 1), list(n))
    n = 0
    do s = 1, size(pass%slaves)
      pass%excluded_start(s) = n + 1
      node = pass%slaves(s)
      do j = pass%segment_start(node), pass%segment_start(node + 1) - 1
        do m = 1, 4
          if (any(list(pass%excluded_start(s):n) == master_index(pass%segments(m, pass%segment_list(j))))) cycle
          n = n + 1
          list(n) = master_index(pass%segments(m, pass%segment_list(j)))
        end do
      end do
    end do
    pass%excluded_start(size(pass%slaves) + 1) = n + 1
    pass%excluded = list(1:n)
    pass%shares_nodes = n > 0
  end subroutine exclusions

end module contact_pass
