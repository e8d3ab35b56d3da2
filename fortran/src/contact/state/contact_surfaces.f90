!> The contact surface of a part: its nodes and shell segments, and the thickness the contact
!> gives it. A single-surface (self) contact caps the thickness at 0.4 of the part's shortest
!> element edge, as LS-DYNA does for its single-surface contacts: a node's own neighbours then lie
!> beyond the contact's reach however thick the shell, so a smooth surface never touches itself.
module contact_surfaces
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t
  use paradyn_schema, only: contact_kind_is_self_contact
  implicit none
  private
  public :: part_nodes, contact_thickness, self_thickness_cap, capped_thickness, shortest_edge, scaled_thickness

  !> The thickness of a single-surface contact is at most this fraction of the shortest edge.
  real(wp), parameter :: self_thickness_cap = 0.4_wp

contains

  !> The nodes of a part and its elements (global ids, ascending).
  subroutine part_nodes(deck, part, nodes, elements)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: part
    integer, allocatable, intent(out) :: nodes(:), elements(:)
    logical, allocatable :: on_part(:)
    integer :: e
    elements = pack([(e, e = 1, deck%n_elements)], deck%element_part == part)
    allocate (on_part(deck%n_nodes), source=.false.)
    do e = 1, size(elements)
      on_part(deck%connectivity(:, elements(e))) = .true.
    end do
    nodes = pack([(e, e = 1, deck%n_nodes)], on_part)
  end subroutine part_nodes

  !> The thickness of part `part` in contact definition `definition`: the shell's thickness times
  !> the definition's scale for that side (scaled_thickness), capped at self_thickness_cap times the
  !> part's shortest element edge (at the deck's positions) when the definition is single_surface.
  real(wp) function contact_thickness(deck, definition, part) result(t)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: definition, part
    t = scaled_thickness(deck, definition, part)
    if (contact_kind_is_self_contact(deck%contact_kind(definition))) &
      t = capped_thickness(t, shortest_edge(deck%coordinates, deck%connectivity, deck%element_part, part))
  end function contact_thickness

  !> The shell thickness of part `part` times /contact/thickness_scale of definition `definition`
  !> for the side the part is on (LS-DYNA SFST for the first part, SFMT for the second; a
  !> single-surface definition names its part twice and takes the first). A scale of 1 leaves the
  !> thickness as it is, bitwise.
  pure real(wp) function scaled_thickness(deck, definition, part) result(t)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: definition, part
    integer :: side
    side = merge(1, 2, part == deck%contact_pairs(1, definition))
    t = deck%thickness(part) * deck%contact_thickness_scale(side, definition)
  end function scaled_thickness

  !> A single-surface contact's thickness: at most self_thickness_cap times the shortest edge.
  pure real(wp) function capped_thickness(thickness, shortest) result(t)
    real(wp), intent(in) :: thickness, shortest
    t = min(thickness, self_thickness_cap * shortest)
  end function capped_thickness

  !> The shortest element edge of part `part` (huge without an element): connectivity(:, e) are
  !> columns of x.
  pure real(wp) function shortest_edge(x, connectivity, element_part, part) result(shortest)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: connectivity(:, :), element_part(:), part
    integer :: e, k
    shortest = huge(1.0_wp)
    do e = 1, size(connectivity, 2)
      if (element_part(e) /= part) cycle
      do k = 1, 4
        shortest = min(shortest, norm2(x(:, connectivity(k, e)) - x(:, connectivity(modulo(k, 4) + 1, e))))
      end do
    end do
  end function shortest_edge

end module contact_surfaces
