!> The local search of edge-to-edge contact (edge_to_edge_contact): for a slave edge, the edges of
!> the master segments around its nearest master node, and the crossing among them that is deepest
!> inside the two half thicknesses (edge_penalty's law with unit stiffness). An edge shared by two
!> segments is met twice with the same answer; the first (the lower segment, then the lower
!> corner) is kept, so the choice does not depend on the order of the threads. Master edges with a
!> node of the slave edge are skipped (they meet it at that node: single-surface passes), as are a
!> triangle's collapsed edge.
!>
!> Pure: no MPI, no I/O, no module state.
module edge_search
  use paradyn_kinds, only: wp
  use edge_penalty, only: edge_edge_force, closest_points_of_edges
  implicit none
  private
  public :: deepest_edge_crossing

contains

  !> The slave edge from x(:, a1) to x(:, a2) (columns of x) against the edges of the segments
  !> segment_list(first:last) (columns of segment_at: their nodes' columns of x): best_segment (0:
  !> no crossing within reach) and best_corner, the master edge from corner best_corner to the next
  !> one (4 to 1), with its penetration.
  pure subroutine deepest_edge_crossing(x, a1, a2, segment_at, segment_list, first, last, t_a, t_b, &
                                        best_segment, best_corner, penetration, clearance)
    real(wp), intent(in) :: x(:, :), t_a, t_b
    integer, intent(in) :: a1, a2, segment_at(:, :), segment_list(:), first, last
    integer, intent(out) :: best_segment, best_corner
    real(wp), intent(out) :: penetration
    !> the least distance of the slave edge to the master edges met, less the reach (t_a + t_b) / 2:
    !> where positive no edge met can touch until the edges have closed by that much
    real(wp), intent(out) :: clearance
    real(wp) :: force(3, 4), depth, s, u
    logical :: touching
    integer :: j, i, b1, b2, segment
    best_segment = 0
    best_corner = 0
    penetration = 0.0_wp
    clearance = huge(1.0_wp)
    do j = first, last
      segment = segment_list(j)
      do i = 1, 4
        b1 = segment_at(i, segment)
        b2 = segment_at(mod(i, 4) + 1, segment)
        if (b1 == b2 .or. b1 == a1 .or. b1 == a2 .or. b2 == a1 .or. b2 == a2) cycle
        call closest_points_of_edges(x(:, a1), x(:, a2), x(:, b1), x(:, b2), s, u)
        clearance = min(clearance, norm2(x(:, a1) + s * (x(:, a2) - x(:, a1)) - x(:, b1) - u * (x(:, b2) - x(:, b1))) &
                                   - 0.5_wp * (t_a + t_b))
        call edge_edge_force(x(:, a1), x(:, a2), x(:, b1), x(:, b2), t_a, t_b, 1.0_wp, force, depth, touching)
        if (.not. touching) cycle
        if (depth > penetration) then
          penetration = depth
          best_segment = segment
          best_corner = i
        end if
      end do
    end do
  end subroutine deepest_edge_crossing

end module edge_search
