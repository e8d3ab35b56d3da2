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
  public :: half_root2

  !> points per pass of j2_plane_stress_update_points (one element group's worth): fixed-size
  !> local arrays, no allocation
  integer, parameter :: batch = 64
  integer, parameter :: return_batch = batch   !< the most points return_points takes per call
  !> the eigenbasis of the plane-stress projector: (sxx, syy) turned by 45 degrees
  real(ek), parameter :: half_root2 = sqrt(0.5_ek)
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
      ! one division for both factors 1 / (1 + dg c)
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
  !> The return is bound by division and root throughput: the yield test compares squares, the
  !> constant factors are products, and the update takes its factors from the return's last
  !> evaluation (one division in all after it).
  pure subroutine j2_plane_stress_update_points(m, stress, back, eps_p, dstrain, young, poisson, &
                                                yield0, tangent, beta, yield_scale)
    integer, intent(in) :: m
    real(ek), intent(inout), contiguous :: stress(:, :), back(:, :), eps_p(:)
    real(ek), intent(in), contiguous :: dstrain(:, :)
    real(ek), intent(in) :: young, poisson, yield0, tangent, beta
    real(ek), intent(in), optional :: yield_scale(:)
    real(ek) :: c, h, h_iso, h_kin, shear, c1, c2, x1, x2, x3, shift, d_eps
    real(ek) :: a1t(batch), a2t(batch), a3t(batch), ep(batch), dgamma(batch), s1(batch), s2(batch), q(batch)
    real(ek) :: y0p(batch), hp(batch), y0t(batch), ht(batch)   !< each point's sigma_y0 and beta H
    !> the trial's squared von Mises stress relative to the back stress, and the squared yield radius
    real(ek) :: effective2(batch), radius2(batch)
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
      ! the radius is sigma_y0 + beta H eps_p (> 0), times the point's factor where one is given
      do i = first, first + nb - 1
        stress(i, 1) = stress(i, 1) + c * (dstrain(i, 1) + poisson * dstrain(i, 2))
        stress(i, 2) = stress(i, 2) + c * (dstrain(i, 2) + poisson * dstrain(i, 1))
        stress(i, 3) = stress(i, 3) + c * 0.5_ek * (1.0_ek - poisson) * dstrain(i, 3)
        x1 = stress(i, 1) - back(i, 1)
        x2 = stress(i, 2) - back(i, 2)
        x3 = stress(i, 3) - back(i, 3)
        ! (a NaN does not yield here, where the scalar version would iterate on it)
        effective2(i - first + 1) = x1**2 - x1 * x2 + x2**2 + 3.0_ek * x3**2
        ! the trial relative stress in the eigenbasis of the projector P
        a1t(i - first + 1) = (x1 + x2) * half_root2
        a2t(i - first + 1) = (x2 - x1) * half_root2
        a3t(i - first + 1) = x3
      end do
      if (present(yield_scale)) then
        y0p(1:nb) = yield0 * yield_scale(first:first + nb - 1)
        hp(1:nb) = h_iso * yield_scale(first:first + nb - 1)
      else
        y0p(1:nb) = yield0
        hp(1:nb) = h_iso
      end if
      radius2(1:nb) = (y0p(1:nb) + hp(1:nb) * eps_p(first:first + nb - 1))**2
      np = count(effective2(1:nb) > radius2(1:nb))
      if (np == 0) cycle   ! most batches stay elastic: no gather, no return
      if (2 * np > nb) then
        ! most points yield: the whole batch returns in place, the elastic points (whose trial
        ! is inside the radius, kappa >= 1) stay at dgamma = 0 and are not written back
        call return_points(nb, a1t, a2t, a3t, eps_p(first:first + nb - 1), c1, c2, y0p, hp, dgamma, s1, s2, q)
        do j = 1, nb
          i = first + j - 1
          call returned_state(a1t(j), a2t(j), a3t(j), s1(j), s2(j), q(j), dgamma(j), h_kin, x1, x2, x3, shift, d_eps)
          eps_p(i) = merge(eps_p(i) + d_eps, eps_p(i), effective2(j) > radius2(j))
          back(i, 1) = merge(back(i, 1) + shift * x1, back(i, 1), effective2(j) > radius2(j))
          back(i, 2) = merge(back(i, 2) + shift * x2, back(i, 2), effective2(j) > radius2(j))
          back(i, 3) = merge(back(i, 3) + shift * x3, back(i, 3), effective2(j) > radius2(j))
          stress(i, 1) = merge(x1 + back(i, 1), stress(i, 1), effective2(j) > radius2(j))
          stress(i, 2) = merge(x2 + back(i, 2), stress(i, 2), effective2(j) > radius2(j))
          stress(i, 3) = merge(x3 + back(i, 3), stress(i, 3), effective2(j) > radius2(j))
        end do
        cycle
      end if
      ! a few points yield: gathered (in place, to the front), returned together and scattered back
      np = 0
      do i = first, first + nb - 1
        if (effective2(i - first + 1) > radius2(i - first + 1)) then
          np = np + 1
          idx(np) = i
        end if
      end do
      do j = 1, np   ! (j <= i - first + 1: each point moves down, none is overwritten first)
        i = idx(j)
        a1t(j) = a1t(i - first + 1)
        a2t(j) = a2t(i - first + 1)
        a3t(j) = a3t(i - first + 1)
        ep(j) = eps_p(i)
        y0t(j) = y0p(i - first + 1)
        ht(j) = hp(i - first + 1)
      end do
      call return_points(np, a1t, a2t, a3t, ep, c1, c2, y0t, ht, dgamma, s1, s2, q)
      do j = 1, np
        i = idx(j)
        call returned_state(a1t(j), a2t(j), a3t(j), s1(j), s2(j), q(j), dgamma(j), h_kin, x1, x2, x3, shift, d_eps)
        eps_p(i) = ep(j) + d_eps
        back(i, 1) = back(i, 1) + shift * x1
        back(i, 2) = back(i, 2) + shift * x2
        back(i, 3) = back(i, 3) + shift * x3
        stress(i, 1) = x1 + back(i, 1)
        stress(i, 2) = x2 + back(i, 2)
        stress(i, 3) = x3 + back(i, 3)
      end do
    end do
  end subroutine j2_plane_stress_update_points

  !> A returned point's relative stress xi = (x1, x2, x3) (the trial's eigen-components a times
  !> the return's factors, turned back), its plastic strain d_eps = (2/3) dgamma q (Simo & Hughes's
  !> dgamma sqrt(2 psi / 3)) and its back stress's move shift xi, shift = (2/3) h_kin dgamma.
  pure subroutine returned_state(a1t, a2t, a3t, s1, s2, q, dgamma, h_kin, x1, x2, x3, shift, d_eps)
    real(ek), intent(in) :: a1t, a2t, a3t, s1, s2, q, dgamma, h_kin
    real(ek), intent(out) :: x1, x2, x3, shift, d_eps
    real(ek) :: a1, a2
    a1 = a1t * s1
    a2 = a2t * s2
    x1 = (a1 - a2) * half_root2
    x2 = (a1 + a2) * half_root2
    x3 = a3t * s2
    d_eps = dgamma * (2.0_ek / 3.0_ek * q)
    shift = 2.0_ek / 3.0_ek * h_kin * dgamma
  end subroutine returned_state

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

  !> Consistency parameter dgamma of np <= batch points (a point inside its radius keeps 0): the
  !> safeguarded Newton iteration of j2_plane_stress_update in lockstep, and the factors of the
  !> returned state at it:
  !> s1 = 1 / (1 + dgamma c1), s2 = 1 / (1 + dgamma c2) (the eigen-components of the returned
  !> relative stress are the trial's times s1, s2, s2) and q, its von Mises stress. Masks freeze a
  !> point once it meets its own stopping test, so it ends where it would alone, and the loops over
  !> points have no exits.
  !>
  !> The residual is g(dgamma) = k0 / q + (2/3) H_iso dgamma - 1, with k0 = sigma_y0 + H_iso eps_p
  !> and q the von Mises stress of the returned relative stress: zero where q equals the hardened
  !> radius k0 + H_iso d_eps_p (Simo & Hughes's f = psi / 2 - sy^2 / 3 = 0, divided through).
  !> 1 / q is linear in dgamma for a deviatoric trial (q = q0 / (1 + dgamma c2)) and nearly so
  !> otherwise, so Newton from 0 meets the tolerance in 2-4 steps; the first step comes from the
  !> trial without an evaluation. g rises with dgamma; its root lies below
  !> 2 (q0 / k0 - 1) / min(c1, c2), where q0 / (1 + dgamma min(c1, c2)) >= q has fallen to k0
  !> (twice that, so that Newton's last steps never touch it).
  !>
  !> Each evaluation takes one root and one division: with u = 1 + dgamma c, U = u1 u2 and the
  !> trial's parts a = (a1t / q0)^2 / 2, b = 3 ((a2t / q0)^2 / 2 + (a3t / q0)^2) (a + b = 1),
  !> q = q0 sqrt(P) / U with P = a u2^2 + b u1^2, so g sqrt(P) = kappa U + ((2/3) H_iso dgamma - 1)
  !> sqrt(P) (kappa = k0 / q0) carries g's sign and its size, and Newton's step
  !> g / g' = g sqrt(P) P / (kappa ((c1 u2 + c2 u1) P - U (a c2 u2 + b c1 u1)) + (2/3) H_iso P sqrt(P)).
  !> Scaled by q0 the numbers stay near 1 in single precision too. A point stops on a small |g| or a
  !> closed bracket at a point it evaluated, whose U and sqrt(P) give the factors.
  pure subroutine return_points(np, a1t, a2t, a3t, eps_p, c1, c2, yield0, h_iso, dgamma, s1, s2, q)
    integer, intent(in) :: np
    real(ek), intent(in) :: a1t(np), a2t(np), a3t(np), eps_p(np), c1, c2, yield0(np), h_iso(np)
    real(ek), intent(out) :: dgamma(np), s1(np), s2(np), q(np)
    real(ek), dimension(batch) :: lo, hi, pa, pb, kappa, hh, q0, uu, root_p
    real(ek) :: g(batch)   !< g sqrt(P) at each point's last evaluation
    real(ek) :: span, inverse, slope, kept, k0
    ! 1 while a point iterates: 64-bit flags, as GCC 12 cannot select doubles by a logical array
    integer(i8) :: active(batch)
    integer :: iter, j

    span = 2.0_ek / min(c1, c2)
    ! the trial scaled by its von Mises stress q0 (by the radius k0 where that is larger: a point
    ! inside it, which a whole batch's return carries along, stays finite with kappa = 1), the
    ! first step and the bracket, with one division for both: dgamma_1 = (1 - kappa) / g'(0) and
    ! the bound span (1 - kappa) / kappa
    do j = 1, np
      q0(j) = sqrt(0.5_ek * a1t(j)**2 + 1.5_ek * a2t(j)**2 + 3.0_ek * a3t(j)**2)
      k0 = yield0(j) + h_iso(j) * eps_p(j)
      inverse = 1.0_ek / max(q0(j), k0, tiny(1.0_ek))
      pa(j) = 0.5_ek * (a1t(j) * inverse)**2
      pb(j) = 1.5_ek * (a2t(j) * inverse)**2 + 3.0_ek * (a3t(j) * inverse)**2
      kappa(j) = k0 * inverse
      hh(j) = 2.0_ek / 3.0_ek * h_iso(j)
      slope = max(kappa(j) * (pa(j) * c1 + pb(j) * c2) + hh(j), tiny(1.0_ek))
      kept = merge(kappa(j), 1.0_ek, kappa(j) > 0.0_ek)
      inverse = 1.0_ek / (kept * slope)
      dgamma(j) = max(1.0_ek - kappa(j), 0.0_ek) * kept * inverse
      hi(j) = merge(span * max(1.0_ek - kappa(j), 0.0_ek) * slope * inverse, huge(1.0_ek), kappa(j) > 0.0_ek)
      active(j) = merge(1_i8, 0_i8, kappa(j) < 1.0_ek)   ! a point inside its radius keeps dgamma = 0
      uu(j) = 1.0_ek
      root_p(j) = 1.0_ek   ! sqrt(a + b): a point that never iterates returns with q = q0
    end do
    ! the first three evaluations of every point in registers (most points stop at the third),
    ! then the points still iterating step and evaluate in lockstep over the arrays: the same
    ! steps in the same order. A point steps only after an evaluation that did not stop it.
    do j = 1, np   ! the calls written out (a counted loop here stops the vectoriser), inlined
      ! (fortran/CMakeLists.txt)
      lo(j) = 0.0_ek
      call evaluate(pa(j), pb(j), kappa(j), hh(j), c1, c2, dgamma(j), lo(j), hi(j), active(j), uu(j), root_p(j), g(j))
      call newton_step(pa(j), pb(j), kappa(j), hh(j), c1, c2, g(j), root_p(j), lo(j), hi(j), active(j), dgamma(j))
      call evaluate(pa(j), pb(j), kappa(j), hh(j), c1, c2, dgamma(j), lo(j), hi(j), active(j), uu(j), root_p(j), g(j))
      call newton_step(pa(j), pb(j), kappa(j), hh(j), c1, c2, g(j), root_p(j), lo(j), hi(j), active(j), dgamma(j))
      call evaluate(pa(j), pb(j), kappa(j), hh(j), c1, c2, dgamma(j), lo(j), hi(j), active(j), uu(j), root_p(j), g(j))
    end do
    do iter = 4, 100
      if (all(active(1:np) == 0)) exit
      do j = 1, np
        call newton_step(pa(j), pb(j), kappa(j), hh(j), c1, c2, g(j), root_p(j), lo(j), hi(j), active(j), dgamma(j))
        call evaluate(pa(j), pb(j), kappa(j), hh(j), c1, c2, dgamma(j), lo(j), hi(j), active(j), uu(j), root_p(j), g(j))
      end do
    end do
    do j = 1, np
      inverse = 1.0_ek / uu(j)
      s1(j) = (1.0_ek + dgamma(j) * c2) * inverse
      s2(j) = (1.0_ek + dgamma(j) * c1) * inverse
      q(j) = q0(j) * root_p(j) * inverse
    end do
  end subroutine return_points

  !> One evaluation of return_points' residual at a point, on scalars so that a loop over points
  !> keeps them in registers: g sqrt(P) (gp), the bracket [lo, hi] moved to the evaluated dgamma;
  !> an active point records the evaluation's U and sqrt(P) and stops there on a small |g| or a
  !> closed bracket. One comparison per merge, so that the loop if-converts and vectorises; lo and
  !> hi of a frozen point may move, its dgamma and factors do not.
  pure subroutine evaluate(pa, pb, kappa, hh, c1, c2, dgamma, lo, hi, active, uu, root_p, gp)
    real(ek), intent(in) :: pa, pb, kappa, hh, c1, c2, dgamma
    real(ek), intent(inout) :: lo, hi, uu, root_p
    integer(i8), intent(inout) :: active
    real(ek), intent(out) :: gp
    real(ek) :: u1, u2, rp
    u1 = 1.0_ek + dgamma * c1
    u2 = 1.0_ek + dgamma * c2
    rp = sqrt(pa * u2**2 + pb * u1**2)
    gp = kappa * (u1 * u2) + (hh * dgamma - 1.0_ek) * rp
    uu = merge(u1 * u2, uu, active == 1)
    root_p = merge(rp, root_p, active == 1)
    lo = merge(dgamma, lo, gp < 0.0_ek)
    hi = merge(hi, dgamma, gp < 0.0_ek)
    active = merge(0_i8, active, abs(gp) <= g_tolerance * rp)
    active = merge(0_i8, active, hi - lo <= bracket_tolerance * hi)
  end subroutine evaluate

  !> The safeguarded Newton step of an active point from its last evaluation (gp = g sqrt(P),
  !> root_p = sqrt(P) there): g / g' = gp P / (g' sqrt(P)^3), or bisection where it leaves the
  !> bracket; a stopped point keeps its dgamma. P is recomputed as evaluate computed it.
  pure subroutine newton_step(pa, pb, kappa, hh, c1, c2, gp, root_p, lo, hi, active, dgamma)
    real(ek), intent(in) :: pa, pb, kappa, hh, c1, c2, gp, root_p, lo, hi
    integer(i8), intent(in) :: active
    real(ek), intent(inout) :: dgamma
    real(ek) :: u1, u2, p, dgp, newton, bisection
    u1 = 1.0_ek + dgamma * c1
    u2 = 1.0_ek + dgamma * c2
    p = pa * u2**2 + pb * u1**2
    dgp = kappa * ((c1 * u2 + c2 * u1) * p - (u1 * u2) * (pa * c2 * u2 + pb * c1 * u1)) + hh * p * root_p   ! g' sqrt(P)^3
    bisection = 0.5_ek * (lo + hi)
    newton = dgamma - gp * p / merge(dgp, 1.0_ek, dgp > 0.0_ek)   ! (0 / 0 at a point with no stress)
    newton = merge(bisection, newton, newton <= lo)
    newton = merge(bisection, newton, newton >= hi)
    newton = merge(bisection, newton, dgp <= 0.0_ek)
    dgamma = merge(newton, dgamma, active == 1)
  end subroutine newton_step

  !> A dgamma where the residual g >= 0: q <= q0 / (1 + dgamma min(c1, c2)), so g >= 0 from
  !> (q0 / k0 - 1) / min(c1, c2) on (twice that, so that Newton's last steps never touch it);
  !> without a positive radius k0, no bound (the iteration's own bracket takes over).
  pure real(ek) function upper_bound(q0, k0, c_min) result(hi)
    real(ek), intent(in) :: q0, k0, c_min
    hi = merge(2.0_ek * (q0 / max(k0, tiny(1.0_ek)) - 1.0_ek) / c_min, huge(1.0_ek), k0 > 0.0_ek)
  end function upper_bound

end module plane_stress_returns
