!> The room of the contact's per-candidate arrays (issue 19, item 5): the global search's
!> nearest masters and pairs, the shared pairs of the replicated scheme, and the candidates with
!> their records. One rank and the replicated scheme make room for every slave of every pass; a
!> rank under local contact for the slaves it owns, and the records it receives get room as they
!> come (contact_neighbours), so no rank holds arrays for every slave of the model. No MPI.
module contact_room
  use paradyn_kinds, only: wp
  use contact_interface, only: contact_t
  use contact_pass, only: pass_near_lists
  implicit none
  private
  public :: contact_rooms, contact_search_room, contact_record_room

contains

  !> The rooms of the global search, the records and the near lists: for every slave of every
  !> pass, or under local contact (c%local, after contact_neighbours has kept the pass's own
  !> slaves alone) for this rank's own slaves.
  subroutine contact_rooms(c)
    type(contact_t), intent(inout) :: c
    integer :: p, n_slaves
    n_slaves = 1 + sum([(size(c%passes(p)%slaves), p = 1, size(c%passes))])
    call contact_search_room(c, n_slaves, merge(0, n_slaves, c%local))
    do p = 1, size(c%passes)
      call pass_near_lists(c%passes(p))
    end do
  end subroutine contact_rooms

  !> Room for the global search of n_search slaves (their nearest masters and pairs) and for
  !> n_shared pairs shared by every rank (the replicated scheme; 0 otherwise), and records for
  !> n_search candidates: every slave of every pass on one rank and in the replicated scheme, a
  !> rank's own slaves under local contact (whose records it receives are made room for as they
  !> come, contact_record_room), so that no rank fills more than it uses.
  subroutine contact_search_room(c, n_search, n_shared)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: n_search, n_shared
    allocate (c%nearest(n_search), c%own_pairs(3, n_search), source=0)
    allocate (c%all_pairs(3, n_shared), c%pass_pairs(2, n_shared), source=0)
    call contact_record_room(c, n_search)
  end subroutine contact_search_room

  !> Candidates and records for at least n: at set-up, cleared; grown (a half more than asked, so
  !> that a growing contact reallocates seldom), neither cleared nor kept: the caller writes the
  !> first n, and no stage reads past n_candidates, so only the room used is ever touched.
  subroutine contact_record_room(c, n)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: n
    integer :: room
    if (allocated(c%candidates)) then
      if (size(c%candidates, 2) >= n) return
      room = max(n, size(c%candidates, 2) + size(c%candidates, 2) / 2)
      deallocate (c%candidates, c%record_nodes, c%record_force, c%record_penetration, c%record_failed)
      allocate (c%candidates(3, room), c%record_nodes(5, room), c%record_force(3, 5, room), c%record_penetration(room))
      allocate (c%record_failed(room))
    else
      allocate (c%candidates(3, n), c%record_nodes(5, n), source=0)
      allocate (c%record_force(3, 5, n), c%record_penetration(n), source=0.0_wp)
      allocate (c%record_failed(n), source=.false.)
    end if
  end subroutine contact_record_room

end module contact_room
