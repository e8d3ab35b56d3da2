!> The C0 triangular shell with one-point quadrature (after Belytschko, Stolarski & Carpenter 1984,
!> "A C0 triangular plate element with one-point quadrature", IJNME 20; LS-DYNA's shell form 4), the
!> triangle member of the element family beside the Belytschko-Lin-Tsay quadrilateral (shell_blt).
!>
!> Three nodes; the deck stores a triangle as a quadrilateral whose third and fourth nodes are the
!> same (a degenerate quad, as LS-DYNA does), so the kernel takes the quad's arrays and leaves the
!> fourth corner's force zero. Co-rotational frame per element and step (e1 along side 1-2, e3 the
!> triangle's normal), velocity strains at the centroid from linear velocity and rotation fields:
!> constant-strain membrane, constant curvature, and the transverse shear of the edges (the shear
!> tied along each side, evaluated at the centroid), which vanishes for every Kirchhoff field of
!> quadratic deflection, so a thin plate does not lock. No hourglass modes, no warping; the
!> drilling moments of the family (shell_hourglass's penalty). docs/theory.md, "C0 triangle".
!>
!> Pure kernels over a group of n elements, element index first, like shell_blt: the same
!> material family, through-thickness rule and per-point state, and, compiled like it without FMA
!> contraction, the same arithmetic for an element in a vector body or a scalar remainder.
module shell_c0_triangle
  use paradyn_kinds, only: wp, ek
  use element_groups, only: group_size
  use paradyn_schema, only: max_integration_points
  use shell_section, only: shell_properties_t, stress_components, hourglass_components, shear_correction, &
                           thickness_rule, back_stress_points
  use shell_hourglass, only: drilling_penalty
  use shell_measures, only: triangle_frame_time_steps
  use shell_frames, only: store_corner_forces
  use material_model, only: max_state_words
  use element_erosion, only: zero_failed_points
  implicit none
  private
  public :: c0_triangle_internal_forces

contains

  !> Internal nodal forces and moments of a group of C0 triangles for one time step: the arguments
  !> of shell_blt's blt_internal_forces (corner 4 repeats corner 3 and gets no force); the
  !> hourglass state holds the three drilling moments in its slots 6..8, the others stay zero.
  pure subroutine c0_triangle_internal_forces(n, x, v, w, props, dt_step, stress, back, eps_p, state, &
                                              hourglass, force, e_internal, e_hourglass, inverted, dt_element)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(in) :: dt_step
    real(ek), intent(inout) :: stress(n, stress_components, props%integration_points)
    real(ek), intent(inout) :: back(n, 3, back_stress_points(props))
    real(ek), intent(inout) :: eps_p(n, props%integration_points)
    real(ek), intent(inout), contiguous :: state(:, :, :)
    real(ek), intent(inout) :: hourglass(n, hourglass_components)
    real(wp), intent(out) :: force(6, 4, n)
    real(wp), intent(inout) :: e_internal(n), e_hourglass(n)
    integer, intent(inout) :: inverted
    real(wp), intent(out) :: dt_element(n)

    integer :: first, m, o, i, k, c
    real(ek) :: dt, drill, q_old, drill_work
    real(wp) :: xg(group_size, 3, 4)
    real(ek) :: vg(group_size, 3, 3), wg(group_size, 3, 3)
    real(ek) :: e(group_size, 3, 3), xl(group_size, 3), yl(group_size, 3), normal_mid(group_size, 3)
    real(ek) :: area_mid(group_size), area(group_size), valid(group_size)
    real(ek) :: b1(group_size, 3), b2(group_size, 3)
    !> rates: membrane (1:3), curvature (4:6), transverse shear (7:8); drill: the drilling rates
    real(ek) :: rates(group_size, 8), drill_rate(group_size, 3)
    real(ek) :: res(group_size, 8), work(group_size), hg(group_size, 3), fl(group_size, 6, 3)

    dt = real(dt_step, ek)
    do first = 1, n, group_size
      m = min(group_size, n - first + 1)
      o = first - 1

      ! --- strain rates on the mid-step geometry; an element collapsed there gets zero rates
      xg(1:m, :, :) = x(o + 1:o + m, :, :) - 0.5_wp * dt_step * v(o + 1:o + m, :, :)
      call triangle_frames(m, group_size, 0, xg, e, xl, yl, area_mid)
      valid(1:m) = merge(1.0_ek, 0.0_ek, area_mid(1:m) > 0.0_ek)
      do k = 1, 3
        do c = 1, 3
          vg(1:m, c, k) = valid(1:m) * real(v(o + 1:o + m, c, k), ek)
          wg(1:m, c, k) = valid(1:m) * real(w(o + 1:o + m, c, k), ek)
        end do
      end do
      normal_mid(1:m, :) = e(1:m, :, 3)
      call triangle_gradients(m, xl, yl, area_mid, b1, b2)
      call triangle_rates(m, e, xl, yl, b1, b2, vg, wg, rates, drill_rate)

      ! --- stresses at the through-thickness points, resultants and stress work
      call section_update(m, o, n, props, dt, rates, area_mid, stress, back, eps_p, state, res, work)
      e_internal(o + 1:o + m) = merge(e_internal(o + 1:o + m) + area_mid(1:m) * work(1:m), &
                                      e_internal(o + 1:o + m), area_mid(1:m) > 0.0_ek)

      ! --- drilling moments (the family's penalty), their work counted as hourglass energy
      do i = 1, m
        drill = drilling_penalty * real(props%young * props%thickness, ek) &
                * merge(area_mid(i), 1.0_ek, area_mid(i) > 0.0_ek) * dt
        drill_work = 0.0_ek
        do k = 1, 3
          q_old = hourglass(o + i, 5 + k)
          hg(i, k) = q_old + drill * drill_rate(i, k)
          drill_work = drill_work + 0.5_ek * (q_old + hg(i, k)) * drill_rate(i, k)
          hourglass(o + i, 5 + k) = merge(hg(i, k), q_old, area_mid(i) > 0.0_ek)
        end do
        e_hourglass(o + i) = merge(e_hourglass(o + i) + dt * drill_work, e_hourglass(o + i), area_mid(i) > 0.0_ek)
      end do

      ! --- nodal forces on the end-of-step geometry
      call triangle_frames(m, n, o, x, e, xl, yl, area)
      call triangle_frame_time_steps(m, xl, yl, area, props, dt_element(o + 1:o + m))
      do i = 1, m   ! valid where valid at mid-step and the normal did not flip in the step
        area(i) = merge(area(i), 0.0_ek, area_mid(i) > 0.0_ek .and. area(i) > 0.0_ek &
                        .and. normal_mid(i, 1) * e(i, 1, 3) + normal_mid(i, 2) * e(i, 2, 3) &
                              + normal_mid(i, 3) * e(i, 3, 3) > 0.0_ek)
      end do
      inverted = inverted + count(.not. (area(1:m) > 0.0_ek))
      call triangle_gradients(m, xl, yl, area, b1, b2)
      call triangle_forces(m, e, xl, yl, area, b1, b2, res, hg, fl)
      call store_corner_forces(m, n, o, 3, fl, force)
      force(:, 4, o + 1:o + m) = 0.0_wp
    end do
  end subroutine c0_triangle_internal_forces

  !> The stress update of elements o+1..o+m at every through-thickness point (the material
  !> family's batch call), the transverse shear elastic with the shear correction, written back
  !> where area_mid > 0 (an element collapsed at mid-step keeps its state); res: the resultants
  !> N (1:3), M (4:6), Q (7:8) of the new stresses; work: the stress work per unit area (midpoint
  !> rule). The same arithmetic as shell_blt's loop over the points.
  pure subroutine section_update(m, o, n, props, dt, rates, area_mid, stress, back, eps_p, state, res, work)
    integer, intent(in) :: m, o, n
    type(shell_properties_t), intent(in) :: props
    real(ek), intent(in) :: dt, rates(group_size, 8), area_mid(group_size)
    real(ek), intent(inout) :: stress(n, stress_components, props%integration_points)
    real(ek), intent(inout), contiguous :: back(:, :, :), state(:, :, :)
    real(ek), intent(inout) :: eps_p(n, props%integration_points)
    real(ek), intent(out) :: res(group_size, 8), work(group_size)
    real(wp) :: zeta_wp(max_integration_points), wgt_wp(max_integration_points)
    real(ek) :: zeta, wgt, half_t, shear_step, z, wz, wzz, s1, s2, s3, s4, s5
    real(ek) :: sp(group_size, stress_components), bp(group_size, 3), ep(group_size), deps(group_size, 3)
    real(ek) :: stp(group_size, max_state_words)
    logical :: history
    integer :: nip, ns, k, c, i
    nip = props%integration_points
    ns = size(state, 2)
    history = props%material%has_history()
    call thickness_rule(nip, zeta_wp(1:nip), wgt_wp(1:nip))
    half_t = 0.5_ek * real(props%thickness, ek)
    shear_step = real(shear_correction * (props%young / (2.0_wp * (1.0_wp + props%poisson))), ek) * dt
    res(1:m, :) = 0.0_ek
    work = 0.0_ek
    do k = 1, nip
      zeta = real(zeta_wp(k), ek)
      wgt = real(wgt_wp(k), ek)
      z = zeta * half_t
      do c = 1, 3
        do i = 1, m
          deps(i, c) = dt * (rates(i, c) + z * rates(i, 3 + c))
          sp(i, c) = stress(o + i, c, k)
        end do
      end do
      bp(1:m, :) = 0.0_ek
      if (history) then
        if (size(back, 3) > 0) bp(1:m, :) = back(o + 1:o + m, :, k)
        ep(1:m) = eps_p(o + 1:o + m, k)
      end if
      if (ns > 0) stp(1:m, 1:ns) = state(o + 1:o + m, 1:ns, k)
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
      wz = wgt * half_t
      wzz = wgt * half_t * z
      do i = 1, m
        work(i) = work(i) + wz * ( &
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
        res(i, 1) = res(i, 1) + wz * s1
        res(i, 2) = res(i, 2) + wz * s2
        res(i, 3) = res(i, 3) + wz * s3
        res(i, 4) = res(i, 4) + wzz * s1
        res(i, 5) = res(i, 5) + wzz * s2
        res(i, 6) = res(i, 6) + wzz * s3
        res(i, 7) = res(i, 7) + wz * s4
        res(i, 8) = res(i, 8) + wz * s5
      end do
    end do
  end subroutine section_update

  !> Co-rotational frame of triangles o+1..o+m of x (corners 1..3): e1 along side 1-2, e3 the unit
  !> normal (x2 - x1) x (x3 - x1), e2 = e3 x e1; the local coordinates of the corners about the
  !> centroid and the area (> 0; 0 for a collapsed triangle). Differences of the double positions
  !> are taken in double, then rounded to the kernel's kind (as shell_blt's frames).
  pure subroutine triangle_frames(m, ld, o, x, e, xl, yl, area)
    integer, intent(in) :: m, ld, o
    real(wp), intent(in) :: x(ld, 3, 4)
    real(ek), intent(out) :: e(group_size, 3, 3), xl(group_size, 3), yl(group_size, 3), area(group_size)
    real(ek) :: ax, ay, az, bx, by, bz, nx, ny, nz, r, e11, e21, e31, e12, e22, e32, cx, cy, cz
    real(wp) :: mx, my, mz
    integer :: i, k
    do i = 1, m
      ax = real(x(o + i, 1, 2) - x(o + i, 1, 1), ek)
      ay = real(x(o + i, 2, 2) - x(o + i, 2, 1), ek)
      az = real(x(o + i, 3, 2) - x(o + i, 3, 1), ek)
      bx = real(x(o + i, 1, 3) - x(o + i, 1, 1), ek)
      by = real(x(o + i, 2, 3) - x(o + i, 2, 1), ek)
      bz = real(x(o + i, 3, 3) - x(o + i, 3, 1), ek)
      nx = ay * bz - az * by
      ny = az * bx - ax * bz
      nz = ax * by - ay * bx
      r = 1.0_ek / sqrt(max(nx * nx + ny * ny + nz * nz, tiny(1.0_ek)))
      nx = nx * r
      ny = ny * r
      nz = nz * r
      r = 1.0_ek / sqrt(max(ax * ax + ay * ay + az * az, tiny(1.0_ek)))
      e11 = ax * r
      e21 = ay * r
      e31 = az * r
      e12 = ny * e31 - nz * e21
      e22 = nz * e11 - nx * e31
      e32 = nx * e21 - ny * e11
      e(i, 1, 1) = e11
      e(i, 2, 1) = e21
      e(i, 3, 1) = e31
      e(i, 1, 2) = e12
      e(i, 2, 2) = e22
      e(i, 3, 2) = e32
      e(i, 1, 3) = nx
      e(i, 2, 3) = ny
      e(i, 3, 3) = nz
      mx = (x(o + i, 1, 1) + x(o + i, 1, 2) + x(o + i, 1, 3)) / 3.0_wp
      my = (x(o + i, 2, 1) + x(o + i, 2, 2) + x(o + i, 2, 3)) / 3.0_wp
      mz = (x(o + i, 3, 1) + x(o + i, 3, 2) + x(o + i, 3, 3)) / 3.0_wp
      do k = 1, 3
        cx = real(x(o + i, 1, k) - mx, ek)
        cy = real(x(o + i, 2, k) - my, ek)
        cz = real(x(o + i, 3, k) - mz, ek)
        xl(i, k) = cx * e11 + cy * e21 + cz * e31
        yl(i, k) = cx * e12 + cy * e22 + cz * e32
      end do
      area(i) = 0.5_ek * ((xl(i, 2) - xl(i, 1)) * (yl(i, 3) - yl(i, 1)) - (xl(i, 3) - xl(i, 1)) * (yl(i, 2) - yl(i, 1)))
    end do
  end subroutine triangle_frames

  !> Gradients of the linear shape functions (B1 = dN/dx, B2 = dN/dy), constant over the triangle;
  !> an element of area <= 0 gets those of area 1 (finite, not kept).
  pure subroutine triangle_gradients(m, xl, yl, area, b1, b2)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(group_size, 3), yl(group_size, 3), area(group_size)
    real(ek), intent(out) :: b1(group_size, 3), b2(group_size, 3)
    real(ek) :: r
    integer :: i
    do i = 1, m
      r = 0.5_ek / merge(area(i), 1.0_ek, area(i) > 0.0_ek)
      b1(i, 1) = r * (yl(i, 2) - yl(i, 3))
      b1(i, 2) = r * (yl(i, 3) - yl(i, 1))
      b1(i, 3) = r * (yl(i, 1) - yl(i, 2))
      b2(i, 1) = r * (xl(i, 3) - xl(i, 2))
      b2(i, 2) = r * (xl(i, 1) - xl(i, 3))
      b2(i, 3) = r * (xl(i, 2) - xl(i, 1))
    end do
  end subroutine triangle_gradients

  !> Strain rates at the centroid from the local velocities vl = e^T v and rotation rates wl = e^T w:
  !> membrane and curvature as the BLT element's (the gradients of linear fields); transverse shear
  !> from the edges: with the slopes phi = (theta_y, -theta_x), the rate of the shear gap of edge
  !> i -> j is G = (w_j - w_i) + (phi_i + phi_j) / 2 . (x_j - x_i), and the shear at the centroid is
  !> (1/3) sum_edges G (grad N_j - grad N_i), the edge-element field of the three gaps there. It is
  !> grad w + phi for a constant phi, and 0 for every Kirchhoff field of quadratic deflection. The
  !> drilling rates: each node's rotation rate about the normal less the in-plane spin.
  pure subroutine triangle_rates(m, e, xl, yl, b1, b2, v, w, rates, drill_rate)
    integer, intent(in) :: m
    real(ek), intent(in) :: e(group_size, 3, 3), xl(group_size, 3), yl(group_size, 3)
    real(ek), intent(in) :: b1(group_size, 3), b2(group_size, 3), v(group_size, 3, 3), w(group_size, 3, 3)
    real(ek), intent(out) :: rates(group_size, 8), drill_rate(group_size, 3)
    ! scalars only in the loop body (a small array there stops gfortran's vectoriser)
    real(ek) :: r1, r2, b2v1, b1v2, r4, r5, b2p, b1q, sx, sy, vl1, vl2, vl3, px, py, spin
    real(ek) :: px1, px2, px3, py1, py2, py3, g12, g23, g31
    integer :: i, k
    do i = 1, m
      r1 = 0.0_ek
      r2 = 0.0_ek
      b2v1 = 0.0_ek
      b1v2 = 0.0_ek
      r4 = 0.0_ek
      r5 = 0.0_ek
      b2p = 0.0_ek
      b1q = 0.0_ek
      sx = 0.0_ek
      sy = 0.0_ek
      !GCC$ unroll 3
      do k = 1, 3
        vl1 = e(i, 1, 1) * v(i, 1, k) + e(i, 2, 1) * v(i, 2, k) + e(i, 3, 1) * v(i, 3, k)
        vl2 = e(i, 1, 2) * v(i, 1, k) + e(i, 2, 2) * v(i, 2, k) + e(i, 3, 2) * v(i, 3, k)
        vl3 = e(i, 1, 3) * v(i, 1, k) + e(i, 2, 3) * v(i, 2, k) + e(i, 3, 3) * v(i, 3, k)
        px = e(i, 1, 2) * w(i, 1, k) + e(i, 2, 2) * w(i, 2, k) + e(i, 3, 2) * w(i, 3, k)       ! theta_y
        py = -(e(i, 1, 1) * w(i, 1, k) + e(i, 2, 1) * w(i, 2, k) + e(i, 3, 1) * w(i, 3, k))    ! -theta_x
        drill_rate(i, k) = e(i, 1, 3) * w(i, 1, k) + e(i, 2, 3) * w(i, 2, k) + e(i, 3, 3) * w(i, 3, k)
        r1 = r1 + b1(i, k) * vl1
        r2 = r2 + b2(i, k) * vl2
        b2v1 = b2v1 + b2(i, k) * vl1
        b1v2 = b1v2 + b1(i, k) * vl2
        r4 = r4 + b1(i, k) * px
        r5 = r5 + b2(i, k) * py
        b2p = b2p + b2(i, k) * px
        b1q = b1q + b1(i, k) * py
        sx = sx + b1(i, k) * vl3
        sy = sy + b2(i, k) * vl3
      end do
      rates(i, 1) = r1
      rates(i, 2) = r2
      rates(i, 3) = b2v1 + b1v2
      rates(i, 4) = r4
      rates(i, 5) = r5
      rates(i, 6) = b2p + b1q
      ! the rotation part of each edge's gap (the w part gives grad w above)
      px1 = e(i, 1, 2) * w(i, 1, 1) + e(i, 2, 2) * w(i, 2, 1) + e(i, 3, 2) * w(i, 3, 1)
      px2 = e(i, 1, 2) * w(i, 1, 2) + e(i, 2, 2) * w(i, 2, 2) + e(i, 3, 2) * w(i, 3, 2)
      px3 = e(i, 1, 2) * w(i, 1, 3) + e(i, 2, 2) * w(i, 2, 3) + e(i, 3, 2) * w(i, 3, 3)
      py1 = -(e(i, 1, 1) * w(i, 1, 1) + e(i, 2, 1) * w(i, 2, 1) + e(i, 3, 1) * w(i, 3, 1))
      py2 = -(e(i, 1, 1) * w(i, 1, 2) + e(i, 2, 1) * w(i, 2, 2) + e(i, 3, 1) * w(i, 3, 2))
      py3 = -(e(i, 1, 1) * w(i, 1, 3) + e(i, 2, 1) * w(i, 2, 3) + e(i, 3, 1) * w(i, 3, 3))
      g12 = ((px1 + px2) * (xl(i, 2) - xl(i, 1)) + (py1 + py2) * (yl(i, 2) - yl(i, 1))) / 6.0_ek
      g23 = ((px2 + px3) * (xl(i, 3) - xl(i, 2)) + (py2 + py3) * (yl(i, 3) - yl(i, 2))) / 6.0_ek
      g31 = ((px3 + px1) * (xl(i, 1) - xl(i, 3)) + (py3 + py1) * (yl(i, 1) - yl(i, 3))) / 6.0_ek
      rates(i, 7) = sx + (g12 * (b1(i, 2) - b1(i, 1)) + g23 * (b1(i, 3) - b1(i, 2)) + g31 * (b1(i, 1) - b1(i, 3)))
      rates(i, 8) = sy + (g12 * (b2(i, 2) - b2(i, 1)) + g23 * (b2(i, 3) - b2(i, 2)) + g31 * (b2(i, 1) - b2(i, 3)))
      spin = 0.5_ek * (b1v2 - b2v1)
      drill_rate(i, 1) = drill_rate(i, 1) - spin
      drill_rate(i, 2) = drill_rate(i, 2) - spin
      drill_rate(i, 3) = drill_rate(i, 3) - spin
    end do
  end subroutine triangle_rates

  !> Nodal forces and moments (global axes) of elements 1..m, the power conjugates of the rates:
  !> A B^T of the resultants, the edge shear's moments, the drilling moments hg with their in-plane
  !> forces; zero for an element of area <= 0.
  pure subroutine triangle_forces(m, e, xl, yl, area, b1, b2, res, hg, force)
    integer, intent(in) :: m
    real(ek), intent(in) :: e(group_size, 3, 3), xl(group_size, 3), yl(group_size, 3), area(group_size)
    real(ek), intent(in) :: b1(group_size, 3), b2(group_size, 3), res(group_size, 8), hg(group_size, 3)
    real(ek), intent(out) :: force(group_size, 6, 3)
    !> ex, ey: the edge shear's moment conjugates (on phi = (theta_y, -theta_x)) of the nodes
    real(ek) :: ex(group_size, 3), ey(group_size, 3)
    real(ek) :: p12, p23, p31, drill_total, f1, f2, f3, f4, f5, f6
    integer :: i, k
    do i = 1, m   ! edge i -> j: its gap's conjugate (A/3) Q . (grad N_j - grad N_i), half to each end
      p12 = area(i) * (res(i, 7) * (b1(i, 2) - b1(i, 1)) + res(i, 8) * (b2(i, 2) - b2(i, 1))) / 6.0_ek
      p23 = area(i) * (res(i, 7) * (b1(i, 3) - b1(i, 2)) + res(i, 8) * (b2(i, 3) - b2(i, 2))) / 6.0_ek
      p31 = area(i) * (res(i, 7) * (b1(i, 1) - b1(i, 3)) + res(i, 8) * (b2(i, 1) - b2(i, 3))) / 6.0_ek
      ex(i, 1) = p12 * (xl(i, 2) - xl(i, 1)) + p31 * (xl(i, 1) - xl(i, 3))
      ex(i, 2) = p12 * (xl(i, 2) - xl(i, 1)) + p23 * (xl(i, 3) - xl(i, 2))
      ex(i, 3) = p23 * (xl(i, 3) - xl(i, 2)) + p31 * (xl(i, 1) - xl(i, 3))
      ey(i, 1) = p12 * (yl(i, 2) - yl(i, 1)) + p31 * (yl(i, 1) - yl(i, 3))
      ey(i, 2) = p12 * (yl(i, 2) - yl(i, 1)) + p23 * (yl(i, 3) - yl(i, 2))
      ey(i, 3) = p23 * (yl(i, 3) - yl(i, 2)) + p31 * (yl(i, 1) - yl(i, 3))
    end do
    do k = 1, 3
      do i = 1, m
        drill_total = hg(i, 1) + hg(i, 2) + hg(i, 3)
        f1 = area(i) * (b1(i, k) * res(i, 1) + b2(i, k) * res(i, 3)) + 0.5_ek * drill_total * b2(i, k)
        f2 = area(i) * (b2(i, k) * res(i, 2) + b1(i, k) * res(i, 3)) - 0.5_ek * drill_total * b1(i, k)
        f3 = area(i) * (b1(i, k) * res(i, 7) + b2(i, k) * res(i, 8))
        f4 = -area(i) * (b2(i, k) * res(i, 5) + b1(i, k) * res(i, 6)) - ey(i, k)
        f5 = area(i) * (b1(i, k) * res(i, 4) + b2(i, k) * res(i, 6)) + ex(i, k)
        f6 = hg(i, k)
        force(i, 1, k) = merge(e(i, 1, 1) * f1 + e(i, 1, 2) * f2 + e(i, 1, 3) * f3, 0.0_ek, area(i) > 0.0_ek)
        force(i, 2, k) = merge(e(i, 2, 1) * f1 + e(i, 2, 2) * f2 + e(i, 2, 3) * f3, 0.0_ek, area(i) > 0.0_ek)
        force(i, 3, k) = merge(e(i, 3, 1) * f1 + e(i, 3, 2) * f2 + e(i, 3, 3) * f3, 0.0_ek, area(i) > 0.0_ek)
        force(i, 4, k) = merge(e(i, 1, 1) * f4 + e(i, 1, 2) * f5 + e(i, 1, 3) * f6, 0.0_ek, area(i) > 0.0_ek)
        force(i, 5, k) = merge(e(i, 2, 1) * f4 + e(i, 2, 2) * f5 + e(i, 2, 3) * f6, 0.0_ek, area(i) > 0.0_ek)
        force(i, 6, k) = merge(e(i, 3, 1) * f4 + e(i, 3, 2) * f5 + e(i, 3, 3) * f6, 0.0_ek, area(i) > 0.0_ek)
      end do
    end do
  end subroutine triangle_forces

end module shell_c0_triangle
