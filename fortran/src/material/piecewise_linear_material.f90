!> The piecewise-linear plasticity member of the material family (schema names "piecewise_linear"
!> and "piecewise_linear_rate"), as LS-DYNA's MAT_024 (*MAT_PIECEWISE_LINEAR_PLASTICITY): plane
!> stress J2 with isotropic hardening whose static yield stress is a polyline of the effective
!> plastic strain, k(eps_p), through the points (e_1, s_1) .. (e_n, s_n) (e_1 = 0, strictly
!> increasing, s non-decreasing), extrapolated along its last segment beyond e_n (a bilinear law,
!> sigma_y0 + H eps_p with H = E Et / (E - Et), is the two points (0, sigma_y0), (1, sigma_y0 + H)).
!> The flow stress is the static one times a rate factor of each point's effective strain rate
!> (j2_rate_material's rate, from the step's strain increment):
!>
!>   sigma_y = k(eps_p) R(rate),  R = 1 (rate_none), 1 + (rate / C)^(1/P) (rate_cowper_symonds),
!>   or the rate curve's factor, linear between its points and held beyond its ends (rate_tabulated).
!>
!> The return is the J2 one of plane_stress_returns (return_points: the safeguarded Newton iteration
!> on the consistency parameter, no kinematic hardening) on the segment the point's plastic strain
!> lies in, k = s_j + slope_j (eps_p - e_j): the yield function is linear in eps_p there, so the
!> return is exact on it. A point whose new plastic strain passes the segment's end returns again
!> from the same trial on the next segment (the hardening being non-negative, the yield function
!> is monotone, and the first segment whose answer stays inside it holds the answer on the curve).
!> Each point keeps one state word, its current segment (0-based, as a real), so that the yield
!> test costs one lookup; the dissipated work is the integral of k (the static curve), as j2_rate's.
module piecewise_linear_material
  use paradyn_kinds, only: wp, ek
  use material_model, only: material_t
  use plane_stress_returns, only: return_points, return_batch, half_root2
  implicit none
  private
  public :: piecewise_linear_material_t, piecewise_linear_from_curve
  public :: rate_none, rate_cowper_symonds, rate_tabulated

  integer, parameter :: rate_none = 0             !< the static curve at every rate
  integer, parameter :: rate_cowper_symonds = 1   !< 1 + (rate / C)^(1/P)
  integer, parameter :: rate_tabulated = 2        !< a curve of the factor against the strain rate

  type, extends(material_t) :: piecewise_linear_material_t
    real(wp), allocatable :: curve_strain(:), curve_stress(:)   !< the hardening curve's points
    !> per segment j (of max(n - 1, 1)): its start e_j, end (huge for the last), s_j and slope,
    !> in the kernel's kind
    real(ek), allocatable :: segment_start(:), segment_end(:), segment_stress(:), segment_slope(:)
    integer :: rate_law = rate_none
    real(wp) :: rate_c = 1.0_wp   !< Cowper-Symonds C (1/s)
    real(wp) :: rate_p = 1.0_wp   !< Cowper-Symonds P
    real(ek), allocatable :: rate_points(:), rate_factors(:)   !< the rate curve (1/s, factor)
  contains
    procedure :: update_points => piecewise_update_points
    procedure :: update_uniaxial => piecewise_update_uniaxial
    procedure :: back_stress_points => piecewise_back_points
    procedure :: has_history => piecewise_has_history
    procedure :: dissipated_work => piecewise_dissipated_work
    procedure :: state_width => piecewise_state_width
  end type piecewise_linear_material_t

contains

  !> The member from its hardening curve (strain, stress: at least one point; one point is
  !> perfect plasticity) and its rate law (rate_points, rate_factors: the rate curve, used with
  !> rate_tabulated only).
  pure function piecewise_linear_from_curve(young, poisson, strain, stress, rate_law, rate_c, rate_p, &
                                            rate_points, rate_factors) result(material)
    real(wp), intent(in) :: young, poisson, strain(:), stress(:), rate_c, rate_p, rate_points(:), rate_factors(:)
    integer, intent(in) :: rate_law
    type(piecewise_linear_material_t) :: material
    integer :: n, j, segments
    n = size(strain)
    segments = max(n - 1, 1)
    material%young = young
    material%poisson = poisson
    material%curve_strain = strain
    material%curve_stress = stress
    allocate (material%segment_start(segments), material%segment_end(segments), &
              material%segment_stress(segments), material%segment_slope(segments))
    do j = 1, segments
      material%segment_start(j) = real(strain(j), ek)
      material%segment_stress(j) = real(stress(j), ek)
      if (j < n) then
        material%segment_slope(j) = real((stress(j + 1) - stress(j)) / (strain(j + 1) - strain(j)), ek)
      else
        material%segment_slope(j) = 0.0_ek   ! one point: perfectly plastic
      end if
      material%segment_end(j) = huge(1.0_ek)
      if (j < segments) material%segment_end(j) = real(strain(j + 1), ek)
    end do
    material%rate_law = rate_law
    material%rate_c = rate_c
    material%rate_p = rate_p
    material%rate_points = real(rate_points, ek)
    material%rate_factors = real(rate_factors, ek)
  end function piecewise_linear_from_curve

  pure subroutine piecewise_update_points(self, m, dt, stress, back, eps_p, state, dstrain)
    class(piecewise_linear_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt
    real(ek), intent(inout), contiguous :: stress(:, :), back(:, :), eps_p(:), state(:, :)
    real(ek), intent(in), contiguous :: dstrain(:, :)
    real(ek) :: scale(m), young, poisson, c, shear, c1, c2, x1, x2, x3, a1, a2, a3
    real(ek), dimension(return_batch) :: a1t, a2t, a3t, ep, rel, y0, h, dgamma, s1, s2, q, reached, radius, effective
    integer :: seg(return_batch), kp(return_batch), idx(return_batch), first, nb, i, j, k, np, last
    logical :: crossed
    call rate_factors(self, m, dt, dstrain, scale)
    young = real(self%young, ek)
    poisson = real(self%poisson, ek)
    c = young / (1.0_ek - poisson**2)
    shear = young / (2.0_ek * (1.0_ek + poisson))
    c1 = young / (3.0_ek * (1.0_ek - poisson))   ! the J2 return's c1, c2 without kinematic hardening
    c2 = 2.0_ek * shear
    last = size(self%segment_start)
    associate (start => self%segment_start, finish => self%segment_end, sk => self%segment_stress, &
               slope => self%segment_slope)
      do first = 1, m, return_batch
        nb = min(return_batch, m - first + 1)
        ! elastic trial and the yield test against the segment the point is on
        do i = first, first + nb - 1
          stress(i, 1) = stress(i, 1) + c * (dstrain(i, 1) + poisson * dstrain(i, 2))
          stress(i, 2) = stress(i, 2) + c * (dstrain(i, 2) + poisson * dstrain(i, 1))
          stress(i, 3) = stress(i, 3) + c * 0.5_ek * (1.0_ek - poisson) * dstrain(i, 3)
          x1 = stress(i, 1)
          x2 = stress(i, 2)
          x3 = stress(i, 3)
          effective(i - first + 1) = sqrt(max(x1**2 - x1 * x2 + x2**2 + 3.0_ek * x3**2, 0.0_ek))
          k = min(max(int(state(i, 1)) + 1, 1), last)
          kp(i - first + 1) = k
          radius(i - first + 1) = scale(i) * (sk(k) + slope(k) * (eps_p(i) - start(k)))
        end do
        if (.not. any(effective(1:nb) > radius(1:nb))) cycle
        np = 0
        do i = first, first + nb - 1
          if (effective(i - first + 1) > radius(i - first + 1)) then
            np = np + 1
            idx(np) = i
          end if
        end do
        ! the yielding points, in the projector's eigenbasis, on their segment's line through
        ! (e_k, s_k): plastic strain relative to e_k, the line scaled by the rate factor
        do j = 1, np
          i = idx(j)
          k = kp(i - first + 1)
          seg(j) = k
          a1t(j) = (stress(i, 1) + stress(i, 2)) * half_root2
          a2t(j) = (stress(i, 2) - stress(i, 1)) * half_root2
          a3t(j) = stress(i, 3)
          ep(j) = eps_p(i)
          rel(j) = eps_p(i) - start(k)
          y0(j) = scale(i) * sk(k)
          h(j) = scale(i) * slope(k)
        end do
        call return_points(np, a1t, a2t, a3t, rel, c1, c2, y0, h, dgamma, s1, s2, q)
        crossed = .false.
        do j = 1, np   ! the plastic strain (2/3) dgamma q, q the returned von Mises stress
          reached(j) = ep(j) + dgamma(j) * (2.0_ek / 3.0_ek * q(j))
          crossed = crossed .or. reached(j) > finish(seg(j))
        end do
        if (crossed) call next_segments(self, np, a1t, a2t, a3t, ep, idx, scale, c1, c2, seg, s1, s2, reached)
        do j = 1, np
          i = idx(j)
          a1 = a1t(j) * s1(j)
          a2 = a2t(j) * s2(j)
          a3 = a3t(j) * s2(j)
          eps_p(i) = reached(j)
          stress(i, 1) = (a1 - a2) * half_root2
          stress(i, 2) = (a1 + a2) * half_root2
          stress(i, 3) = a3
          state(i, 1) = real(seg(j) - 1, ek)
        end do
      end do
    end associate
  end subroutine piecewise_update_points

  !> The uniaxial return on the curve (a bar's axial stress): on the segment k the point is on, the
  !> yield radius R (s_k + slope_k (eps_p - e_k)) is linear in eps_p, so
  !> dlambda = (|sigma_trial| - R (s_k + slope_k (eps_p - e_k))) / (E + R slope_k) exactly; a point
  !> whose eps_p + dlambda passes the segment's end returns from the same trial on the next one. R:
  !> the rate factor of the effective rate |deps| / dt (rate_factors' rate of uniaxial flow).
  pure subroutine piecewise_update_uniaxial(self, m, dt, stress, back, eps_p, state, dstrain)
    class(piecewise_linear_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt
    real(ek), intent(inout), contiguous :: stress(:), back(:), eps_p(:), state(:, :)
    real(ek), intent(in), contiguous :: dstrain(:)
    real(ek) :: scale(m), flow(m, 3), young, trial, dlambda
    integer :: i, k, last
    flow(:, 1) = dstrain(1:m)
    flow(:, 2) = -0.5_ek * dstrain(1:m)   ! uniaxial plastic flow: its effective rate is |deps| / dt
    flow(:, 3) = 0.0_ek
    call rate_factors(self, m, dt, flow, scale)
    young = real(self%young, ek)
    last = size(self%segment_start)
    associate (start => self%segment_start, finish => self%segment_end, sk => self%segment_stress, &
               slope => self%segment_slope)
      do i = 1, m
        stress(i) = stress(i) + young * dstrain(i)
        trial = abs(stress(i))
        k = min(max(int(state(i, 1)) + 1, 1), last)
        if (trial <= scale(i) * (sk(k) + slope(k) * (eps_p(i) - start(k)))) cycle
        do
          dlambda = (trial - scale(i) * (sk(k) + slope(k) * (eps_p(i) - start(k)))) / (young + scale(i) * slope(k))
          if (eps_p(i) + dlambda <= finish(k) .or. k == last) exit
          k = k + 1
        end do
        stress(i) = stress(i) - young * dlambda * sign(1.0_ek, stress(i))
        eps_p(i) = eps_p(i) + dlambda
        state(i, 1) = real(k - 1, ek)
      end do
    end associate
  end subroutine piecewise_update_uniaxial

  !> The points of a return whose new plastic strain `reached` passed the end of their segment:
  !> each returns again from the same trial on the next segment, until none passes (the rare case:
  !> a step across a break point). seg, s1, s2 (the return's factors 1 / (1 + dgamma c)) and
  !> reached end as each point's final ones.
  pure subroutine next_segments(self, np, a1t, a2t, a3t, ep, idx, scale, c1, c2, seg, s1, s2, reached)
    class(piecewise_linear_material_t), intent(in) :: self
    integer, intent(in) :: np, idx(:)
    real(ek), intent(in) :: a1t(:), a2t(:), a3t(:), ep(:), scale(:), c1, c2
    integer, intent(inout) :: seg(:)
    real(ek), intent(inout) :: s1(:), s2(:), reached(:)
    real(ek), dimension(return_batch) :: qa1, qa2, qa3, rel, y0, h, dg, f1, f2, qv
    integer :: list(return_batch), nq, q, j, pass, kept
    nq = 0
    do j = 1, np
      if (reached(j) > self%segment_end(seg(j))) then
        nq = nq + 1
        list(nq) = j
      end if
    end do
    do pass = 1, size(self%segment_start)
      do q = 1, nq
        j = list(q)
        seg(j) = seg(j) + 1
        qa1(q) = a1t(j)
        qa2(q) = a2t(j)
        qa3(q) = a3t(j)
        rel(q) = ep(j) - self%segment_start(seg(j))
        y0(q) = scale(idx(j)) * self%segment_stress(seg(j))
        h(q) = scale(idx(j)) * self%segment_slope(seg(j))
      end do
      call return_points(nq, qa1, qa2, qa3, rel, c1, c2, y0, h, dg, f1, f2, qv)
      kept = 0
      do q = 1, nq
        j = list(q)
        s1(j) = f1(q)
        s2(j) = f2(q)
        reached(j) = ep(j) + dg(q) * (2.0_ek / 3.0_ek * qv(q))
        if (reached(j) > self%segment_end(seg(j))) then   ! past this one too: again on the next
          kept = kept + 1
          list(kept) = j
        end if
      end do
      nq = kept
      if (nq == 0) exit
    end do
  end subroutine next_segments

  !> scale(1:m): each point's rate factor from its effective strain rate over the step (1 without
  !> a rate law, or without a step)
  pure subroutine rate_factors(self, m, dt, dstrain, scale)
    class(piecewise_linear_material_t), intent(in) :: self
    integer, intent(in) :: m
    real(ek), intent(in) :: dt, dstrain(:, :)
    real(ek), intent(out) :: scale(:)
    real(ek) :: rate(m), inverse_dt, inverse_c, exponent, t
    integer :: i, j, q, n
    if (self%rate_law == rate_none) then
      scale(1:m) = 1.0_ek
      return
    end if
    inverse_dt = merge(1.0_ek / dt, 0.0_ek, dt > 0.0_ek)
    do i = 1, m
      rate(i) = sqrt(max(4.0_ek / 3.0_ek * (dstrain(i, 1)**2 + dstrain(i, 2)**2 + dstrain(i, 1) * dstrain(i, 2)) &
                         + dstrain(i, 3)**2 / 3.0_ek, 0.0_ek)) * inverse_dt
    end do
    if (self%rate_law == rate_cowper_symonds) then
      inverse_c = real(1.0_wp / self%rate_c, ek)
      exponent = real(1.0_wp / self%rate_p, ek)
      do i = 1, m
        scale(i) = 1.0_ek + (rate(i) * inverse_c)**exponent   ! 0**x = 0: at rest, the static curve
      end do
      return
    end if
    n = size(self%rate_points)
    if (n == 1) then
      scale(1:m) = self%rate_factors(1)
      return
    end if
    do i = 1, m
      j = 1
      do q = 2, n - 1
        j = j + merge(1, 0, rate(i) >= self%rate_points(q))
      end do
      t = (rate(i) - self%rate_points(j)) / (self%rate_points(j + 1) - self%rate_points(j))
      t = min(max(t, 0.0_ek), 1.0_ek)
      scale(i) = self%rate_factors(j) + t * (self%rate_factors(j + 1) - self%rate_factors(j))
    end do
  end subroutine rate_factors

  pure integer function piecewise_back_points(self, nip) result(points)
    class(piecewise_linear_material_t), intent(in) :: self
    integer, intent(in) :: nip
    points = 0   ! isotropic hardening: the back stress stays zero, unstored (back is not used)
  end function piecewise_back_points

  pure logical function piecewise_has_history(self) result(changes)
    class(piecewise_linear_material_t), intent(in) :: self
    changes = .true.
  end function piecewise_has_history

  pure integer function piecewise_state_width(self) result(width)
    class(piecewise_linear_material_t), intent(in) :: self
    width = 1   ! the segment of the curve each point's plastic strain is on
  end function piecewise_state_width

  !> The integral of the static curve k over [0, eps_p]: exact for the polyline (with its
  !> extrapolation), summed segment by segment.
  pure subroutine piecewise_dissipated_work(self, eps_p, work)
    class(piecewise_linear_material_t), intent(in) :: self
    real(wp), intent(in) :: eps_p(:, :)
    real(wp), intent(out) :: work(:, :)
    real(wp) :: e, total, lo, hi, s, slope
    integer :: i, k, j, n
    n = size(self%curve_strain)
    do k = 1, size(eps_p, 2)
      do i = 1, size(eps_p, 1)
        e = eps_p(i, k)
        total = 0.0_wp
        do j = 1, max(n - 1, 1)
          lo = self%curve_strain(j)
          hi = e
          if (j < n - 1) hi = min(e, self%curve_strain(j + 1))
          if (hi <= lo) exit
          s = self%curve_stress(j)
          slope = 0.0_wp
          if (n > 1) slope = (self%curve_stress(j + 1) - s) / (self%curve_strain(j + 1) - lo)
          total = total + (hi - lo) * (s + 0.5_wp * slope * (hi - lo))
        end do
        work(i, k) = total
      end do
    end do
  end subroutine piecewise_dissipated_work

end module piecewise_linear_material
