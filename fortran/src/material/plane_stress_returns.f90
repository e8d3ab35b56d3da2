!> Material laws at one integration point, in plane stress, and their array forms across many
!> points (point index first) that the element kernel vectorises.
!>
!> J2 plasticity with linear combined isotropic/kinematic hardening and a radial return that
!> satisfies the plane-stress condition exactly (Simo & Taylor 1986; Simo & Hughes,
!> Computational Inelasticity, 1998, sec. 3.4). Stress vectors are (sxx, syy, sxy).
!> The laws compute in the element kernel's kind ek (core/kinds.f90): single in the mixed engine.
module plane_stress_returns
  use paradyn_kinds, only: wp, ek, i8
  implicit none
  private
  public :: elastic_plane_stress_update, j2_plane_stress_update, von_mises_plane_stress
  public :: elastic_plane_stress_update_points, j2_plane_stress_update_points
  public :: j2_kinematic_modulus, return_points, return_batch, j2_radial_update_points

  !> points per pass of j2_plane_stress_update_points (one element group's worth): fixed-size
  !> local arrays, no allocation
  integer, parameter :: batch = 64
  integer, parameter :: return_batch = batch   !< the most points return_points takes per call
  !> the return's stopping tests: |g| (return_points' relative residual) below g_tolerance, or a
  !> bracket closed to bracket_tolerance of its upper end. 1e-13 and 1e-15 in double; single precision (the mixed
  !> engine) cannot reach those, so there they are a few times the kind's epsilon (1.2e-7)
  real(ek), parameter :: g_tolerance = max(1.0e-13_ek, 100 * epsilon(1.0_ek))
  real(ek), parameter :: bracket_tolerance = max(1.0e-15_ek, 4 * epsilon(1.0_ek))

contains

  !> Linear elastic plane-stress increment: stress += C * dstrain (dstrain has engineering shear).
  pure subroutine elastic_plane_stress_update(stress, dstrain, young, poisson)
    real(ek), intent(inout) :: stress(3)
    real(ek), intent(in) :: dstrain(3), young, poisson
    real(ek) :: c
    c = young / (1.0_ek - poisson**2)
    stress(1) = stress(1) + c * (dstrain(1) + poisson * dstrain(2))
    stress(2) = stress(2) + c * (dstrain(2) + poisson * dstrain(1))
    stress(3) = stress(3) + c * 0.5_ek * (1.0_ek - poisson) * dstrain(3)
  end subroutine elastic_plane_stress_update

  pure real(ek) function von_mises_plane_stress(s) result(vm)
    real(ek), intent(in) :: s(3)
    vm = sqrt(max(s(1)**2 - s(1) * s(2) + s(2)**2 + 3.0_ek * s(3)**2, 0.0_ek))
  end function von_mises_plane_stress

  !> Kinematic hardening modulus (1 - beta) H, H = E Et / (E - Et): zero for perfect plasticity
  !> and for purely isotropic hardening, where the back stress never leaves zero.
  pure real(wp) function j2_kinematic_modulus(young, tangent, beta) result(h_kin)
    real(wp), intent(in) :: young, tangent, beta
    h_kin = (1.0_wp - beta) * (young * tangent / (young - tangent))
  end function j2_kinematic_modulus

  !> Plane-stress J2 return mapping with combined hardening.
  !>
  !> Plastic modulus H = E Et / (E - Et); isotropic part beta*H, kinematic part (1-beta)*H.
  !> Flow eps_p' = dgamma P xi, back stress alpha' = (2/3) h_kin dgamma xi, xi = sigma - alpha.
  !> The return is solved in the eigenbasis of the plane-stress projector P, where the update is
  !> diagonal, for the consistency parameter dgamma by safeguarded Newton iteration.
  pure subroutine j2_plane_stress_update(stress, back, eps_p, dstrain, young, poisson, &
                                         yield0, tangent, beta)
    real(ek), intent(inout) :: stress(3), back(3), eps_p
    real(ek), intent(in) :: dstrain(3), young, poisson, yield0, tangent, beta
    real(ek) :: h, h_iso, h_kin, shear, c1, c2, a1t, a2t, a3t, psi_trial, q0, k0
    real(ek) :: dgamma, lo, hi, f, df, psi, s1, s2, a1, a2, a3
    real(ek) :: xi(3)
    integer :: iter

    call elastic_plane_stress_update(stress, dstrain, young, poisson)
    xi = stress - back
    h = young * tangent / (young - tangent)
    h_iso = beta * h
    h_kin = (1.0_ek - beta) * h
    k0 = yield0 + h_iso * eps_p
    if (von_mises_plane_stress(xi) <= k0) return

    shear = young / (2.0_ek * (1.0_ek + poisson))
    c1 = young / (3.0_ek * (1.0_ek - poisson)) + 2.0_ek * h_kin / 3.0_ek
    c2 = 2.0_ek * shear + 2.0_ek * h_kin / 3.0_ek
    a1t = (xi(1) + xi(2)) / sqrt(2.0_ek)
    a2t = (xi(2) - xi(1)) / sqrt(2.0_ek)
    a3t = xi(3)
    psi_trial = a1t**2 / 3.0_ek + a2t**2 + 2.0_ek * a3t**2

    q0 = sqrt(1.5_ek * psi_trial)

    ! g(dgamma) = k0 / q + (2/3) H_iso dgamma - 1 rises from g(0) < 0 (return_points)
    lo = 0.0_ek
    hi = upper_bound(q0, k0, min(c1, c2))
    ! Newton's first step from 0, from the trial alone (return_points)
    dgamma = (q0 - k0) / (k0 * (a1t**2 / 3.0_ek * c1 + (a2t**2 + 2.0_ek * a3t**2) * c2) / psi_trial &
                          + 2.0_ek / 3.0_ek * h_iso * q0)
    do iter = 1, 100
      call evaluate(dgamma, f, df)
      if (f < 0.0_ek) then
        lo = dgamma
      else
        hi = dgamma
      end if
      if (abs(f) <= g_tolerance) exit
      dgamma = dgamma - f / df
      if (dgamma <= lo .or. dgamma >= hi .or. df <= 0.0_ek) dgamma = 0.5_ek * (lo + hi)
      if (hi - lo <= bracket_tolerance * hi) exit
    end do

    s1 = 1.0_ek / (1.0_ek + dgamma * c1)
    s2 = 1.0_ek / (1.0_ek + dgamma * c2)
    a1 = a1t * s1
    a2 = a2t * s2
    a3 = a3t * s2
    psi = a1**2 / 3.0_ek + a2**2 + 2.0_ek * a3**2
    xi(1) = (a1 - a2) / sqrt(2.0_ek)
    xi(2) = (a1 + a2) / sqrt(2.0_ek)
    xi(3) = a3
    ! back stress moves along the relative stress, (2/3) h_kin dgamma xi (Simo & Hughes, Box 3.3):
    ! under uniaxial stress it stays uniaxial and the plastic modulus is h_kin
    back = back + 2.0_ek / 3.0_ek * h_kin * dgamma * xi
    eps_p = eps_p + dgamma * sqrt(2.0_ek * psi / 3.0_ek)
    stress = xi + back

  contains

    pure subroutine evaluate(dg, fv, dfv)
      real(ek), intent(in) :: dg
      real(ek), intent(out) :: fv, dfv
      real(ek), parameter :: third = 1.0_ek / 3.0_ek
      real(ek) :: t1, t2, u1, u2, r12, p, dp, w
      ! one division for both factors 1 / (1 + dg c) (yield_functions)
      u1 = 1.0_ek + dg * c1
      u2 = 1.0_ek + dg * c2
      r12 = 1.0_ek / (u1 * u2)
      t1 = r12 * u2
      t2 = r12 * u1
      p = (a1t * t1)**2 * third + (a2t**2 + 2.0_ek * a3t**2) * t2**2
      dp = -2.0_ek * ((a1t * t1)**2 * third * c1 * t1 + (a2t**2 + 2.0_ek * a3t**2) * t2**2 * c2 * t2)
      w = 1.0_ek / sqrt(1.5_ek * p)
      fv = k0 * w + 2.0_ek * third * h_iso * dg - 1.0_ek
      dfv = -0.75_ek * k0 * dp * w**3 + 2.0_ek * third * h_iso
    end subroutine evaluate

  end subroutine j2_plane_stress_update

  !> elastic_plane_stress_update for points 1..m of arrays laid out point first (stress(:, 1:3))
  pure subroutine elastic_plane_stress_update_points(m, stress, dstrain, young, poisson)
    integer, intent(in) :: m
    real(ek), intent(inout), contiguous :: stress(:, :)
    real(ek), intent(in), contiguous :: dstrain(:, :)
    real(ek), intent(in) :: young, poisson
    real(ek) :: c
    integer :: i
    c = young / (1.0_ek - poisson**2)
    do i = 1, m
      stress(i, 1) = stress(i, 1) + c * (dstrain(i, 1) + poisson * dstrain(i, 2))
      stress(i, 2) = stress(i, 2) + c * (dstrain(i, 2) + poisson * dstrain(i, 1))
      stress(i, 3) = stress(i, 3) + c * 0.5_ek * (1.0_ek - poisson) * dstrain(i, 3)
    end do
  end subroutine elastic_plane_stress_update_points

  !> j2_plane_stress_update for points 1..m of arrays laid out point first (stress(:, 1:3)), with
  !> the same algorithm vectorised across the points: the elastic trial runs on every point, the
  !> yielding ones are gathered and returned together (return_points). A point's arithmetic does
  !> not depend on the other points or on its position in the arrays. yield_scale(1:m), when
  !> given, scales each point's yield radius sigma_y0 + beta H eps_p (a rate law: its member
  !> computes the factor from the point's strain rate); absent, every factor is 1 exactly.
  pure subroutine j2_plane_stress_update_points(m, stress, back, eps_p, dstrain, young, poisson, &
                                                yield0, tangent, beta, yield_scale)
    integer, intent(in) :: m
    real(ek), intent(inout), contiguous :: stress(:, :), back(:, :), eps_p(:)
    real(ek), intent(in), contiguous :: dstrain(:, :)
    real(ek), intent(in) :: young, poisson, yield0, tangent, beta
    real(ek), intent(in), optional :: yield_scale(:)
    real(ek), parameter :: root2 = sqrt(2.0_ek)
    real(ek) :: c, h, h_iso, h_kin, shear, c1, c2, s1, s2, a1, a2, a3, psi, x1, x2, x3
    real(ek) :: a1t(batch), a2t(batch), a3t(batch), ep(batch), dgamma(batch)
    real(ek) :: y0p(batch), hp(batch), y0t(batch), ht(batch)   !< each point's sigma_y0 and beta H
    real(ek) :: effective(batch)   !< the trial's von Mises stress relative to the back stress
    logical :: yielding(batch)
    integer :: idx(batch), first, nb, i, j, np

    c = young / (1.0_ek - poisson**2)
    h = young * tangent / (young - tangent)
    h_iso = beta * h
    h_kin = (1.0_ek - beta) * h
    shear = young / (2.0_ek * (1.0_ek + poisson))
    c1 = young / (3.0_ek * (1.0_ek - poisson)) + 2.0_ek * h_kin / 3.0_ek
    c2 = 2.0_ek * shear + 2.0_ek * h_kin / 3.0_ek
    ! loop bodies use scalars only: a small array such as xi(3) inside stops the vectoriser
    do first = 1, m, batch
      nb = min(batch, m - first + 1)
      ! elastic trial and yield test on every point (elastic_plane_stress_update, von_mises_plane_stress);
      ! the radius is sigma_y0 + beta H eps_p, times the point's factor where one is given
      do i = first, first + nb - 1
        stress(i, 1) = stress(i, 1) + c * (dstrain(i, 1) + poisson * dstrain(i, 2))
        stress(i, 2) = stress(i, 2) + c * (dstrain(i, 2) + poisson * dstrain(i, 1))
        stress(i, 3) = stress(i, 3) + c * 0.5_ek * (1.0_ek - poisson) * dstrain(i, 3)
        x1 = stress(i, 1) - back(i, 1)
        x2 = stress(i, 2) - back(i, 2)
        x3 = stress(i, 3) - back(i, 3)
        ! (a NaN does not yield here, where the scalar version would iterate on it)
        effective(i - first + 1) = sqrt(max(x1**2 - x1 * x2 + x2**2 + 3.0_ek * x3**2, 0.0_ek))
      end do
      if (present(yield_scale)) then
        y0p(1:nb) = yield0 * yield_scale(first:first + nb - 1)
        hp(1:nb) = h_iso * yield_scale(first:first + nb - 1)
        yielding(1:nb) = effective(1:nb) > y0p(1:nb) + hp(1:nb) * eps_p(first:first + nb - 1)
      else
        yielding(1:nb) = effective(1:nb) > yield0 + h_iso * eps_p(first:first + nb - 1)
      end if
      if (.not. any(yielding(1:nb))) cycle   ! most batches stay elastic: no gather, no return
      ! gather the yielding points: trial relative stress in the eigenbasis of the projector P
      np = 0
      do i = first, first + nb - 1
        if (yielding(i - first + 1)) then
          np = np + 1
          idx(np) = i
        end if
      end do
      if (np == 0) cycle
      do j = 1, np
        x1 = stress(idx(j), 1) - back(idx(j), 1)
        x2 = stress(idx(j), 2) - back(idx(j), 2)
        a1t(j) = (x1 + x2) / root2
        a2t(j) = (x2 - x1) / root2
        a3t(j) = stress(idx(j), 3) - back(idx(j), 3)
        ep(j) = eps_p(idx(j))
      end do
      if (present(yield_scale)) then
        y0t(1:np) = y0p(idx(1:np) - first + 1)
        ht(1:np) = hp(idx(1:np) - first + 1)
      else
        y0t(1:np) = yield0
        ht(1:np) = h_iso
      end if
      call return_points(np, a1t, a2t, a3t, ep, c1, c2, y0t, ht, dgamma)
      ! the returned state, in the compact arrays, then scattered back
      do j = 1, np
        s1 = 1.0_ek / (1.0_ek + dgamma(j) * c1)
        s2 = 1.0_ek / (1.0_ek + dgamma(j) * c2)
        a1 = a1t(j) * s1
        a2 = a2t(j) * s2
        a3 = a3t(j) * s2
        psi = a1**2 / 3.0_ek + a2**2 + 2.0_ek * a3**2
        ep(j) = ep(j) + dgamma(j) * sqrt(2.0_ek * psi / 3.0_ek)
        ! xi, kept in a1t, a2t, a3t
        a1t(j) = (a1 - a2) / root2
        a2t(j) = (a1 + a2) / root2
        a3t(j) = a3
        dgamma(j) = 2.0_ek / 3.0_ek * h_kin * dgamma(j)
      end do
      do j = 1, np
        i = idx(j)
        back(i, 1) = back(i, 1) + dgamma(j) * a1t(j)
        back(i, 2) = back(i, 2) + dgamma(j) * a2t(j)
        back(i, 3) = back(i, 3) + dgamma(j) * a3t(j)
        eps_p(i) = ep(j)
        stress(i, 1) = a1t(j) + back(i, 1)
        stress(i, 2) = a2t(j) + back(i, 2)
        stress(i, 3) = a3t(j) + back(i, 3)
      end do
    end do
  end subroutine j2_plane_stress_update_points

  !> The radial return without the plane-stress iteration, at points 1..m laid out as
  !> j2_plane_stress_update_points': the elastic trial; a point whose relative stress xi = s - alpha
  !> lies outside the yield radius k = sigma_y0 + beta H eps_p gets the plastic strain of the 3-D
  !> radial return, d_eps_p = (|xi| - k) / (3 G + H) (|.| von Mises, H = E Et / (E - Et)), and its
  !> relative stress scaled onto the hardened radius, xi k' / |xi|, k' = k + beta H d_eps_p; the
  !> back stress moves by (1 - beta) H d_eps_p xi / |xi|. The plane-stress condition is not iterated
  !> (the trial's through-thickness strain stays elastic): the cheaper return of explicit codes
  !> (OpenRadioss's shell default, Iplas = 2), a model choice beside the exact return above.
  pure subroutine j2_radial_update_points(m, stress, back, eps_p, dstrain, young, poisson, yield0, tangent, beta)
    integer, intent(in) :: m
    real(ek), intent(inout), contiguous :: stress(:, :), back(:, :), eps_p(:)
    real(ek), intent(in), contiguous :: dstrain(:, :)
    real(ek), intent(in) :: young, poisson, yield0, tangent, beta
    real(ek) :: c, h, h_iso, h_kin, shear, x1, x2, x3, effective, radius, d_eps, scale, shift
    integer :: i
    c = young / (1.0_ek - poisson**2)
    h = young * tangent / (young - tangent)
    h_iso = beta * h
    h_kin = (1.0_ek - beta) * h
    shear = young / (2.0_ek * (1.0_ek + poisson))
    do i = 1, m
      stress(i, 1) = stress(i, 1) + c * (dstrain(i, 1) + poisson * dstrain(i, 2))
      stress(i, 2) = stress(i, 2) + c * (dstrain(i, 2) + poisson * dstrain(i, 1))
      stress(i, 3) = stress(i, 3) + c * 0.5_ek * (1.0_ek - poisson) * dstrain(i, 3)
      x1 = stress(i, 1) - back(i, 1)
      x2 = stress(i, 2) - back(i, 2)
      x3 = stress(i, 3) - back(i, 3)
      effective = sqrt(max(x1**2 - x1 * x2 + x2**2 + 3.0_ek * x3**2, 0.0_ek))
      radius = yield0 + h_iso * eps_p(i)
      d_eps = merge((effective - radius) / (3.0_ek * shear + h), 0.0_ek, effective > radius)
      scale = merge((radius + h_iso * d_eps) / merge(effective, 1.0_ek, effective > radius), 1.0_ek, &
                    effective > radius)
      shift = merge(h_kin * d_eps / merge(effective, 1.0_ek, effective > radius), 0.0_ek, effective > radius)
      back(i, 1) = back(i, 1) + shift * x1
      back(i, 2) = back(i, 2) + shift * x2
      back(i, 3) = back(i, 3) + shift * x3
      stress(i, 1) = scale * x1 + back(i, 1)
      stress(i, 2) = scale * x2 + back(i, 2)
      stress(i, 3) = scale * x3 + back(i, 3)
      eps_p(i) = eps_p(i) + d_eps
    end do
  end subroutine j2_radial_update_points

  !> Consistency parameter dgamma of np <= batch yielding points: the safeguarded Newton iteration
  !> of j2_plane_stress_update in lockstep. Masks freeze a point once it meets its own stopping
  !> test, so it ends where it would alone, and the loops over points have no exits.
  !> merge selects only between operands already computed: an operation that only one branch
  !> needs is moved into that branch, which the vectoriser then cannot if-convert (it may trap).
  !>
  !> The residual is g(dgamma) = k0 / q + (2/3) H_iso dgamma - 1, with k0 = sigma_y0 + H_iso eps_p
  !> and q the von Mises stress of the returned relative stress: zero where q equals the hardened
  !> radius k0 + H_iso d_eps_p (Simo & Hughes's f = psi / 2 - sy^2 / 3 = 0, divided through).
  !> 1 / q is linear in dgamma for a deviatoric trial (q = q0 / (1 + dgamma c2)) and nearly so
  !> otherwise, so Newton from 0 meets the tolerance in 2-4 steps where f took 4-6 after a bracket
  !> search (more for large steps); the first step comes from the trial without an evaluation.
  !> g rises with dgamma; upper_bound gives a point where g >= 0.
  pure subroutine return_points(np, a1t, a2t, a3t, eps_p, c1, c2, yield0, h_iso, dgamma)
    integer, intent(in) :: np
    real(ek), intent(in) :: a1t(np), a2t(np), a3t(np), eps_p(np), c1, c2, yield0(np), h_iso(np)
    real(ek), intent(out) :: dgamma(np)
    real(ek) :: lo(batch), hi(batch), k0(batch), g(batch), dg(batch), newton, bisection, part1, part2, q0, slope
    ! 1 while a point iterates: 64-bit flags, as GCC 12 cannot select doubles by a logical array
    integer(i8) :: active(batch)
    integer :: iter, j

    ! g(0) < 0 (the point yields) and Newton's first step from 0, from the trial alone: there
    ! 1/q = 1/q0 and d(1/q)/d(dgamma) = c/q0, c the mean of c1, c2 weighted by the trial's parts
    do j = 1, np
      k0(j) = yield0(j) + h_iso(j) * eps_p(j)
      part1 = a1t(j)**2 / 3.0_ek
      part2 = a2t(j)**2 + 2.0_ek * a3t(j)**2
      q0 = sqrt(1.5_ek * (part1 + part2))
      hi(j) = upper_bound(q0, k0(j), min(c1, c2))
      slope = k0(j) * (part1 * c1 + part2 * c2) / max(part1 + part2, tiny(1.0_ek)) + 2.0_ek / 3.0_ek * h_iso(j) * q0
      dgamma(j) = max(q0 - k0(j), 0.0_ek) / max(slope, tiny(1.0_ek))
      active(j) = merge(1_i8, 0_i8, q0 > k0(j))   ! a point inside its radius keeps dgamma = 0
    end do
    lo(1:np) = 0.0_ek
    do iter = 1, 100
      call yield_functions(np, a1t, a2t, a3t, k0, c1, c2, h_iso, dgamma, g, dg)
      ! one comparison per merge, so that the loop if-converts and vectorises; lo and hi of a
      ! frozen point may move, its dgamma does not
      do j = 1, np
        lo(j) = merge(dgamma(j), lo(j), g(j) < 0.0_ek)
        hi(j) = merge(hi(j), dgamma(j), g(j) < 0.0_ek)
        ! Newton's step, or bisection where it leaves the bracket
        bisection = 0.5_ek * (lo(j) + hi(j))
        newton = dgamma(j) - g(j) / dg(j)
        newton = merge(bisection, newton, newton <= lo(j))
        newton = merge(bisection, newton, newton >= hi(j))
        newton = merge(bisection, newton, dg(j) <= 0.0_ek)
        ! stop on a small |g| keeping dgamma, or on a closed bracket after the step
        newton = merge(dgamma(j), newton, abs(g(j)) <= g_tolerance)
        dgamma(j) = merge(newton, dgamma(j), active(j) == 1)
        active(j) = merge(0_i8, active(j), abs(g(j)) <= g_tolerance)
        active(j) = merge(0_i8, active(j), hi(j) - lo(j) <= bracket_tolerance * hi(j))
      end do
      if (all(active(1:np) == 0)) exit
    end do
  end subroutine return_points

  !> A dgamma where the residual g >= 0: q <= q0 / (1 + dgamma min(c1, c2)), so g >= 0 from
  !> (q0 / k0 - 1) / min(c1, c2) on (twice that, so that Newton's last steps never touch it);
  !> without a positive radius k0, no bound (the iteration's own bracket takes over).
  pure real(ek) function upper_bound(q0, k0, c_min) result(hi)
    real(ek), intent(in) :: q0, k0, c_min
    hi = merge(2.0_ek * (q0 / max(k0, tiny(1.0_ek)) - 1.0_ek) / c_min, huge(1.0_ek), k0 > 0.0_ek)
  end function upper_bound

  !> g(dgamma) = k0 / q + (2/3) H_iso dgamma - 1 and its derivative at np points (the evaluate
  !> of j2_plane_stress_update, the same operations); one loop, vectorised. The iteration is
  !> bound by division throughput: both factors 1 / (1 + dg c) come from one division of their
  !> product, and the thirds are products with 1/3.
  pure subroutine yield_functions(np, a1t, a2t, a3t, k0, c1, c2, h_iso, dg, gv, dgv)
    integer, intent(in) :: np
    real(ek), intent(in) :: a1t(np), a2t(np), a3t(np), k0(np), c1, c2, h_iso(np), dg(np)
    real(ek), intent(out) :: gv(np), dgv(np)
    real(ek), parameter :: third = 1.0_ek / 3.0_ek
    real(ek) :: t1, t2, u1, u2, r12, p, dp, w
    integer :: j
    do j = 1, np
      u1 = 1.0_ek + dg(j) * c1
      u2 = 1.0_ek + dg(j) * c2
      r12 = 1.0_ek / (u1 * u2)
      t1 = r12 * u2
      t2 = r12 * u1
      p = (a1t(j) * t1)**2 * third + (a2t(j)**2 + 2.0_ek * a3t(j)**2) * t2**2
      dp = -2.0_ek * ((a1t(j) * t1)**2 * third * c1 * t1 + (a2t(j)**2 + 2.0_ek * a3t(j)**2) * t2**2 * c2 * t2)
      w = 1.0_ek / sqrt(1.5_ek * p)
      gv(j) = k0(j) * w + 2.0_ek * third * h_iso(j) * dg(j) - 1.0_ek
      dgv(j) = -0.75_ek * k0(j) * dp * w**3 + 2.0_ek * third * h_iso(j)
    end do
  end subroutine yield_functions

end module plane_stress_returns
