!> The contact surface of a part: its nodes and shell segments, and the thickness the contact
!> gives it. A single-surface (self) contact caps the thickness at 0.4 of the part's shortest
!> element edge, as LS-DYNA does for its single-surface contacts: a node's own neighbours then lie
!> beyond the contact's reach however thick the shell, so a smooth surface never touches itself.
module contact_surfaces
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t
  use paradyn_schema, only: contact_kind_single_surface
  implicit none
  private
  public :: part_nodes, contact_thickness, self_thickness_cap

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

  !> The thickness of part `part` in contact definition `definition`: the shell's thickness, capped
  !> at self_thickness_cap times the part's shortest element edge (at the deck's positions) when the
  !> definition is single_surface.
  real(wp) function contact_thickness(deck, definition, part) result(t)
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: definition, part
    integer :: e, k
    real(wp) :: shortest
    t = deck%thickness(part)
    if (deck%contact_kind(definition) /= contact_kind_single_surface) return
    shortest = huge(1.0_wp)
    do e = 1, deck%n_elements
      if (deck%element_part(e) /= part) cycle
      do k = 1, 4
        shortest = min(shortest, norm2(deck%coordinates(:, deck%connectivity(k, e)) &
                                       - deck%coordinates(:, deck%connectivity(modulo(k, 4) + 1, e))))
      end do
    end do
    t = min(t, self_thickness_cap * shortest)
  end function contact_thickness

end module contact_surfaces
