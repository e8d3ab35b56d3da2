!> Single-surface (self) contact of one part (schema name "single_surface"; the definition names
!> the part twice): the part's nodes are slave to its own shell segments, both faces, with rounded
!> edges, in one pass every cycle. A node never meets the segments that contain it, and its search
!> for the nearest master node skips its own neighbours (contact_pass); the contact thickness is
!> capped at 0.4 of the shortest edge (contact_surfaces). An all-parts automatic contact is one
!> such definition per part and a node_to_segment pair per two parts (the frontend writes them).
module single_surface_contact
  use model_deck, only: deck_t
  use contact_pass, only: contact_pass_t, pass_between_parts
  use contact_kind, only: contact_kind_t
  implicit none
  private
  public :: single_surface_t

  type, extends(contact_kind_t) :: single_surface_t
  contains
    procedure :: pass_count => single_surface_pass_count
    procedure :: make_passes => single_surface_passes
  end type single_surface_t

contains

  pure integer function single_surface_pass_count(self) result(n)
    class(single_surface_t), intent(in) :: self
    n = 1
  end function single_surface_pass_count

  subroutine single_surface_passes(self, deck, definition, contact_id, n_contact, passes)
    class(single_surface_t), intent(in) :: self
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: definition, contact_id(:), n_contact
    type(contact_pass_t), intent(inout) :: passes(:)
    call pass_between_parts(deck, definition, deck%contact_pairs(1, definition), deck%contact_pairs(1, definition), &
                            contact_id, passes(1))
    passes(1)%every_cycle = .true.
  end subroutine single_surface_passes

end module single_surface_contact
