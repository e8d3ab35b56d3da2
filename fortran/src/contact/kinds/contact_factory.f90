!> Makes a member of the contact family from its schema name. Adding a member: its module, a case
!> here, and its name in the schema.
module contact_factory
  use contact_kind, only: contact_kind_t
  use node_to_segment_contact, only: node_to_segment_t
  use single_surface_contact, only: single_surface_t
  use tied_contact, only: tied_t
  use tiebreak_contact, only: tiebreak_t
  use edge_to_edge_contact, only: edge_to_edge_t, single_surface_edges_t
  implicit none
  private
  public :: contact_kind_from_name

contains

  !> The member named name; not allocated for an unknown name.
  subroutine contact_kind_from_name(name, kind)
    character(len=*), intent(in) :: name
    class(contact_kind_t), allocatable, intent(out) :: kind
    select case (name)
    case ('node_to_segment')
      allocate (node_to_segment_t :: kind)
    case ('single_surface')
      allocate (single_surface_t :: kind)
    case ('tied')
      allocate (tied_t :: kind)
    case ('tiebreak')
      allocate (tiebreak_t :: kind)
    case ('edge_to_edge')
      allocate (edge_to_edge_t :: kind)
    case ('single_surface_edges')
      allocate (single_surface_edges_t :: kind)
    end select
  end subroutine contact_kind_from_name

end module contact_factory
