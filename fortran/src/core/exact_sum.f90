!> Exact, order-independent sums of doubles (docs/theory.md, "Parallel contact and determinism").
!>
!> An accumulator is a fixed-point integer that spans the whole double range: every finite double
!> is m 2^(s - 1074) with an integer mantissa m < 2^53 and 0 <= s <= 2045, so it is an integer
!> number of units 2^-1074 below 2^2098. The accumulator keeps that integer in limbs of 32 bits
!> (limb i counts units 2^(32 (i - 1) - 1074)), each held in a 64-bit integer so that many terms
!> add without a carry: adding a double adds its mantissa, cut at the limb boundaries, to at most
!> three limbs. Integer additions are exact and associative, so the accumulator holds the exact
!> sum of its terms whatever their order, and two accumulators (two ranks' partial sums) add limb
!> by limb to the accumulator of all their terms: an MPI_Allreduce with MPI_SUM of normalised
!> accumulators (limbs in [0, 2^32), the last signed) is exact for up to 2^31 ranks. The sum is
!> rounded to a double once, to nearest with ties to even: the correctly rounded sum of the terms.
!> NaN and infinite terms are counted apart (NaN, +inf, -inf), so they add too, and give the IEEE
!> answer (NaN for a NaN or both infinities, else the infinity). A finite sum beyond the largest
!> double rounds to an infinity of its sign.
module exact_sum
  use paradyn_kinds, only: wp, i8
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, ieee_negative_inf
  implicit none
  private
  public :: exact_width, exact_add, exact_add_all, exact_normalise, exact_value

  integer, parameter :: limb_bits = 32
  !> 2098 bits of range and 46 of headroom for carries into the last limb
  integer, parameter :: n_limbs = 67
  integer, parameter :: nan_at = n_limbs + 1, plus_inf_at = n_limbs + 2, minus_inf_at = n_limbs + 3
  integer, parameter :: adds_at = n_limbs + 4   !< terms added since the last normalisation (0 when normalised)
  !> the integers of one accumulator: limbs, the NaN and infinity counts and the add counter
  integer, parameter :: exact_width = n_limbs + 4
  integer(i8), parameter :: low_mask = 2_i8**limb_bits - 1
  !> a limb grows by less than 2^32 a term: normalising every 2^30 terms keeps it below 2^63
  integer(i8), parameter :: adds_between_normalisations = 2_i8**30

contains

  !> acc += x, exactly. acc: exact_width integers, all 0 for an empty sum.
  pure subroutine exact_add(acc, x)
    integer(i8), intent(inout) :: acc(exact_width)
    real(wp), intent(in) :: x
    integer(i8) :: bits, mantissa, lo, mid, hi
    integer :: biased, shift, limb, offset
    bits = transfer(x, 0_i8)
    biased = int(ibits(bits, 52, 11))
    mantissa = ibits(bits, 0, 52)
    if (biased == 2047) then          ! NaN or infinity
      if (mantissa /= 0) then
        acc(nan_at) = acc(nan_at) + 1
      else if (bits < 0) then
        acc(minus_inf_at) = acc(minus_inf_at) + 1
      else
        acc(plus_inf_at) = acc(plus_inf_at) + 1
      end if
      return
    end if
    if (biased > 0) mantissa = ibset(mantissa, 52)   ! normal: the hidden bit
    if (mantissa == 0) return
    shift = max(biased, 1) - 1       ! x = mantissa 2^(shift - 1074)
    limb = shift / limb_bits + 1
    offset = mod(shift, limb_bits)
    lo = iand(ishft(mantissa, offset), low_mask)
    mid = iand(ishft(mantissa, offset - limb_bits), low_mask)
    hi = ishft(mantissa, offset - 2 * limb_bits)
    if (bits < 0) then
      acc(limb) = acc(limb) - lo
      acc(limb + 1) = acc(limb + 1) - mid
      acc(limb + 2) = acc(limb + 2) - hi
    else
      acc(limb) = acc(limb) + lo
      acc(limb + 1) = acc(limb + 1) + mid
      acc(limb + 2) = acc(limb + 2) + hi
    end if
    acc(adds_at) = acc(adds_at) + 1
    if (acc(adds_at) >= adds_between_normalisations) call exact_normalise(acc)
  end subroutine exact_add

  !> acc += sum(x), exactly.
  pure subroutine exact_add_all(acc, x)
    integer(i8), intent(inout) :: acc(exact_width)
    real(wp), intent(in) :: x(:)
    integer :: i
    do i = 1, size(x)
      call exact_add(acc, x(i))
    end do
  end subroutine exact_add_all

  !> The same sum with every limb but the last in [0, 2^32) (carries moved up; the last limb
  !> carries the sign), ready to be added to other accumulators (MPI_Allreduce, MPI_SUM).
  pure subroutine exact_normalise(acc)
    integer(i8), intent(inout) :: acc(exact_width)
    integer(i8) :: carry
    integer :: i
    do i = 1, n_limbs - 1
      carry = shifta(acc(i), limb_bits)      ! floor(acc(i) / 2^32)
      acc(i) = iand(acc(i), low_mask)
      acc(i + 1) = acc(i + 1) + carry
    end do
    acc(adds_at) = 0
  end subroutine exact_normalise

  !> The sum held by acc, rounded once to the nearest double (ties to even).
  pure real(wp) function exact_value(acc_in) result(x)
    integer(i8), intent(in) :: acc_in(exact_width)
    integer(i8) :: acc(exact_width), q
    integer :: top, length, low, i, o
    logical :: negative, guard, sticky
    x = 0.0_wp
    if (acc_in(nan_at) > 0 .or. (acc_in(plus_inf_at) > 0 .and. acc_in(minus_inf_at) > 0)) then
      x = ieee_value(x, ieee_quiet_nan)
      return
    else if (acc_in(plus_inf_at) > 0) then
      x = ieee_value(x, ieee_positive_inf)
      return
    else if (acc_in(minus_inf_at) > 0) then
      x = ieee_value(x, ieee_negative_inf)
      return
    else if (all(acc_in(1:n_limbs) == 0)) then
      return
    end if
    acc = acc_in
    call exact_normalise(acc)
    negative = acc(n_limbs) < 0
    if (negative) then               ! the magnitude: negate every limb and carry again
      acc(1:n_limbs) = -acc(1:n_limbs)
      call exact_normalise(acc)
    end if
    do top = n_limbs, 1, -1
      if (acc(top) /= 0) exit
    end do
    if (top < 1) return
    ! the magnitude is an integer of `length` bits (units 2^-1074)
    length = limb_bits * (top - 1) + (bit_size(acc(top)) - leadz(acc(top)))
    if (length <= 53) then           ! exact: subnormal, or normal below 2^-1021
      q = acc(1)
      if (top == 2) q = q + ishft(acc(2), limb_bits)
      x = scale(real(q, wp), -1074)
    else                             ! the top 53 bits, from bit `low` on, then round
      low = length - 53
      i = low / limb_bits + 1
      o = mod(low, limb_bits)
      q = ishft(acc(i), -o)
      if (i + 1 <= top) q = q + ishft(acc(i + 1), limb_bits - o)
      if (i + 2 <= top) q = q + ishft(acc(i + 2), 2 * limb_bits - o)
      ! the guard bit (just below the 53) and whether any bit below it is set
      i = (low - 1) / limb_bits + 1
      o = mod(low - 1, limb_bits)
      guard = btest(acc(i), o)
      sticky = iand(acc(i), ishft(1_i8, o) - 1) /= 0 .or. any(acc(1:i - 1) /= 0)
      if (guard .and. (sticky .or. btest(q, 0))) q = q + 1   ! to nearest, ties to even
      x = scale(real(q, wp), low - 1074)
    end if
    if (negative) x = -x
  end function exact_value

end module exact_sum
