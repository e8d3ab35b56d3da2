!> The Belytschko-Lin-Tsay shell (Belytschko, Lin & Tsay 1984; Hallquist, LS-DYNA Theory Manual).
!>
!> Four-node quadrilateral, one-point quadrature in the plane, Gauss points through the thickness,
!> co-rotational local frame per element and step, velocity-strain formulation (membrane, bending,
!> transverse shear), stresses stored in the co-rotational frame (an objective rate), and
!> hourglass control (shell_hourglass: physical, or stiffness and viscous forms with a coefficient).
!> and the warping correction of shell_warping where the part asks for it.
!>
!> Kernels work on a group of n elements whose arrays put the element index first (structure of
!> arrays). They are pure: no MPI, no I/O, no module state.
module shell_blt
  use paradyn_kinds, only: wp, ek
  use vector_algebra, only: cross
  use element_groups, only: group_size
  use paradyn_schema, only: max_integration_points, hourglass_physical
  use shell_section, only: shell_properties_t, stress_components, hourglass_components, shear_correction, &
                           thickness_rule, back_stress_points
  use shell_hourglass, only: hourglass_update, add_shear_hourglass_moments, tangent_work, tangent_share
  use shell_warping, only: warp_heights, warp_curvature, warp_twist_moment
  use shell_measures, only: frame_time_steps
  use shell_frames, only: frames, check_end_frames, store_corner_forces
  use material_model, only: max_state_words
  use element_erosion, only: zero_failed_points
  implicit none
  private
  public :: blt_internal_forces

  real(ek), parameter :: h(4) = [1.0_ek, -1.0_ek, 1.0_ek, -1.0_ek]   !< the hourglass pattern

contains

  !> Internal nodal forces and moments of a group of BLT shells for one time step.
  !>
  !> x: node positions at t(n+1); v, w: velocities and angular velocities at t(n+1/2).
  !> Strain rates use the mid-step geometry x - dt/2 v (exact for rigid rotation to second
  !> order); forces use the end-of-step geometry. State arrays are updated in place:
  !> stress (local frame), back stress, effective plastic strain, hourglass resultants.
  !> Element energies accumulate the stress and hourglass work of the step (midpoint rule).
  !> force(1:3, k, i) is the internal force, force(4:6, k, i) the internal moment at corner k of
  !> element i, global axes: the engine's corner layout, so that the forces go straight into it.
  !>
  !> Vectorised across elements: elements are taken group_size at a time, and every stage (frame,
  !> gradients, strain rates, each through-thickness point, hourglass, forces) is a loop over
  !> them, innermost, on per-stage arrays with the element index first. Loop bodies hold scalars
  !> only: a small local array in a body stops gfortran's vectoriser. An element that fails a
  !> check is computed with the others (on a safe area) and its results are dropped by merge.
  !> An element's arithmetic is bitwise the same in a vector body or a scalar remainder, whatever
  !> the group's size: nothing is summed across elements, and this file is compiled without FMA
  !> contraction (fortran/CMakeLists.txt), so the layouts of tests/test_parallel.py agree.
  !> Precision: x, v, w, the step, forces and energies are double (wp); the arithmetic and the
  !> element state are of kind ek, single in the mixed engine (frames; docs/theory.md).
  !> thickness (optional; a part with thickness_update): each element's current thickness, which
  !> the step's strains and resultants use in place of props%thickness and which the step updates
  !> from its thickness strain rate (thickness_strain_step; docs/theory.md, "Thickness update").
  !> Without it every element has props%thickness, bitwise as before the option.
  pure subroutine blt_internal_forces(n, x, v, w, props, dt_step, stress, back, eps_p, state, hourglass, &
                                      force, e_internal, e_hourglass, inverted, dt_element, thickness)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(in) :: dt_step
    real(ek), intent(inout) :: stress(n, stress_components, props%integration_points)
    real(ek), intent(inout) :: back(n, 3, back_stress_points(props))
    real(ek), intent(inout) :: eps_p(n, props%integration_points)
    real(ek), intent(inout), contiguous :: state(:, :, :)   !< (n, the material's state words, points)
    real(ek), intent(inout) :: hourglass(n, hourglass_components)
    real(wp), intent(out) :: force(6, 4, n)
    real(wp), intent(inout) :: e_internal(n), e_hourglass(n)
    integer, intent(inout) :: inverted
    real(wp), intent(out) :: dt_element(n)   !< stable step L / c on the end-of-step geometry
    real(ek), intent(inout), optional :: thickness(n)   !< current thickness of each element (m)

    integer :: first, m, o, i, k, c, nip, ns
    real(wp) :: zeta_wp(max_integration_points), wgt_wp(max_integration_points)
    real(ek) :: zeta(max_integration_points), wgt(max_integration_points)
    real(ek) :: dt, t, half_t, shear_step, s1, s2, s3, s4, s5, wk, zk, squeeze
    logical :: history   !< the material keeps a back stress or plastic strain
    ! per-pass arrays, element index first
    real(wp) :: xg(group_size, 3, 4)   !< the mid-step positions (double, as the nodes')
    real(ek) :: vg(group_size, 3, 4), wg(group_size, 3, 4)
    real(ek) :: e(group_size, 3, 3), xl(group_size, 4), yl(group_size, 4), normal_mid(group_size, 3)
    real(ek) :: area_mid(group_size), area(group_size), valid(group_size)
    real(ek) :: zw(group_size), dh(group_size)   !< warp and twist term (shell_warping); 0: flat element
    real(ek) :: b1(group_size, 4), b2(group_size, 4), gamma(group_size, 4)
    !> rates: membrane dm(1:3), curvature kappa(4:6), transverse shear gs(7:8)
    real(ek) :: rates(group_size, 8), qrate(group_size, hourglass_components), grad_w(group_size, 4)
    real(ek) :: sp(group_size, stress_components)
    real(ek) :: bp(group_size, 3), ep(group_size), deps(group_size, 3), work(group_size)
    real(ek) :: stp(group_size, max_state_words)   !< the material's own state at a point
    !> res: membrane resultant N (1:3), moment M (4:6), shear Q (7:8)
    real(ek) :: hg(group_size, hourglass_components), res(group_size, 8), fl(group_size, 6, 4)
    real(ek) :: s_xi(group_size)
    !> the stress increments' work against its elastic value over the points: the tangent share
    real(ek) :: actual_work(group_size), elastic_work(group_size), tangent(group_size)
    !> half the thickness of each element this step, and (thickness update) the mean in-plane stress
    !> trace through the thickness before and after the step's stress update
    real(ek) :: ht(group_size), trace_old(group_size), trace_new(group_size)
    logical :: update

    nip = props%integration_points
    ns = size(state, 2)
    history = props%material%has_history()
    call thickness_rule(nip, zeta_wp(1:nip), wgt_wp(1:nip))
    zeta(1:nip) = real(zeta_wp(1:nip), ek)
    wgt(1:nip) = real(wgt_wp(1:nip), ek)
    dt = real(dt_step, ek)
    t = real(props%thickness, ek)
    half_t = 0.5_ek * t
    update = present(thickness)
    squeeze = real((1.0_wp - 2.0_wp * props%poisson) / props%young, ek)
    shear_step = real(shear_correction * (props%young / (2.0_wp * (1.0_wp + props%poisson))), ek) * dt

    do first = 1, n, group_size
      m = min(group_size, n - first + 1)
      o = first - 1

      ! --- strain rates on the mid-step geometry; an element inverted there (area_mid <= 0) gets
      ! zero velocities, hence zero rates, and keeps its state
      xg(1:m, :, :) = x(o + 1:o + m, :, :) - 0.5_wp * dt_step * v(o + 1:o + m, :, :)
      call frames(m, group_size, 0, xg, e, xl, yl, area_mid)
      ! a product, not merge(v, 0, ...): a masked load of v would stop the vectoriser
      valid(1:m) = merge(1.0_ek, 0.0_ek, area_mid(1:m) > 0.0_ek)
      do k = 1, 4
        do c = 1, 3
          vg(1:m, c, k) = valid(1:m) * real(v(o + 1:o + m, c, k), ek)
          wg(1:m, c, k) = valid(1:m) * real(w(o + 1:o + m, c, k), ek)
        end do
      end do
      normal_mid(1:m, :) = e(1:m, :, 3)
      call gradient_arrays(m, xl, yl, area_mid, b1, b2, gamma)
      zw = 0.0_ek
      if (props%warping_correction) call warp_heights(m, group_size, 0, xg, e, area_mid, zw)
      call strain_rates(m, e, b1, b2, gamma, vg, wg, zw, rates, qrate, grad_w)
      if (props%warping_correction) call warp_curvature(m, zw, b1, b2, qrate, rates)

      ! --- stress update at each through-thickness point on copies (sp, bp, ep), written back by
      ! merge so that an element inverted at mid-step keeps its state
      ! (res, the resultants of the stresses at the end of the step, is summed point by point here)
      res(1:m, :) = 0.0_ek
      work = 0.0_ek
      actual_work = 0.0_ek
      elastic_work = 0.0_ek
      if (update) then
        ht(1:m) = 0.5_ek * thickness(o + 1:o + m)
        trace_old(1:m) = 0.0_ek
        trace_new(1:m) = 0.0_ek
      else
        ht(1:m) = half_t
      end if
      do k = 1, nip
        do c = 1, 3
          do i = 1, m
            deps(i, c) = dt * (rates(i, c) + (zeta(k) * ht(i)) * rates(i, 3 + c))
            sp(i, c) = stress(o + i, c, k)
          end do
        end do
        if (update) trace_old(1:m) = trace_old(1:m) + &
                                     0.5_ek * wgt(k) * (stress(o + 1:o + m, 1, k) + stress(o + 1:o + m, 2, k))
        if (history) then
          if (size(back, 3) > 0) then
            bp(1:m, :) = back(o + 1:o + m, :, k)
          else
            bp(1:m, :) = 0.0_ek   ! no kinematic hardening: the back stress stays zero, unstored
          end if
          ep(1:m) = eps_p(o + 1:o + m, k)
        end if
        if (ns > 0) stp(1:m, 1:ns) = state(o + 1:o + m, 1:ns, k)
        ! one dispatch per batch of points: the member's loop over them vectorises
        call props%material%update_points(m, dt, sp, bp, ep, stp(:, 1:ns), deps)
        do c = 1, ns
          state(o + 1:o + m, c, k) = merge(stp(1:m, c), state(o + 1:o + m, c, k), area_mid(1:m) > 0.0_ek)
        end do
        if (history) then
          if (size(back, 3) > 0) then
            do c = 1, 3
              back(o + 1:o + m, c, k) = merge(bp(1:m, c), back(o + 1:o + m, c, k), area_mid(1:m) > 0.0_ek)
            end do
          end if
          eps_p(o + 1:o + m, k) = merge(ep(1:m), eps_p(o + 1:o + m, k), area_mid(1:m) > 0.0_ek)
        end if
        do i = 1, m   ! the transverse shear, elastic
          sp(i, 4) = stress(o + i, 4, k) + shear_step * rates(i, 7)
          sp(i, 5) = stress(o + i, 5, k) + shear_step * rates(i, 8)
        end do
        ! a failed point carries no stress (element_erosion)
        if (props%failure_strain > 0.0_wp) call zero_failed_points(m, props%failure_strain, eps_p(o + 1:o + m, k), sp)
        if (history) call tangent_work(m, wgt(k), props, deps, stress(o + 1:o + m, 1:3, k), sp, actual_work, elastic_work)
        wk = wgt(k)
        zk = zeta(k)
        ! one pass: work, the write-back and the point's share of the resultants
        do i = 1, m
          work(i) = work(i) + (wk * ht(i)) * ( &
                    (0.5_ek * (stress(o + i, 1, k) + sp(i, 1)) * deps(i, 1) &
                     + 0.5_ek * (stress(o + i, 2, k) + sp(i, 2)) * deps(i, 2) &
                     + 0.5_ek * (stress(o + i, 3, k) + sp(i, 3)) * deps(i, 3)) &
                    + (0.5_ek * (stress(o + i, 4, k) + sp(i, 4)) * (dt * rates(i, 7)) &
                       + 0.5_ek * (stress(o + i, 5, k) + sp(i, 5)) * (dt * rates(i, 8))))
          s1 = merge(sp(i, 1), stress(o + i, 1, k), area_mid(i) > 0.0_ek)
          s2 = merge(sp(i, 2), stress(o + i, 2, k), area_mid(i) > 0.0_ek)
          s3 = merge(sp(i, 3), stress(o + i, 3, k), area_mid(i) > 0.0_ek)
          s4 = merge(sp(i, 4), stress(o + i, 4, k), area_mid(i) > 0.0_ek)
          s5 = merge(sp(i, 5), stress(o + i, 5, k), area_mid(i) > 0.0_ek)
          stress(o + i, 1, k) = s1
          stress(o + i, 2, k) = s2
          stress(o + i, 3, k) = s3
          stress(o + i, 4, k) = s4
          stress(o + i, 5, k) = s5
          res(i, 1) = res(i, 1) + (wk * ht(i)) * s1
          res(i, 2) = res(i, 2) + (wk * ht(i)) * s2
          res(i, 3) = res(i, 3) + (wk * ht(i)) * s3
          res(i, 4) = res(i, 4) + (wk * ht(i) * (zk * ht(i))) * s1
          res(i, 5) = res(i, 5) + (wk * ht(i) * (zk * ht(i))) * s2
          res(i, 6) = res(i, 6) + (wk * ht(i) * (zk * ht(i))) * s3
          res(i, 7) = res(i, 7) + (wk * ht(i)) * s4
          res(i, 8) = res(i, 8) + (wk * ht(i)) * s5
        end do
        if (update) trace_new(1:m) = trace_new(1:m) + &
                                     0.5_ek * wgt(k) * (stress(o + 1:o + m, 1, k) + stress(o + 1:o + m, 2, k))
      end do
      if (update) call thickness_strain_step(m, dt, squeeze, rates, trace_old, trace_new, area_mid, &
                                             thickness(o + 1:o + m), res)
      e_internal(o + 1:o + m) = merge(e_internal(o + 1:o + m) + area_mid(1:m) * work(1:m), &
                                      e_internal(o + 1:o + m), area_mid(1:m) > 0.0_ek)

      ! --- hourglass resultants and drilling moments
      hg(1:m, :) = hourglass(o + 1:o + m, :)
      tangent(1:m) = 1.0_ek
      if (history) tangent(1:m) = tangent_share(m, actual_work, elastic_work)
      call hourglass_update(m, props, dt, area_mid, b1, b2, xl, yl, qrate, grad_w, tangent, hg, work)
      do c = 1, hourglass_components
        hourglass(o + 1:o + m, c) = merge(hg(1:m, c), hourglass(o + 1:o + m, c), area_mid(1:m) > 0.0_ek)
      end do
      e_hourglass(o + 1:o + m) = merge(e_hourglass(o + 1:o + m) + work(1:m), e_hourglass(o + 1:o + m), &
                                       area_mid(1:m) > 0.0_ek)

      ! --- resultants and nodal forces on the end-of-step geometry
      call frames(m, n, o, x, e, xl, yl, area)
      call frame_time_steps(m, xl, yl, area, props, dt_element(o + 1:o + m))
      call check_end_frames(m, area_mid, normal_mid, e, xl, yl, area)
      inverted = inverted + count(.not. (area(1:m) > 0.0_ek))
      call gradient_arrays(m, xl, yl, area, b1, b2, gamma)
      if (props%hourglass_form == hourglass_physical) then
        s_xi(1:m) = hg(1:m, 5)
        hg(1:m, 5) = 0.25_ek * (hg(1:m, 5) + hg(1:m, 10))   ! both shear resultants drive the lateral hourglass
      end if
      zw = 0.0_ek
      dh = 0.0_ek
      if (props%warping_correction) call warp_twist_moment(m, n, o, x, e, area, b1, b2, res, zw, dh)
      call nodal_forces(m, e, area, b1, b2, gamma, res, hg, zw, dh, fl)
      if (props%hourglass_form == hourglass_physical) &
        call add_shear_hourglass_moments(m, e, area, xl, yl, s_xi, hg(:, 10), fl)
      call store_corner_forces(m, n, o, 4, fl, force)
    end do
  end subroutine blt_internal_forces

  !> The thickness update of one step (docs/theory.md, "Thickness update"): the thickness strain
  !> increment of plane stress with volume-keeping plastic flow,
  !> d eps_z = -(d eps_x + d eps_y) + (1 - 2 nu) / E (d sigma_x + d sigma_y), from the membrane
  !> rates (the mid-surface's in-plane strain increment) and the change of the mean in-plane stress
  !> trace through the thickness (squeeze = (1 - 2 nu) / E); t <- t exp(d eps_z). The resultants,
  !> summed with the thickness at the start of the step, are carried to the new one: membrane and
  !> shear resultants by t_new / t, moments by (t_new / t)^2. An element inverted at mid-step
  !> keeps its thickness.
  pure subroutine thickness_strain_step(m, dt, squeeze, rates, trace_old, trace_new, area_mid, thickness, res)
    integer, intent(in) :: m
    real(ek), intent(in) :: dt, squeeze, rates(group_size, 8), trace_old(group_size), trace_new(group_size)
    real(ek), intent(in) :: area_mid(group_size)
    real(ek), intent(inout) :: thickness(m), res(group_size, 8)
    real(ek) :: ratio
    integer :: i
    do i = 1, m
      ratio = exp(-dt * (rates(i, 1) + rates(i, 2)) + squeeze * (trace_new(i) - trace_old(i)))
      ratio = merge(ratio, 1.0_ek, area_mid(i) > 0.0_ek)
      thickness(i) = thickness(i) * ratio
      res(i, 1:3) = res(i, 1:3) * ratio
      res(i, 4:6) = res(i, 4:6) * (ratio * ratio)
      res(i, 7:8) = res(i, 7:8) * ratio
    end do
  end subroutine thickness_strain_step

  !> Shape-function derivatives at the centre (B1 = dN/dx, B2 = dN/dy) and the hourglass shape
  !> vector gamma = h - (h.x) B1 - (h.y) B2 (h = 1, -1, 1, -1), orthogonal to the linear velocity
  !> fields, for elements 1..m; an element of area <= 0 gets those of area 1 (finite, not kept).
  pure subroutine gradient_arrays(m, xl, yl, area, b1, b2, gamma)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(group_size, 4), yl(group_size, 4), area(group_size)
    real(ek), intent(out) :: b1(group_size, 4), b2(group_size, 4), gamma(group_size, 4)
    real(ek) :: r, hx, hy
    integer :: i
    do i = 1, m
      r = 0.5_ek / merge(area(i), 1.0_ek, area(i) > 0.0_ek)
      b1(i, 1) = r * (yl(i, 2) - yl(i, 4))
      b1(i, 2) = r * (yl(i, 3) - yl(i, 1))
      b1(i, 3) = r * (yl(i, 4) - yl(i, 2))
      b1(i, 4) = r * (yl(i, 1) - yl(i, 3))
      b2(i, 1) = r * (xl(i, 4) - xl(i, 2))
      b2(i, 2) = r * (xl(i, 1) - xl(i, 3))
      b2(i, 3) = r * (xl(i, 2) - xl(i, 4))
      b2(i, 4) = r * (xl(i, 3) - xl(i, 1))
      hx = xl(i, 1) - xl(i, 2) + xl(i, 3) - xl(i, 4)
      hy = yl(i, 1) - yl(i, 2) + yl(i, 3) - yl(i, 4)
      gamma(i, 1) = 1.0_ek - hx * b1(i, 1) - hy * b2(i, 1)
      gamma(i, 2) = -1.0_ek - hx * b1(i, 2) - hy * b2(i, 2)
      gamma(i, 3) = 1.0_ek - hx * b1(i, 3) - hy * b2(i, 3)
      gamma(i, 4) = -1.0_ek - hx * b1(i, 4) - hy * b2(i, 4)
    end do
  end subroutine gradient_arrays

  !> Strain rates of elements 1..m from the local velocities vl = e^T v, wl = e^T w: membrane
  !> dm and curvature kappa (Voigt, engineering shear), transverse shear gs, and the hourglass
  !> rates (5 modes, then the drilling rate of each node about the normal relative to the
  !> in-plane spin). A warped element (zw /= 0) first moves its nodes' velocities to the mean
  !> plane along rigid links of length z = +-zw (shell_warping): vl - z (wl x e3).
  pure subroutine strain_rates(m, e, b1, b2, gamma, v, w, zw, rates, qrate, grad_w)
    integer, intent(in) :: m
    real(ek), intent(in) :: e(group_size, 3, 3), b1(group_size, 4), b2(group_size, 4), gamma(group_size, 4)
    real(ek), intent(in) :: v(group_size, 3, 4), w(group_size, 3, 4), zw(group_size)
    real(ek), intent(out) :: rates(group_size, 8), qrate(group_size, hourglass_components)
    !> the centre gradients of the nodal rotation rates: d/dx theta_x, d/dy theta_y, d/dx theta_y,
    !> d/dy theta_x (before any warping correction of the curvatures)
    real(ek), intent(out) :: grad_w(group_size, 4)
    ! sums over the nodes, in scalars: one pass over the elements (the loop over k unrolls)
    real(ek) :: r1, r2, r4, r5, r7, r8, b2v1, b1v2, b2w2, b1w1, w1sum, w2sum, q1, q2, q3, q4, q5
    real(ek) :: vl1, vl2, vl3, wl1, wl2, wl3, spin, hk
    integer :: i, k
    do i = 1, m
      r1 = 0.0_ek
      r2 = 0.0_ek
      r4 = 0.0_ek
      r5 = 0.0_ek
      r7 = 0.0_ek
      r8 = 0.0_ek
      b2v1 = 0.0_ek
      b1v2 = 0.0_ek
      b2w2 = 0.0_ek
      b1w1 = 0.0_ek
      w1sum = 0.0_ek
      w2sum = 0.0_ek
      q1 = 0.0_ek
      q2 = 0.0_ek
      q3 = 0.0_ek
      q4 = 0.0_ek
      q5 = 0.0_ek
      !GCC$ unroll 4
      do k = 1, 4
        hk = h(k)
        vl1 = e(i, 1, 1) * v(i, 1, k) + e(i, 2, 1) * v(i, 2, k) + e(i, 3, 1) * v(i, 3, k)
        vl2 = e(i, 1, 2) * v(i, 1, k) + e(i, 2, 2) * v(i, 2, k) + e(i, 3, 2) * v(i, 3, k)
        vl3 = e(i, 1, 3) * v(i, 1, k) + e(i, 2, 3) * v(i, 2, k) + e(i, 3, 3) * v(i, 3, k)
        wl1 = e(i, 1, 1) * w(i, 1, k) + e(i, 2, 1) * w(i, 2, k) + e(i, 3, 1) * w(i, 3, k)
        wl2 = e(i, 1, 2) * w(i, 1, k) + e(i, 2, 2) * w(i, 2, k) + e(i, 3, 2) * w(i, 3, k)
        wl3 = e(i, 1, 3) * w(i, 1, k) + e(i, 2, 3) * w(i, 2, k) + e(i, 3, 3) * w(i, 3, k)
        vl1 = merge(vl1 - (hk * zw(i)) * wl2, vl1, zw(i) /= 0.0_ek)
        vl2 = merge(vl2 + (hk * zw(i)) * wl1, vl2, zw(i) /= 0.0_ek)
        r1 = r1 + b1(i, k) * vl1
        r2 = r2 + b2(i, k) * vl2
        b2v1 = b2v1 + b2(i, k) * vl1
        b1v2 = b1v2 + b1(i, k) * vl2
        r4 = r4 + b1(i, k) * wl2
        r5 = r5 + b2(i, k) * wl1
        b2w2 = b2w2 + b2(i, k) * wl2
        b1w1 = b1w1 + b1(i, k) * wl1
        r7 = r7 + b1(i, k) * vl3
        r8 = r8 + b2(i, k) * vl3
        w1sum = w1sum + wl1
        w2sum = w2sum + wl2
        q1 = q1 + gamma(i, k) * vl1
        q2 = q2 + gamma(i, k) * vl2
        q3 = q3 + gamma(i, k) * wl1
        q4 = q4 + gamma(i, k) * wl2
        q5 = q5 + gamma(i, k) * vl3
        qrate(i, 5 + k) = wl3
      end do
      rates(i, 1) = r1
      rates(i, 2) = r2
      rates(i, 3) = b2v1 + b1v2
      rates(i, 4) = r4
      rates(i, 5) = -r5
      rates(i, 6) = b2w2 - b1w1
      grad_w(i, 1) = b1w1
      grad_w(i, 2) = b2w2
      grad_w(i, 3) = r4
      grad_w(i, 4) = r5
      rates(i, 7) = r7 + 0.25_ek * w2sum
      rates(i, 8) = r8 - 0.25_ek * w1sum
      qrate(i, 1) = q1
      qrate(i, 2) = q2
      qrate(i, 3) = q3
      qrate(i, 4) = q4
      qrate(i, 5) = q5
      qrate(i, 10) = 0.0_ek
      spin = 0.5_ek * (b1v2 - b2v1)
      qrate(i, 6) = qrate(i, 6) - spin
      qrate(i, 7) = qrate(i, 7) - spin
      qrate(i, 8) = qrate(i, 8) - spin
      qrate(i, 9) = qrate(i, 9) - spin
    end do
  end subroutine strain_rates

  !> Nodal forces and moments of elements 1..m in global axes from the resultants res (N, M, Q),
  !> the hourglass resultants and the drilling moments; zero for an element of area <= 0. A
  !> warped element (zw /= 0) adds its twist term's forces (dh = D / 2) and the moments
  !> z (f x e3) of its rigid links (shell_warping).
  pure subroutine nodal_forces(m, e, area, b1, b2, gamma, res, hg, zw, dh, force)
    integer, intent(in) :: m
    real(ek), intent(in) :: e(group_size, 3, 3), area(group_size)
    real(ek), intent(in) :: b1(group_size, 4), b2(group_size, 4), gamma(group_size, 4)
    real(ek), intent(in) :: res(group_size, 8), hg(group_size, hourglass_components)
    real(ek), intent(in) :: zw(group_size), dh(group_size)
    real(ek), intent(out) :: force(group_size, 6, 4)
    real(ek) :: drill_total, f1, f2, f3, f4, f5, f6, g1, g2, hk
    integer :: i, k
    do k = 1, 4
      hk = h(k)
      do i = 1, m
        drill_total = hg(i, 6) + hg(i, 7) + hg(i, 8) + hg(i, 9)
        f1 = area(i) * (b1(i, k) * res(i, 1) + b2(i, k) * res(i, 3)) + gamma(i, k) * hg(i, 1) &
             + 0.5_ek * drill_total * b2(i, k)
        f2 = area(i) * (b2(i, k) * res(i, 2) + b1(i, k) * res(i, 3)) + gamma(i, k) * hg(i, 2) &
             - 0.5_ek * drill_total * b1(i, k)
        f3 = area(i) * (b1(i, k) * res(i, 7) + b2(i, k) * res(i, 8)) + gamma(i, k) * hg(i, 5)
        f4 = -area(i) * (b2(i, k) * res(i, 5) + b1(i, k) * res(i, 6) + 0.25_ek * res(i, 8)) &
             + gamma(i, k) * hg(i, 3)
        f5 = area(i) * (b1(i, k) * res(i, 4) + b2(i, k) * res(i, 6) + 0.25_ek * res(i, 7)) &
             + gamma(i, k) * hg(i, 4)
        f6 = hg(i, 5 + k)
        g1 = f1 + dh(i) * b2(i, k)
        g2 = f2 - dh(i) * b1(i, k)
        f4 = merge(f4 + (hk * zw(i)) * g2, f4, zw(i) /= 0.0_ek)
        f5 = merge(f5 - (hk * zw(i)) * g1, f5, zw(i) /= 0.0_ek)
        f6 = merge(f6 + 0.5_ek * dh(i), f6, zw(i) /= 0.0_ek)
        f1 = merge(g1, f1, zw(i) /= 0.0_ek)
        f2 = merge(g2, f2, zw(i) /= 0.0_ek)
        force(i, 1, k) = merge(e(i, 1, 1) * f1 + e(i, 1, 2) * f2 + e(i, 1, 3) * f3, 0.0_ek, area(i) > 0.0_ek)
        force(i, 2, k) = merge(e(i, 2, 1) * f1 + e(i, 2, 2) * f2 + e(i, 2, 3) * f3, 0.0_ek, area(i) > 0.0_ek)
        force(i, 3, k) = merge(e(i, 3, 1) * f1 + e(i, 3, 2) * f2 + e(i, 3, 3) * f3, 0.0_ek, area(i) > 0.0_ek)
        force(i, 4, k) = merge(e(i, 1, 1) * f4 + e(i, 1, 2) * f5 + e(i, 1, 3) * f6, 0.0_ek, area(i) > 0.0_ek)
        force(i, 5, k) = merge(e(i, 2, 1) * f4 + e(i, 2, 2) * f5 + e(i, 2, 3) * f6, 0.0_ek, area(i) > 0.0_ek)
        force(i, 6, k) = merge(e(i, 3, 1) * f4 + e(i, 3, 2) * f5 + e(i, 3, 3) * f6, 0.0_ek, area(i) > 0.0_ek)
      end do
    end do
  end subroutine nodal_forces

end module shell_blt
