!> Makes a member of the contact family from its schema name. Adding a member: its module, a case
!> here, and its name in the schema.
module contact_factory
  use contact_kind, only: contact_kind_t
  use node_to_segment_contact, only: node_to_segment_t
  use paradyn_schema, only: deck_enums, enum_contact_kind
  implicit none
  private
  public :: contact_kind_from_name, contact_kind_name_of_code

contains

  !> The member named name; not allocated for an unknown name.
  subroutine contact_kind_from_name(name, kind)
    character(len=*), intent(in) :: name
    class(contact_kind_t), allocatable, intent(out) :: kind
    select case (name)
    case ('node_to_segment')
      allocate (node_to_segment_t :: kind)
    end select
  end subroutine contact_kind_from_name

  !> The schema name of a /contact/kind code (schema/deck.toml), '' for an unknown code.
  pure function contact_kind_name_of_code(code) result(name)
    integer, intent(in) :: code
    character(len=:), allocatable :: name
    integer :: k
    name = ''
    associate (members => deck_enums(enum_contact_kind))
      do k = 1, members%n_members
        if (members%codes(k) == code) name = trim(members%names(k))
      end do
    end associate
  end function contact_kind_name_of_code

end module contact_factory
