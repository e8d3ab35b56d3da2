!> The two-part node-to-segment penalty contact (schema name "node_to_segment"): each part of the
!> pair is slave to the other's shell segments, both passes every cycle (/contact/passes = 2) or
!> one per cycle, swapping slave and master, as in the paper (passes = 1).
module node_to_segment_contact
  use model_deck, only: deck_t
  use contact_pass, only: contact_pass_t, pass_between_parts
  use contact_kind, only: contact_kind_t
  implicit none
  private
  public :: node_to_segment_t

  type, extends(contact_kind_t) :: node_to_segment_t
  contains
    procedure :: pass_count => node_to_segment_pass_count
    procedure :: make_passes => node_to_segment_passes
  end type node_to_segment_t

contains

  pure integer function node_to_segment_pass_count(self) result(n)
    class(node_to_segment_t), intent(in) :: self
    n = 2
  end function node_to_segment_pass_count

  subroutine node_to_segment_passes(self, deck, definition, contact_id, n_contact, passes)
    class(node_to_segment_t), intent(in) :: self
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
  end subroutine node_to_segment_passes

end module node_to_segment_contact
