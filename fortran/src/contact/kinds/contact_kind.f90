!> The contact family: a kind of contact turns one contact definition of the deck into the passes
!> that the parallel search runs (slave nodes against master segments). Members:
!> node_to_segment_contact, single_surface_contact; contact_factory makes one from its schema name.
module contact_kind
  use model_deck, only: deck_t
  use contact_pass, only: contact_pass_t
  implicit none
  private
  public :: contact_kind_t, contact_kind_holder_t

  type, abstract :: contact_kind_t
  contains
    !> How many passes a definition of this kind gives
    procedure(pass_count_interface), deferred :: pass_count
    !> The passes of definition `definition` of the deck (contact_id: the contact-node id of
    !> each global node, n_contact of them)
    procedure(make_passes_interface), deferred :: make_passes
  end type contact_kind_t

  !> One member, for arrays of kinds
  type :: contact_kind_holder_t
    class(contact_kind_t), allocatable :: kind
  end type contact_kind_holder_t

  abstract interface
    pure integer function pass_count_interface(self) result(n)
      import :: contact_kind_t
      class(contact_kind_t), intent(in) :: self
    end function pass_count_interface

    subroutine make_passes_interface(self, deck, definition, contact_id, n_contact, passes)
      import :: contact_kind_t, deck_t, contact_pass_t
      class(contact_kind_t), intent(in) :: self
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: definition, contact_id(:), n_contact
      type(contact_pass_t), intent(inout) :: passes(:)
    end subroutine make_passes_interface
  end interface

end module contact_kind
