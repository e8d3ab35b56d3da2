!> Load curves (LS-DYNA *DEFINE_CURVE): piecewise linear in time between their points, the first
!> value held before the first time and the last value held after the last time. Holding the last
!> value (rather than extrapolating) lets a load whose curve ended at zero stop costing anything.
module load_curves
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: load_curves_t, load_curves_from, curve_value, curve_ended_at_zero, curve_point_range

  !> Every curve of a deck: curve k is points first(k) .. first(k + 1) - 1 (first has n + 1 entries).
  type :: load_curves_t
    integer :: n = 0
    integer, allocatable :: first(:)
    real(wp), allocatable :: time(:), value(:)
  end type load_curves_t

contains

  !> The curves of a deck: first_point (1-based) of each curve, and all points' times and values.
  pure function load_curves_from(first_point, time, value) result(c)
    integer, intent(in) :: first_point(:)
    real(wp), intent(in) :: time(:), value(:)
    type(load_curves_t) :: c
    c%n = size(first_point)
    c%first = [first_point, size(time) + 1]
    c%time = time
    c%value = value
  end function load_curves_from

  !> First and last point of curve k.
  pure subroutine curve_point_range(c, k, first, last)
    type(load_curves_t), intent(in) :: c
    integer, intent(in) :: k
    integer, intent(out) :: first, last
    first = c%first(k)
    last = c%first(k + 1) - 1
  end subroutine curve_point_range

  !> Curve k at time t: linear between the two points around t, held outside the curve's times.
  pure real(wp) function curve_value(c, k, t) result(y)
    type(load_curves_t), intent(in) :: c
    integer, intent(in) :: k
    real(wp), intent(in) :: t
    integer :: lo, hi, mid
    call curve_point_range(c, k, lo, hi)
    if (t <= c%time(lo)) then
      y = c%value(lo)
      return
    end if
    if (t >= c%time(hi)) then
      y = c%value(hi)
      return
    end if
    do while (hi - lo > 1)   ! bisection: time(lo) < t < time(hi)
      mid = (lo + hi) / 2
      if (c%time(mid) <= t) then
        lo = mid
      else
        hi = mid
      end if
    end do
    y = c%value(lo) + (c%value(hi) - c%value(lo)) * ((t - c%time(lo)) / (c%time(hi) - c%time(lo)))
  end function curve_value

  !> Whether curve k has ended at time t with a last value of zero (it stays zero from then on).
  pure logical function curve_ended_at_zero(c, k, t) result(ended)
    type(load_curves_t), intent(in) :: c
    integer, intent(in) :: k
    real(wp), intent(in) :: t
    integer :: last
    last = c%first(k + 1) - 1
    ended = t >= c%time(last) .and. c%value(last) == 0.0_wp
  end function curve_ended_at_zero

end module load_curves
