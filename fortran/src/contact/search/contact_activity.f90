!> Whether a contact pass can touch before the next activity check, and when that check falls
!> (docs/theory.md, idle pairs). At a check each side of a pass (its slave nodes, its master
!> nodes) is summed up by an extent: the axis-aligned bounding box of its nodes, their largest
!> speed and their largest change of velocity over the last cycle. Extents are stored as maxima
!> only ([-lower, upper, speed^2, change^2]), so the ranks' extents of their own nodes combine
!> with one maximum reduction, exact in any order: the decision is the same on every layout.
!>
!> A pass is idle for the next n cycles when its two boxes, each grown by safety_factor times
!> what its nodes cover in n cycles at the present speed and acceleration (v n dt + a (n dt)^2 / 2),
!> stay farther apart than the margin (the caller gives the sum of the two thicknesses: a node
!> touches a segment only within half of it). The factor allows speeds and accelerations to
!> double before the next check; the check comes again at the latest after max_idle_cycles.
!>
!> Pure: no MPI, no I/O, no module state.
module contact_activity
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: extent_width, extent_empty, side_extent, idle_cycles
  public :: safety_factor, max_idle_cycles, active_recheck_cycles

  integer, parameter :: extent_width = 8           !< -lower(3), upper(3), speed^2, velocity change^2
  real(wp), parameter :: safety_factor = 2.0_wp    !< speeds and accelerations may double before the next check
  integer, parameter :: max_idle_cycles = 1000     !< the longest time between two checks
  integer, parameter :: active_recheck_cycles = 50 !< an active pass is looked at again after this

contains

  !> The extent of no node: every entry at its smallest, so any node's entry is larger.
  pure function extent_empty() result(extent)
    real(wp) :: extent(extent_width)
    extent = -huge(1.0_wp)
  end function extent_empty

  !> Add the nodes at local columns `columns` of x and v (the rank's own nodes of a side) to
  !> extent; v_before(:, column) is the node's velocity a cycle earlier.
  pure subroutine side_extent(columns, x, v, v_before, extent)
    integer, intent(in) :: columns(:)
    real(wp), intent(in) :: x(:, :), v(:, :), v_before(:, :)
    real(wp), intent(inout) :: extent(extent_width)
    integer :: i, j
    do i = 1, size(columns)
      j = columns(i)
      extent(1:3) = max(extent(1:3), -x(:, j))
      extent(4:6) = max(extent(4:6), x(:, j))
      extent(7) = max(extent(7), v(1, j)**2 + v(2, j)**2 + v(3, j)**2)
      extent(8) = max(extent(8), (v(1, j) - v_before(1, j))**2 + (v(2, j) - v_before(2, j))**2 &
                                 + (v(3, j) - v_before(3, j))**2)
    end do
  end subroutine side_extent

  !> The cycles, from this one, during which the sides of a pass (their extents over all ranks)
  !> cannot come within margin of each other: 0 if they may now, else at most max_idle_cycles. An
  !> empty side can touch nothing. In n cycles the sides close at most by
  !> safety_factor (b n + a n^2), b = (v_s + v_m) dt, a = (dv_s + dv_m) dt / 2.
  pure integer function idle_cycles(slave, master, margin, dt) result(n)
    real(wp), intent(in) :: slave(extent_width), master(extent_width), margin, dt
    real(wp) :: gap, a, b, allowed
    if (slave(7) < 0.0_wp .or. master(7) < 0.0_wp) then
      n = max_idle_cycles
      return
    end if
    ! the widest separation of the boxes along an axis (negative where they overlap on all)
    gap = maxval(max(-master(1:3) - slave(4:6), -slave(1:3) - master(4:6))) - margin
    b = safety_factor * (sqrt(slave(7)) + sqrt(master(7))) * dt
    a = safety_factor * 0.5_wp * (sqrt(slave(8)) + sqrt(master(8))) * dt
    if (.not. (gap > a + b)) then
      n = 0
    else if (gap >= real(max_idle_cycles, wp) * (b + a * real(max_idle_cycles, wp))) then
      n = max_idle_cycles
    else if (a > 0.0_wp) then
      ! the positive root of a n^2 + b n = gap, written to avoid cancellation
      allowed = 2.0_wp * gap / (b + sqrt(b * b + 4.0_wp * a * gap))
      n = max(1, min(max_idle_cycles, int(allowed)))
    else
      n = max(1, min(max_idle_cycles, int(gap / b)))
    end if
  end function idle_cycles

end module contact_activity
