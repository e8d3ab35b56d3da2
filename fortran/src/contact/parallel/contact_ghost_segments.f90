!> The segments a pass holds under local contact (docs/theory.md, "Dividing the contact state":
!> passes per rank): the segments of its domain's elements (contact_local_setup) and the ghost
!> segments of the last refresh of the ghosts, and from those its masters (the nodes of the
!> segments held) and each master's segments (contact_pass's pass_hold_segments). A ghost
!> segment travels with the ghosts (contact_neighbours) as one row: its pass, its element, its 4
!> contact nodes and its penalty stiffness, computed once from the deck's coordinates (the same
!> bits on every rank). The segments held are in ascending element id, so each master's segments
!> are listed in the order of one rank, and the lower segment on a tie is the same one. No MPI.
module contact_ghost_segments
  use paradyn_kinds, only: wp
  use integer_sort, only: merge_sort_ascending, sorted_position
  use contact_interface, only: contact_t
  use contact_pass, only: pass_hold_segments
  implicit none
  private
  public :: segment_row_width, segment_row, hold_ghost_segments

  integer, parameter :: segment_row_width = 7   !< pass, element, 4 contact nodes, stiffness

contains

  !> The row of own segment s of pass p, for a rank that holds it as a ghost segment.
  pure function segment_row(c, p, s) result(row)
    type(contact_t), intent(in) :: c
    integer, intent(in) :: p, s
    real(wp) :: row(segment_row_width)
    row(1) = real(p, wp)
    row(2) = real(c%passes(p)%own_element(s), wp)
    row(3:6) = real(c%passes(p)%own_segments(:, s), wp)
    row(7) = c%passes(p)%own_stiffness(s)
  end function segment_row

  !> The segments held by each pass: its own and the ghost segments received (rows of segment_row),
  !> in ascending element id, with their masters and each master's segments.
  subroutine hold_ghost_segments(c, rows)
    type(contact_t), intent(inout) :: c
    real(wp), intent(in) :: rows(:, :)
    integer, allocatable :: elements(:), nodes(:, :), sorted(:)
    real(wp), allocatable :: stiffness(:)
    integer :: p, i, n, m, j
    do p = 1, size(c%passes)
      associate (pass => c%passes(p))
      m = size(pass%own_element)
      n = m + count(nint(rows(1, :)) == p)
      allocate (elements(n), nodes(4, n), stiffness(n))
      elements(1:m) = pass%own_element
      nodes(:, 1:m) = pass%own_segments
      stiffness(1:m) = pass%own_stiffness
      do i = 1, size(rows, 2)
        if (nint(rows(1, i)) /= p) cycle
        m = m + 1
        elements(m) = nint(rows(2, i))
        nodes(:, m) = nint(rows(3:6, i))
        stiffness(m) = rows(7, i)
      end do
      sorted = elements
      call merge_sort_ascending(sorted)
      if (allocated(pass%segments)) deallocate (pass%segments, pass%segment_element, pass%stiffness)
      allocate (pass%segments(4, n), pass%segment_element(n), pass%stiffness(n))
      do i = 1, n   ! an element is a segment of a pass once: held here or sent by its own rank
        j = sorted_position(sorted, elements(i))
        pass%segments(:, j) = nodes(:, i)
        pass%segment_element(j) = elements(i)
        pass%stiffness(j) = stiffness(i)
      end do
      deallocate (elements, nodes, stiffness)
      call pass_hold_segments(pass, c%eroded_elements)   ! a ghost segment of an eroded element is dead
      end associate
    end do
  end subroutine hold_ghost_segments

end module contact_ghost_segments
