!> Contact with edge-to-edge checks (issue 35 item 2; as LS-DYNA's edge-to-edge option of its
!> automatic contacts), two members of the contact family:
!>   - edge_to_edge_t (schema name "edge_to_edge"): a node_to_segment pair (both passes, or the
!>     paper's swap) plus one edge pass: every element edge of the first part against the edges of
!>     the second's segments;
!>   - single_surface_edges_t ("single_surface_edges"): a single_surface definition plus the part's
!>     edges against its own (master edges that share a node with the slave edge are skipped).
!> Node-to-segment contact sees a node entering a face; two thin walls that cross edge against edge
!> between their nodes (a node moves more than the wall's thickness in a step) are caught by the
!> edge pass, whose law (edge_penalty) pushes the two closest points apart along their separation
!> and shares the force to the four nodes so that momentum is conserved.
!>
!> An edge pass lists each slave edge once, by its lower contact node (slaves, ascending; a node
!> that begins several edges is listed once for each) and its other node (slave_other). The global
!> search looks for the master node nearest the edge's midpoint; the local search (edge_search)
!> takes the deepest crossing among the edges of the segments around that node, and its record
!> names the slave edge's two nodes and the master edge's two (the fifth repeats the last, with no
!> force). The passes run in the replicated scheme on more than one rank (contact_is_local), where
!> every rank holds every contact node, so the records and their sum are the same on any layout.
module edge_to_edge_contact
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t
  use contact_pass, only: contact_pass_t, pass_between_parts, pass_hold_segments
  use contact_kind, only: contact_kind_t
  use contact_surfaces, only: part_nodes
  implicit none
  private
  public :: edge_to_edge_t, single_surface_edges_t, edge_pass, part_edges

  type, extends(contact_kind_t) :: edge_to_edge_t
  contains
    procedure :: pass_count => edge_to_edge_pass_count
    procedure :: make_passes => edge_to_edge_passes
  end type edge_to_edge_t

  type, extends(contact_kind_t) :: single_surface_edges_t
  contains
    procedure :: pass_count => single_surface_edges_pass_count
    procedure :: make_passes => single_surface_edges_passes
  end type single_surface_edges_t

contains

  pure integer function edge_to_edge_pass_count(self) result(n)
    class(edge_to_edge_t), intent(in) :: self
    n = 3
  end function edge_to_edge_pass_count

  !> The pair's two node-to-segment passes (as node_to_segment_contact) and the first part's edges
  !> against the second's.
  subroutine edge_to_edge_passes(self, deck, definition, contact_id, n_contact, passes)
    class(edge_to_edge_t), intent(in) :: self
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: definition, contact_id(:), n_contact
    type(contact_pass_t), intent(inout) :: passes(:)
    integer :: i
    do i = 1, 2
      call pass_between_parts(deck, definition, deck%contact_pairs(i, definition), &
                              deck%contact_pairs(3 - i, definition), contact_id, passes(i))
      passes(i)%every_cycle = deck%contact_passes(definition) == 2
      passes(i)%swap_index = i
    end do
    call edge_pass(deck, definition, deck%contact_pairs(1, definition), deck%contact_pairs(2, definition), &
                   contact_id, passes(3))
  end subroutine edge_to_edge_passes

  pure integer function single_surface_edges_pass_count(self) result(n)
    class(single_surface_edges_t), intent(in) :: self
    n = 2
  end function single_surface_edges_pass_count

  !> The part's single-surface pass (as single_surface_contact) and its edges against its own.
  subroutine single_surface_edges_passes(self, deck, definition, contact_id, n_contact, passes)
    class(single_surface_edges_t), intent(in) :: self
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: definition, contact_id(:), n_contact
    type(contact_pass_t), intent(inout) :: passes(:)
    call pass_between_parts(deck, definition, deck%contact_pairs(1, definition), deck%contact_pairs(1, definition), &
                            contact_id, passes(1))
    passes(1)%every_cycle = .true.
    call edge_pass(deck, definition, deck%contact_pairs(1, definition), deck%contact_pairs(1, definition), &
                   contact_id, passes(2))
  end subroutine single_surface_edges_passes

  !> The edge pass of slave_part's element edges against master_part's segments (the same part: a
  !> single-surface edge pass), every cycle: the pass of the two parts with its slaves replaced by
  !> the slave part's edges.
  subroutine edge_pass(deck, definition, slave_part, master_part, contact_id, pass)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: definition, slave_part, master_part, contact_id(:)
    type(contact_pass_t), intent(out) :: pass
    integer, allocatable :: nodes(:), elements(:), lower(:), upper(:), corners(:, :)
    integer :: j
    call pass_between_parts(deck, definition, slave_part, master_part, contact_id, pass)
    pass%every_cycle = .true.
    pass%edges = .true.
    call part_nodes(deck, slave_part, nodes, elements)
    corners = deck%connectivity(:, elements)
    corners = reshape(contact_id(pack(corners, .true.)), shape(corners))
    call part_edges(corners, lower, upper)
    pass%slaves = lower
    pass%slave_other = upper
    pass%near_slaves = [(j, j = 1, size(lower))]
    pass%n_near = size(lower)
    deallocate (pass%overlap)
    allocate (pass%overlap(size(lower)), source=0.0_wp)   ! an edge takes no initial gap
    pass%gap_at_birth = .false.
    call pass_hold_segments(pass)   ! the exclusions of the new slaves (their lower nodes)
  end subroutine edge_pass

  !> The distinct edges of the elements (4, n: node ids >= 1; a triangle repeats its third node, and
  !> its collapsed edge is left out), each as its lower and upper node, in ascending (lower, upper)
  !> order: the edges are binned by their lower node, and each bin's upper nodes sorted.
  pure subroutine part_edges(elements, lower, upper)
    integer, intent(in) :: elements(:, :)
    integer, allocatable, intent(out) :: lower(:), upper(:)
    integer, allocatable :: start(:), fill(:), bin(:)
    integer :: e, i, a, b, n, node, top, k
    top = maxval([0, elements])
    allocate (start(top + 1), source=0)
    do e = 1, size(elements, 2)
      do i = 1, 4
        a = elements(i, e)
        b = elements(mod(i, 4) + 1, e)
        if (a /= b) start(min(a, b) + 1) = start(min(a, b) + 1) + 1
      end do
    end do
    start(1) = 1
    do node = 2, top + 1
      start(node) = start(node) + start(node - 1)
    end do
    ! node's bin: bin(start(node) : start(node + 1) - 1)
    allocate (bin(start(top + 1) - 1))
    fill = start
    do e = 1, size(elements, 2)
      do i = 1, 4
        a = elements(i, e)
        b = elements(mod(i, 4) + 1, e)
        if (a == b) cycle
        bin(fill(min(a, b))) = max(a, b)
        fill(min(a, b)) = fill(min(a, b)) + 1
      end do
    end do
    allocate (lower(size(bin)), upper(size(bin)))
    n = 0
    do node = 1, top
      associate (list => bin(start(node):start(node + 1) - 1))
      call insertion_sort(list)
      do k = 1, size(list)
        if (k > 1) then
          if (list(k) == list(k - 1)) cycle
        end if
        n = n + 1
        lower(n) = node
        upper(n) = list(k)
      end do
      end associate
    end do
    lower = lower(1:n)
    upper = upper(1:n)
  end subroutine part_edges

  !> A short list (a node's edges) in ascending order.
  pure subroutine insertion_sort(a)
    integer, intent(inout) :: a(:)
    integer :: i, j, v
    do i = 2, size(a)
      v = a(i)
      j = i - 1
      do while (j >= 1)
        if (a(j) <= v) exit
        a(j + 1) = a(j)
        j = j - 1
      end do
      a(j + 1) = v
    end do
  end subroutine insertion_sort

end module edge_to_edge_contact
