!> The contact state's set-up under local contact from each rank's own rows (docs/theory.md,
!> "Dividing the contact state": set-up), with nothing sized by the global mesh but the contact
!> nodes' count:
!>   - which parts meet at each node of the domain: the part of every element corner at its nodes,
!>     this rank's and (one halo exchange of the corners, as the nodal sum's) those of the ranks
!>     sharing the node, so a node is known as a contact node, a slave or a master wherever its
!>     elements of that part lie;
!>   - the contact-node ids (the place of a node among the contact nodes of the model, by global
!>     id): each rank sends its domain's contact nodes to their homes in the node directory (by id
!>     range, block_owner), each home numbers its own after those of the homes before it (one
!>     MPI_Exscan) and answers;
!>   - each pass from its member of the contact family on the deck without its mesh (its
!>     definition, parts, friction, thicknesses), then its lists from this rank's rows: the slaves
!>     it owns, the segments of its elements with their stiffnesses (from the deck's coordinates,
!>     the bits of one rank), the masters it owns (the activity extents), the bucket size (the
!>     longest diagonal: a maximum over the ranks), a single-surface thickness cap (the shortest
!>     edge: a minimum, contact_checks' held_thickness), the gap mode's overlaps (its slaves
!>     against the master elements near them from every rank, as the start checks measure them)
!>     and a bound pass's bindings (its slaves against the same, contact_laws).
!> One rank and the replicated scheme keep contact_setup on the global layout (every contact node
!> is held there). Collective.
module contact_local_setup
  use mpi_f08
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: initial_penetration_gap
  use model_deck, only: deck_t, node_row
  use domain_decomposition, only: domain_t, block_owner, local_element
  use halo_exchange, only: halo_t, halo_setup, exchange_corners
  use rank_exchange, only: exchange_int
  use integer_sort, only: distinct_ascending, sorted_position, merge_sort_ascending
  use contact_penalty, only: shell_penalty_stiffness
  use contact_interface, only: contact_t, definitions_passes
  use contact_ghost_segments, only: hold_ghost_segments, segment_row_width
  use contact_checks, only: held_thickness, part_rows, corners
  use near_elements, only: near_set_t, gather_near, box_of
  use initial_penetration, only: slave_penetrations
  use contact_pass, only: contact_pass_t
  use contact_laws, only: binding_reach, bind_slaves
  use tiebreak_contact, only: tie_areas
  implicit none
  private
  public :: local_contact_setup

contains

  !> c from this rank's rows (deck) on its domain; contact_of(ln): the contact-node id of local
  !> node ln (0: not a contact node). Collective.
  subroutine local_contact_setup(deck, dom, comm, c, contact_of)
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    type(contact_t), intent(out) :: c
    integer, allocatable, intent(out) :: contact_of(:)
    real(wp), allocatable :: corner(:, :)
    logical, allocatable :: in_contact(:)
    integer :: ln, j
    call corner_parts(deck, dom, comm, corner)
    allocate (in_contact(dom%n_nodes), source=.false.)
    do ln = 1, dom%n_nodes
      do j = dom%assembly_start(ln), dom%assembly_start(ln + 1) - 1
        if (any(deck%contact_pairs(:, 1:deck%n_contacts) == nint(corner(1, dom%assembly_slot(j))))) &
          in_contact(ln) = .true.
      end do
    end do
    call number_contact_nodes(deck%n_nodes, dom, comm, in_contact, contact_of, c%n_nodes)
    c%sort_interval = deck%contact_sort_interval
    allocate (c%eroded_elements(0), c%dead_nodes(0))
    call make_passes(deck, dom, comm, corner, contact_of, c)
    allocate (c%pair_active_cycles(deck%n_contacts), c%pair_skipped_cycles(deck%n_contacts), source=0_i8)
    allocate (c%definition_force(3, deck%n_contacts), source=0.0_wp)
  end subroutine local_contact_setup

  !> corner(1, slot): the part of each corner slot of the domain (4 (e - 1) + k for local element e,
  !> then the slots of the corners the neighbours send at shared nodes), as a real.
  subroutine corner_parts(deck, dom, comm, corner)
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    real(wp), allocatable, intent(out) :: corner(:, :)
    type(halo_t) :: halo
    integer :: r, e
    allocate (corner(1, 4 * dom%n_elements + dom%n_ghost_slots), source=0.0_wp)
    do r = 1, size(deck%element_ids)
      e = local_element(dom, deck%element_ids(r))
      corner(1, 4 * e - 3:4 * e) = real(deck%element_part(r), wp)
    end do
    call halo_setup(dom, comm, halo)
    call exchange_corners(dom, halo, corner)
  end subroutine corner_parts

  !> The contact-node id of each contact node of the domain (in_contact), from the node directory,
  !> and how many contact nodes the model has.
  subroutine number_contact_nodes(n_nodes, dom, comm, in_contact, contact_of, n_contact)
    integer, intent(in) :: n_nodes
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    logical, intent(in) :: in_contact(:)
    integer, allocatable, intent(out) :: contact_of(:)
    integer, intent(out) :: n_contact
    integer, allocatable :: nodes(:), counts(:), asked(:), asked_counts(:), mine(:), answer(:), ids(:), back(:)
    integer :: i, base, n_mine
    nodes = pack(dom%nodes, in_contact)   ! ascending: their homes too
    allocate (counts(dom%n_ranks), source=0)
    do i = 1, size(nodes)
      counts(block_owner(nodes(i), n_nodes, dom%n_ranks) + 1) = counts(block_owner(nodes(i), n_nodes, dom%n_ranks) + 1) + 1
    end do
    call exchange_int(comm, nodes, counts, asked, asked_counts)
    mine = distinct_ascending(asked)
    n_mine = size(mine)
    base = 0
    call MPI_Exscan(n_mine, base, 1, MPI_INTEGER, MPI_SUM, comm)
    if (dom%rank == 0) base = 0
    call MPI_Allreduce(n_mine, n_contact, 1, MPI_INTEGER, MPI_SUM, comm)
    allocate (answer(size(asked)))
    do i = 1, size(asked)
      answer(i) = base + sorted_position(mine, asked(i))
    end do
    call exchange_int(comm, answer, asked_counts, ids, back)
    allocate (contact_of(dom%n_nodes), source=0)
    contact_of(pack([(i, i = 1, dom%n_nodes)], in_contact)) = ids
  end subroutine number_contact_nodes

  !> The passes of every definition, with this rank's lists (see the module's notes).
  subroutine make_passes(deck, dom, comm, corner, contact_of, c)
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: corner(:, :)
    integer, intent(in) :: contact_of(:)
    type(contact_t), intent(inout) :: c
    type(deck_t) :: shell
    real(wp), allocatable :: longest(:)
    integer :: p, n_passes
    ! the deck without its mesh: the kinds give each pass its constants and empty lists
    shell = deck
    shell%n_nodes = 0
    shell%n_elements = 0
    deallocate (shell%coordinates, shell%connectivity, shell%element_part)
    allocate (shell%coordinates(3, 0), shell%connectivity(4, 0), shell%element_part(0))
    shell%contact_initial_penetration = -1   ! the overlaps come from this rank's rows (gap_overlaps)
    call definitions_passes(shell, [integer ::], 0, c%passes)
    n_passes = size(c%passes)
    allocate (longest(n_passes))
    do p = 1, n_passes
      call own_lists(deck, dom, corner, contact_of, c, p, longest(p))
    end do
    call MPI_Allreduce(MPI_IN_PLACE, longest, n_passes, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
    do p = 1, n_passes
      associate (pass => c%passes(p))
      pass%bucket_size = longest(p)
      pass%t_slave = held_thickness(deck, comm, pass%pair, pass%slave_part)
      pass%t_master = held_thickness(deck, comm, pass%pair, pass%master_part)
      deallocate (pass%overlap)
      allocate (pass%overlap(size(pass%slaves)), source=0.0_wp)
      if (deck%contact_initial_penetration(pass%pair) == initial_penetration_gap .and. &
          deck%contact_birth_time(pass%pair) == 0.0_wp) &
        call gap_overlaps(deck, dom, comm, contact_of, c, p)
      pass%gap_at_birth = deck%contact_initial_penetration(pass%pair) == initial_penetration_gap .and. &
                          deck%contact_birth_time(pass%pair) > 0.0_wp .and. .not. pass%bound   ! contact_birth_gaps
      if (pass%bound) call own_bindings(deck, dom, comm, contact_of, c, p)
      end associate
    end do
    call hold_ghost_segments(c, reshape([real(wp) ::], [segment_row_width, 0]))
  end subroutine make_passes

  !> Pass p's slaves and masters that this rank owns, the segments of its elements (ascending)
  !> with their stiffnesses, and their longest diagonal (0 without one).
  subroutine own_lists(deck, dom, corner, contact_of, c, p, longest)
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    real(wp), intent(in) :: corner(:, :)
    integer, intent(in) :: contact_of(:)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: p
    real(wp), intent(out) :: longest
    integer, allocatable :: rows(:), ids(:)
    real(wp) :: xseg(3, 4), young, poisson
    integer :: s, m, r, k4
    associate (pass => c%passes(p))
    pass%slaves = pack(contact_of, in_part(pass%slave_part) .and. dom%node_owned == 1)
    pass%own_masters = pack(contact_of, in_part(pass%master_part) .and. dom%node_owned == 1)
    pass%near_slaves = [(s, s = 1, size(pass%slaves))]
    pass%n_near = size(pass%slaves)
    rows = part_rows(deck, pass%master_part)
    ids = deck%element_ids(rows)
    call merge_sort_ascending(ids)
    allocate (pass%own_segments(4, size(rows)), pass%own_element(size(rows)), pass%own_stiffness(size(rows)))
    young = deck%young(deck%part_material(pass%master_part))
    poisson = deck%poisson(deck%part_material(pass%master_part))
    longest = 0.0_wp
    do s = 1, size(rows)
      r = rows(s)
      m = sorted_position(ids, deck%element_ids(r))
      pass%own_element(m) = deck%element_ids(r)
      pass%own_segments(:, m) = [(contact_of(sorted_position(dom%nodes, deck%connectivity(k4, r))), k4 = 1, 4)]
      xseg = deck%coordinates(:, [(node_row(deck, deck%connectivity(k4, r)), k4 = 1, 4)])
      pass%own_stiffness(m) = shell_penalty_stiffness(xseg, young, poisson, deck%contact_penalty_scale(pass%pair))
      longest = max(longest, norm2(xseg(:, 3) - xseg(:, 1)), norm2(xseg(:, 4) - xseg(:, 2)))
    end do
    end associate
  contains
    !> Whether each node of the domain has a corner of an element of part `part`.
    function in_part(part) result(on)
      integer, intent(in) :: part
      logical :: on(dom%n_nodes)
      integer :: ln, j
      on = .false.
      do ln = 1, dom%n_nodes
        do j = dom%assembly_start(ln), dom%assembly_start(ln + 1) - 1
          if (nint(corner(1, dom%assembly_slot(j))) == part) on(ln) = .true.
        end do
      end do
    end function in_part
  end subroutine own_lists

  !> Pass p's overlaps under /contact/initial_penetration = gap: each slave this rank owns against
  !> the master part's elements near it, this rank's and those of the other ranks (near_elements),
  !> at the deck's positions, as the start checks measure them (contact_checks).
  subroutine gap_overlaps(deck, dom, comm, contact_of, c, p)
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: contact_of(:)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: p
    integer, allocatable :: at(:)
    real(wp), allocatable :: push(:, :)
    type(near_set_t) :: near
    associate (pass => c%passes(p))
    call own_slaves_near(deck, dom, comm, contact_of, pass, pass%master_part, 0.5_wp * (pass%t_slave + pass%t_master), &
                         near, at)
    allocate (push(3, size(at)))
    call slave_penetrations(near%x, at, near%connectivity, pass%t_slave, pass%t_master, pass%overlap, push)
    end associate
  end subroutine gap_overlaps

  !> A bound pass p's bindings (contact_laws: a tied pass's ties) of the slaves this rank owns,
  !> against the master part's elements near them from every rank, at the deck's positions: those
  !> one rank holding the whole deck finds (the elements come in id order, and a tie goes to the
  !> lowest id among the nearest).
  subroutine own_bindings(deck, dom, comm, contact_of, c, p)
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: contact_of(:)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: p
    integer, allocatable :: at(:)
    type(near_set_t) :: near
    real(wp), allocatable :: area(:)
    associate (pass => c%passes(p))
    ! each slave's tributary area: its elements (of every rank) in id order, as on one rank
    call own_slaves_near(deck, dom, comm, contact_of, pass, pass%slave_part, 0.0_wp, near, at)
    area = tie_areas(near%x, at, near%connectivity)
    call own_slaves_near(deck, dom, comm, contact_of, pass, pass%master_part, binding_reach(pass), near, at)
    call bind_slaves(pass, near%x, at, near%connectivity, near%element_ids, area)
    end associate
  end subroutine own_bindings

  !> The elements of part `part` within margin of the pass's slaves that this rank owns, this rank's
  !> and the other ranks' (near_elements), at the deck's positions; at(s): slave s's place in near.
  subroutine own_slaves_near(deck, dom, comm, contact_of, pass, part, margin, near, at)
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: contact_of(:), part
    type(contact_pass_t), intent(in) :: pass
    real(wp), intent(in) :: margin
    type(near_set_t), intent(out) :: near
    integer, allocatable, intent(out) :: at(:)
    integer, allocatable :: rows(:), slaves(:)
    real(wp), allocatable :: slave_x(:, :)
    integer :: i
    slaves = pack(dom%nodes, contact_of > 0)
    slaves = slaves([(sorted_position(pack(contact_of, contact_of > 0), pass%slaves(i)), i = 1, size(pass%slaves))])
    slave_x = deck%coordinates(:, [(node_row(deck, slaves(i)), i = 1, size(slaves))])
    rows = part_rows(deck, part)
    call gather_near(comm, box_of(slave_x), margin, deck%element_ids(rows), &
                     deck%connectivity(:, rows), corners(deck, deck%coordinates, rows), slaves, slave_x, near)
    at = [(sorted_position(near%node_ids, slaves(i)), i = 1, size(slaves))]
  end subroutine own_slaves_near

end module contact_local_setup
