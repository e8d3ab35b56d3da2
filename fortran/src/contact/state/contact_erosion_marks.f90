!> Eroded elements leave the contact (docs/theory.md, "Element erosion"), as in LS-DYNA: the
!> segment of an eroded element is met by no slave of any kind of contact (a tie to it is
!> released), a master node left with no live segment leaves the bucket grid, and a slave node
!> whose elements are all eroded is no longer searched: its mass stays and it flies free. The
!> lists come the same to every rank (the solver's eroded_contact shares them), so the answer
!> stays independent of the layout. No MPI.
module contact_erosion_marks
  use integer_sort, only: merge_sort_ascending
  use contact_interface, only: contact_t, contact_sort_pass
  use contact_pass, only: pass_hold_segments, pass_mark_dead_slaves
  implicit none
  private
  public :: contact_erosion_found, contact_erode

contains

  !> Elements eroded and nodes left without a live element since the last look (the same lists
  !> on every rank: global element ids, contact-node ids), for the next contact step.
  subroutine contact_erosion_found(c, new_elements, new_dead)
    type(contact_t), intent(inout) :: c
    integer, intent(in) :: new_elements(:), new_dead(:)
    if (allocated(c%eroded_pending)) then
      c%eroded_pending = [c%eroded_pending, new_elements]
      c%dead_pending = [c%dead_pending, new_dead]
    else
      c%eroded_pending = new_elements
      c%dead_pending = new_dead
    end if
  end subroutine contact_erosion_found

  !> The erosion found since the last step (contact_erosion_found) added to the contact's lists
  !> and marked in every pass: its segments and masters, its slaves, and its grid (rebuilt from
  !> the positions of the last sort without the dead masters; an idle pass rebuilds it when it
  !> wakes).
  subroutine contact_erode(c)
    type(contact_t), intent(inout) :: c
    integer :: p
    logical :: new_elements, new_dead
    if (.not. allocated(c%eroded_pending)) return
    new_elements = size(c%eroded_pending) > 0
    new_dead = size(c%dead_pending) > 0
    if (new_elements) then
      c%eroded_elements = [c%eroded_elements, c%eroded_pending]
      call merge_sort_ascending(c%eroded_elements)
    end if
    if (new_dead) then
      c%dead_nodes = [c%dead_nodes, c%dead_pending]
      call merge_sort_ascending(c%dead_nodes)
    end if
    deallocate (c%eroded_pending, c%dead_pending)
    do p = 1, size(c%passes)
      associate (pass => c%passes(p))
      if (new_elements) call pass_hold_segments(pass, c%eroded_elements)
      if (new_dead) call pass_mark_dead_slaves(pass, c%dead_nodes)
      if (new_elements .and. c%last_sort >= 0) then
        if (pass%idle) then
          pass%stale = .true.
        else
          call contact_sort_pass(c, p)
        end if
      end if
      end associate
    end do
  end subroutine contact_erode

end module contact_erosion_marks
