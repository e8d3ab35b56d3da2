!> The fully integrated 4-node shell (docs/theory.md, "Fully integrated shell"): the element of
!> LS-DYNA's formulation 16 in kind, without hourglass modes and so without hourglass control.
!>
!> Bilinear quadrilateral in the co-rotational frame of the element (shell_blt's frames: one frame
!> per element and step), 2 x 2 Gauss points in the plane and the part's Gauss points through the
!> thickness, velocity strains at each point (membrane and Mindlin curvature from the exact
!> shape-function derivatives), and transverse shear by assumed natural strains (MITC4, Dvorkin &
!> Bathe 1984; Bathe & Dvorkin 1985): the covariant shear strains are taken at the four edge
!> midpoints (tying points) and interpolated, gamma_xi linearly in eta between the edges eta = -1
!> and eta = 1, gamma_eta linearly in xi, then turned to the local axes by the Jacobian's inverse.
!> That shear field has no spurious stiffness in pure bending, so a thin plate does not lock.
!> Warped elements take shell_warping's corrections as the BLT element does (rigid links to the
!> mean plane, and the twist term with its conjugate from the mean moments).
!>
!> State: stress, back stress, plastic strain and the material's own state at every in-plane and
!> through-thickness point, point p = (g - 1) nip + k for in-plane point g and layer k. Each step
!> the material family's update runs once per layer on the 4 m points of a batch of m elements.
!> Pure kernels over the elements of a group, element index first, as shell_blt; compiled without
!> FMA contraction (fortran/CMakeLists.txt) so an element's bits do not depend on its group.
module shell_full
  use paradyn_kinds, only: wp, ek
  use element_groups, only: group_size
  use paradyn_schema, only: max_integration_points
  use shell_section, only: shell_properties_t, stress_components, shear_correction, thickness_rule
  use shell_blt, only: frames, check_end_frames
  use shell_warping, only: warp_heights, warp_curvature, warp_twist_moment
  use shell_measures, only: frame_time_steps
  use material_model, only: max_state_words
  implicit none
  private
  public :: full_internal_forces, full_points

  integer, parameter :: full_points = 4   !< in-plane Gauss points
  real(ek), parameter :: gq = 0.57735026918962576_ek   !< 1 / sqrt(3)
  !> the in-plane points (counter-clockwise from node 1's corner) and the nodes' natural coordinates
  real(ek), parameter :: xi_g(4) = [-gq, gq, gq, -gq], eta_g(4) = [-gq, -gq, gq, gq]
  real(ek), parameter :: xi_n(4) = [-1.0_ek, 1.0_ek, 1.0_ek, -1.0_ek], eta_n(4) = [-1.0_ek, -1.0_ek, 1.0_ek, 1.0_ek]
  real(ek), parameter :: hw(4) = [1.0_ek, -1.0_ek, 1.0_ek, -1.0_ek]   !< node heights' pattern of a warped element

contains

  !> Internal nodal forces and moments of a group of fully integrated shells for one time step,
  !> with the arguments of shell_blt's blt_internal_forces less the hourglass ones; the state
  !> arrays hold full_points x integration_points points. Strain rates on the mid-step geometry,
  !> forces on the end-of-step geometry; an element inverted at mid-step keeps its state.
  pure subroutine full_internal_forces(n, x, v, w, props, dt_step, stress, back, eps_p, state, &
                                       force, e_internal, inverted, dt_element)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(in) :: dt_step
    real(ek), intent(inout) :: stress(n, stress_components, full_points * props%integration_points)
    real(ek), intent(inout) :: back(:, :, :)   !< (n, 3, all points), or no points without kinematic hardening
    real(ek), intent(inout) :: eps_p(n, full_points * props%integration_points)
    real(ek), intent(inout) :: state(:, :, :)   !< (n, the material's state words, all points)
    real(wp), intent(out) :: force(6, 4, n)
    real(wp), intent(inout) :: e_internal(n)
    integer, intent(inout) :: inverted
    real(wp), intent(out) :: dt_element(n)

    integer :: first, m, o, i, j, k, c, g, p, nip, ns
    real(wp) :: zeta_wp(max_integration_points), wgt_wp(max_integration_points)
    real(ek) :: zeta(max_integration_points), wgt(max_integration_points)
    real(ek) :: dt, half_t, shear_step, z, wz, wzz, s1, s2, s3, s4, s5
    logical :: history, backs
    real(wp) :: xg(group_size, 3, 4)
    real(ek) :: e(group_size, 3, 3), xl(group_size, 4), yl(group_size, 4), normal_mid(group_size, 3)
    real(ek) :: area_mid(group_size), area(group_size)
    real(ek) :: vl(group_size, 3, 4), wl(group_size, 3, 4), zw(group_size), dh(group_size)
    !> per in-plane point: shape-function derivatives (element, node, point), Jacobian determinant
    !> and entries x_xi, y_xi, x_eta, y_eta
    real(ek) :: dnx(group_size, 4, 4), dny(group_size, 4, 4), detj(group_size, 4), jac(group_size, 4, 4)
    !> per in-plane point: membrane (1:3), curvature (4:6), transverse shear (7:8) rates; then the
    !> resultants N, M, Q of the end-of-step stresses
    real(ek) :: rates(group_size, 8, 4), res(group_size, 8, 4)
    real(ek) :: twist(group_size, 8), drill(group_size, 9), b1(group_size, 4), b2(group_size, 4)
    real(ek) :: sp(full_points * group_size, stress_components), deps(full_points * group_size, 3)
    real(ek) :: bp(full_points * group_size, 3), ep(full_points * group_size)
    real(ek) :: stp(full_points * group_size, max_state_words)
    real(ek) :: work(group_size, 4), fl(group_size, 6, 4)

    nip = props%integration_points
    ns = size(state, 2)
    history = props%material%has_history()
    backs = size(back, 3) > 0
    call thickness_rule(nip, zeta_wp(1:nip), wgt_wp(1:nip))
    zeta(1:nip) = real(zeta_wp(1:nip), ek)
    wgt(1:nip) = real(wgt_wp(1:nip), ek)
    dt = real(dt_step, ek)
    half_t = 0.5_ek * real(props%thickness, ek)
    shear_step = real(shear_correction * (props%young / (2.0_wp * (1.0_wp + props%poisson))), ek) * dt

    do first = 1, n, group_size
      m = min(group_size, n - first + 1)
      o = first - 1

      ! --- strain rates at the in-plane points on the mid-step geometry
      xg(1:m, :, :) = x(o + 1:o + m, :, :) - 0.5_wp * dt_step * v(o + 1:o + m, :, :)
      call frames(m, group_size, 0, xg, e, xl, yl, area_mid)
      normal_mid(1:m, :) = e(1:m, :, 3)
      zw = 0.0_ek
      if (props%warping_correction) call warp_heights(m, group_size, 0, xg, e, area_mid, zw)
      call local_velocities(m, n, o, v, w, e, area_mid, zw, vl, wl)
      call point_geometry(m, xl, yl, dnx, dny, detj, jac)
      call point_rates(m, xl, yl, vl, wl, dnx, dny, detj, jac, rates)
      if (props%warping_correction) then
        if (any(zw(1:m) /= 0.0_ek)) then
          call centre_gradients(m, xl, yl, area_mid, b1, b2)
          call drilling_rates(m, b1, b2, vl, wl, drill)
          twist(1:m, :) = 0.0_ek
          call warp_curvature(m, zw, b1, b2, drill, twist)
          do g = 1, 4
            do c = 4, 6
              rates(1:m, c, g) = rates(1:m, c, g) + twist(1:m, c)
            end do
          end do
        end if
      end if

      ! --- stress update, one material call per layer on the 4 m points of the batch (row
      ! j = (g - 1) m + i), written back by merge so that an element inverted at mid-step keeps
      ! its state; res sums the end-of-step resultants point by point
      res(1:m, :, :) = 0.0_ek
      work(1:m, :) = 0.0_ek
      do k = 1, nip
        z = zeta(k) * half_t
        do g = 1, 4
          p = (g - 1) * nip + k
          do c = 1, 3
            do i = 1, m
              deps((g - 1) * m + i, c) = dt * (rates(i, c, g) + z * rates(i, 3 + c, g))
              sp((g - 1) * m + i, c) = stress(o + i, c, p)
            end do
          end do
          if (history) then
            if (backs) then
              bp((g - 1) * m + 1:g * m, :) = back(o + 1:o + m, :, p)
            else
              bp((g - 1) * m + 1:g * m, :) = 0.0_ek
            end if
            ep((g - 1) * m + 1:g * m) = eps_p(o + 1:o + m, p)
          end if
          if (ns > 0) stp((g - 1) * m + 1:g * m, 1:ns) = state(o + 1:o + m, 1:ns, p)
        end do
        call props%material%update_points(full_points * m, dt, sp, bp, ep, stp(:, 1:ns), deps)
        wz = wgt(k) * half_t
        wzz = wgt(k) * half_t * z
        do g = 1, 4
          p = (g - 1) * nip + k
          do c = 1, ns
            state(o + 1:o + m, c, p) = merge(stp((g - 1) * m + 1:g * m, c), state(o + 1:o + m, c, p), &
                                             area_mid(1:m) > 0.0_ek)
          end do
          if (history) then
            if (backs) then
              do c = 1, 3
                back(o + 1:o + m, c, p) = merge(bp((g - 1) * m + 1:g * m, c), back(o + 1:o + m, c, p), &
                                                area_mid(1:m) > 0.0_ek)
              end do
            end if
            eps_p(o + 1:o + m, p) = merge(ep((g - 1) * m + 1:g * m), eps_p(o + 1:o + m, p), area_mid(1:m) > 0.0_ek)
          end if
          do i = 1, m
            j = (g - 1) * m + i
            sp(j, 4) = stress(o + i, 4, p) + shear_step * rates(i, 7, g)
            sp(j, 5) = stress(o + i, 5, p) + shear_step * rates(i, 8, g)
            work(i, g) = work(i, g) + wz * ( &
                         (0.5_ek * (stress(o + i, 1, p) + sp(j, 1)) * deps(j, 1) &
                          + 0.5_ek * (stress(o + i, 2, p) + sp(j, 2)) * deps(j, 2) &
                          + 0.5_ek * (stress(o + i, 3, p) + sp(j, 3)) * deps(j, 3)) &
                         + (0.5_ek * (stress(o + i, 4, p) + sp(j, 4)) * (dt * rates(i, 7, g)) &
                            + 0.5_ek * (stress(o + i, 5, p) + sp(j, 5)) * (dt * rates(i, 8, g))))
            s1 = merge(sp(j, 1), stress(o + i, 1, p), area_mid(i) > 0.0_ek)
            s2 = merge(sp(j, 2), stress(o + i, 2, p), area_mid(i) > 0.0_ek)
            s3 = merge(sp(j, 3), stress(o + i, 3, p), area_mid(i) > 0.0_ek)
            s4 = merge(sp(j, 4), stress(o + i, 4, p), area_mid(i) > 0.0_ek)
            s5 = merge(sp(j, 5), stress(o + i, 5, p), area_mid(i) > 0.0_ek)
            stress(o + i, 1, p) = s1
            stress(o + i, 2, p) = s2
            stress(o + i, 3, p) = s3
            stress(o + i, 4, p) = s4
            stress(o + i, 5, p) = s5
            res(i, 1, g) = res(i, 1, g) + wz * s1
            res(i, 2, g) = res(i, 2, g) + wz * s2
            res(i, 3, g) = res(i, 3, g) + wz * s3
            res(i, 4, g) = res(i, 4, g) + wzz * s1
            res(i, 5, g) = res(i, 5, g) + wzz * s2
            res(i, 6, g) = res(i, 6, g) + wzz * s3
            res(i, 7, g) = res(i, 7, g) + wz * s4
            res(i, 8, g) = res(i, 8, g) + wz * s5
          end do
        end do
      end do
      do i = 1, m
        e_internal(o + i) = merge(e_internal(o + i) + ((detj(i, 1) * work(i, 1) + detj(i, 2) * work(i, 2)) &
                                                       + (detj(i, 3) * work(i, 3) + detj(i, 4) * work(i, 4))), &
                                  e_internal(o + i), area_mid(i) > 0.0_ek)
      end do

      ! --- nodal forces on the end-of-step geometry
      call frames(m, n, o, x, e, xl, yl, area)
      call frame_time_steps(m, xl, yl, area, props, dt_element(o + 1:o + m))
      call check_end_frames(m, area_mid, normal_mid, e, xl, yl, area)
      inverted = inverted + count(.not. (area(1:m) > 0.0_ek))
      call point_geometry(m, xl, yl, dnx, dny, detj, jac)
      zw = 0.0_ek
      dh = 0.0_ek
      if (props%warping_correction) then
        ! the twist term's conjugate from the area-weighted mean moments
        call centre_gradients(m, xl, yl, area, b1, b2)
        do c = 4, 6
          do i = 1, m
            twist(i, c) = ((detj(i, 1) * res(i, c, 1) + detj(i, 2) * res(i, c, 2)) &
                           + (detj(i, 3) * res(i, c, 3) + detj(i, 4) * res(i, c, 4))) &
                          / merge(area(i), 1.0_ek, area(i) > 0.0_ek)
          end do
        end do
        call warp_twist_moment(m, n, o, x, e, area, b1, b2, twist, zw, dh)
      end if
      call nodal_forces(m, xl, yl, dnx, dny, detj, jac, res, fl)
      if (any(zw(1:m) /= 0.0_ek)) call warp_forces(m, zw, dh, b1, b2, fl)
      do k = 1, 4
        do i = 1, m
          force(1, k, o + i) = merge(e(i, 1, 1) * fl(i, 1, k) + e(i, 1, 2) * fl(i, 2, k) + e(i, 1, 3) * fl(i, 3, k), &
                                     0.0_ek, area(i) > 0.0_ek)
          force(2, k, o + i) = merge(e(i, 2, 1) * fl(i, 1, k) + e(i, 2, 2) * fl(i, 2, k) + e(i, 2, 3) * fl(i, 3, k), &
                                     0.0_ek, area(i) > 0.0_ek)
          force(3, k, o + i) = merge(e(i, 3, 1) * fl(i, 1, k) + e(i, 3, 2) * fl(i, 2, k) + e(i, 3, 3) * fl(i, 3, k), &
                                     0.0_ek, area(i) > 0.0_ek)
          force(4, k, o + i) = merge(e(i, 1, 1) * fl(i, 4, k) + e(i, 1, 2) * fl(i, 5, k) + e(i, 1, 3) * fl(i, 6, k), &
                                     0.0_ek, area(i) > 0.0_ek)
          force(5, k, o + i) = merge(e(i, 2, 1) * fl(i, 4, k) + e(i, 2, 2) * fl(i, 5, k) + e(i, 2, 3) * fl(i, 6, k), &
                                     0.0_ek, area(i) > 0.0_ek)
          force(6, k, o + i) = merge(e(i, 3, 1) * fl(i, 4, k) + e(i, 3, 2) * fl(i, 5, k) + e(i, 3, 3) * fl(i, 6, k), &
                                     0.0_ek, area(i) > 0.0_ek)
        end do
      end do
    end do
  end subroutine full_internal_forces

  !> Local velocities vl = e^T v, wl = e^T w of elements o+1..o+m (zero for an element inverted at
  !> mid-step: no rates, its state kept); a warped element's nodes moved to the mean plane along
  !> their rigid links (shell_warping): vl - z (wl x e3), z = +-zw.
  pure subroutine local_velocities(m, ld, o, v, w, e, area_mid, zw, vl, wl)
    integer, intent(in) :: m, ld, o
    real(wp), intent(in) :: v(ld, 3, 4), w(ld, 3, 4)
    real(ek), intent(in) :: e(group_size, 3, 3), area_mid(group_size), zw(group_size)
    real(ek), intent(out) :: vl(group_size, 3, 4), wl(group_size, 3, 4)
    real(ek) :: valid, v1, v2, v3, w1, w2, w3
    integer :: i, k, c
    do k = 1, 4
      do i = 1, m
        valid = merge(1.0_ek, 0.0_ek, area_mid(i) > 0.0_ek)
        v1 = valid * real(v(o + i, 1, k), ek)
        v2 = valid * real(v(o + i, 2, k), ek)
        v3 = valid * real(v(o + i, 3, k), ek)
        w1 = valid * real(w(o + i, 1, k), ek)
        w2 = valid * real(w(o + i, 2, k), ek)
        w3 = valid * real(w(o + i, 3, k), ek)
        do c = 1, 3
          vl(i, c, k) = e(i, 1, c) * v1 + e(i, 2, c) * v2 + e(i, 3, c) * v3
          wl(i, c, k) = e(i, 1, c) * w1 + e(i, 2, c) * w2 + e(i, 3, c) * w3
        end do
        vl(i, 1, k) = merge(vl(i, 1, k) - (hw(k) * zw(i)) * wl(i, 2, k), vl(i, 1, k), zw(i) /= 0.0_ek)
        vl(i, 2, k) = merge(vl(i, 2, k) + (hw(k) * zw(i)) * wl(i, 1, k), vl(i, 2, k), zw(i) /= 0.0_ek)
      end do
    end do
  end subroutine local_velocities

  !> The Jacobian (x_xi, y_xi, x_eta, y_eta), its determinant and the shape-function derivatives
  !> dN/dx, dN/dy of the bilinear map at the 4 in-plane points of elements 1..m; a point whose
  !> determinant is not positive gets derivatives over 1 (finite, its element's results dropped).
  pure subroutine point_geometry(m, xl, yl, dnx, dny, detj, jac)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(group_size, 4), yl(group_size, 4)
    real(ek), intent(out) :: dnx(group_size, 4, 4), dny(group_size, 4, 4), detj(group_size, 4), jac(group_size, 4, 4)
    real(ek) :: a1, a2, a3, c1, c2, c3, x_xi, x_eta, y_xi, y_eta, r, n_xi, n_eta
    integer :: i, k, g
    do g = 1, 4
      do i = 1, m
        a1 = 0.25_ek * ((xl(i, 2) - xl(i, 1)) + (xl(i, 3) - xl(i, 4)))
        a2 = 0.25_ek * ((xl(i, 3) - xl(i, 2)) + (xl(i, 4) - xl(i, 1)))
        a3 = 0.25_ek * ((xl(i, 1) - xl(i, 2)) + (xl(i, 3) - xl(i, 4)))
        c1 = 0.25_ek * ((yl(i, 2) - yl(i, 1)) + (yl(i, 3) - yl(i, 4)))
        c2 = 0.25_ek * ((yl(i, 3) - yl(i, 2)) + (yl(i, 4) - yl(i, 1)))
        c3 = 0.25_ek * ((yl(i, 1) - yl(i, 2)) + (yl(i, 3) - yl(i, 4)))
        x_xi = a1 + eta_g(g) * a3
        x_eta = a2 + xi_g(g) * a3
        y_xi = c1 + eta_g(g) * c3
        y_eta = c2 + xi_g(g) * c3
        detj(i, g) = x_xi * y_eta - y_xi * x_eta
        jac(i, 1, g) = x_xi
        jac(i, 2, g) = y_xi
        jac(i, 3, g) = x_eta
        jac(i, 4, g) = y_eta
        r = 1.0_ek / merge(detj(i, g), 1.0_ek, detj(i, g) > 0.0_ek)
        do k = 1, 4
          n_xi = 0.25_ek * xi_n(k) * (1.0_ek + eta_n(k) * eta_g(g))
          n_eta = 0.25_ek * eta_n(k) * (1.0_ek + xi_n(k) * xi_g(g))
          dnx(i, k, g) = r * (y_eta * n_xi - y_xi * n_eta)
          dny(i, k, g) = r * (x_xi * n_eta - x_eta * n_xi)
        end do
      end do
    end do
  end subroutine point_geometry

  !> Rates at the 4 in-plane points: membrane d = (vx_x, vy_y, vx_y + vy_x), curvature
  !> (thy_x, -thx_y, thy_y - thx_x) with thx = wl1, thy = wl2, and the MITC4 transverse shear:
  !> the covariant strains at the edge midpoints A (1-2), C (4-3) for gamma_xi and D (1-4),
  !> B (2-3) for gamma_eta, each w_s + (x_s th_y - y_s th_x) along the edge s, interpolated
  !> and turned to local axes by the inverse Jacobian.
  pure subroutine point_rates(m, xl, yl, vl, wl, dnx, dny, detj, jac, rates)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(group_size, 4), yl(group_size, 4), vl(group_size, 3, 4), wl(group_size, 3, 4)
    real(ek), intent(in) :: dnx(group_size, 4, 4), dny(group_size, 4, 4), detj(group_size, 4), jac(group_size, 4, 4)
    real(ek), intent(out) :: rates(group_size, 8, 4)
    real(ek) :: g_xi, g_eta, r, r1, r2, r3, r4, r5, r6
    real(ek) :: tie(group_size, 4)   !< the covariant shear rates at the tying points A, B, C, D
    integer :: i, k, g
    do i = 1, m
      tie(i, 1) = tying_strain(i, 1, 2)
      tie(i, 2) = tying_strain(i, 2, 3)
      tie(i, 3) = tying_strain(i, 4, 3)
      tie(i, 4) = tying_strain(i, 1, 4)
    end do
    do g = 1, 4
      do i = 1, m
        r1 = 0.0_ek
        r2 = 0.0_ek
        r3 = 0.0_ek
        r4 = 0.0_ek
        r5 = 0.0_ek
        r6 = 0.0_ek
        do k = 1, 4
          r1 = r1 + dnx(i, k, g) * vl(i, 1, k)
          r2 = r2 + dny(i, k, g) * vl(i, 2, k)
          r3 = r3 + (dny(i, k, g) * vl(i, 1, k) + dnx(i, k, g) * vl(i, 2, k))
          r4 = r4 + dnx(i, k, g) * wl(i, 2, k)
          r5 = r5 - dny(i, k, g) * wl(i, 1, k)
          r6 = r6 + (dny(i, k, g) * wl(i, 2, k) - dnx(i, k, g) * wl(i, 1, k))
        end do
        rates(i, 1, g) = r1
        rates(i, 2, g) = r2
        rates(i, 3, g) = r3
        rates(i, 4, g) = r4
        rates(i, 5, g) = r5
        rates(i, 6, g) = r6
        g_xi = 0.5_ek * ((1.0_ek - eta_g(g)) * tie(i, 1) + (1.0_ek + eta_g(g)) * tie(i, 3))
        g_eta = 0.5_ek * ((1.0_ek - xi_g(g)) * tie(i, 4) + (1.0_ek + xi_g(g)) * tie(i, 2))
        r = 1.0_ek / merge(detj(i, g), 1.0_ek, detj(i, g) > 0.0_ek)
        rates(i, 7, g) = r * (jac(i, 4, g) * g_xi - jac(i, 2, g) * g_eta)
        rates(i, 8, g) = r * (jac(i, 1, g) * g_eta - jac(i, 3, g) * g_xi)
      end do
    end do
  contains
    !> The covariant transverse shear rate at the midpoint of the edge from node a to node b.
    pure real(ek) function tying_strain(i, a, b) result(gs)
      integer, intent(in) :: i, a, b
      gs = 0.5_ek * (vl(i, 3, b) - vl(i, 3, a)) &
           + 0.25_ek * ((xl(i, b) - xl(i, a)) * (wl(i, 2, a) + wl(i, 2, b)) &
                        - (yl(i, b) - yl(i, a)) * (wl(i, 1, a) + wl(i, 1, b)))
    end function tying_strain
  end subroutine point_rates

  !> The centre derivatives B1 = dN/dx, B2 = dN/dy (those of the one-point element) of elements
  !> 1..m, for the twist term of a warped element.
  pure subroutine centre_gradients(m, xl, yl, area, b1, b2)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(group_size, 4), yl(group_size, 4), area(group_size)
    real(ek), intent(out) :: b1(group_size, 4), b2(group_size, 4)
    real(ek) :: r
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
    end do
  end subroutine centre_gradients

  !> Each node's rotation rate about the normal relative to the element's in-plane spin (slots
  !> 6:9, as shell_warping's warp_curvature reads them; 1:5 unused).
  pure subroutine drilling_rates(m, b1, b2, vl, wl, drill)
    integer, intent(in) :: m
    real(ek), intent(in) :: b1(group_size, 4), b2(group_size, 4), vl(group_size, 3, 4), wl(group_size, 3, 4)
    real(ek), intent(out) :: drill(group_size, 9)
    real(ek) :: spin
    integer :: i, k
    drill = 0.0_ek
    do i = 1, m
      spin = 0.0_ek
      do k = 1, 4
        spin = spin + (b1(i, k) * vl(i, 2, k) - b2(i, k) * vl(i, 1, k))
      end do
      do k = 1, 4
        drill(i, 5 + k) = wl(i, 3, k) - 0.5_ek * spin
      end do
    end do
  end subroutine drilling_rates

  !> Local nodal forces (1:3) and moments (4:6) of elements 1..m from the resultants at the 4
  !> in-plane points: the transposes of point_rates' maps, the Gauss weights being the Jacobian
  !> determinants (the shear's cancel against its inverse Jacobian).
  pure subroutine nodal_forces(m, xl, yl, dnx, dny, detj, jac, res, fl)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(group_size, 4), yl(group_size, 4)
    real(ek), intent(in) :: dnx(group_size, 4, 4), dny(group_size, 4, 4), detj(group_size, 4), jac(group_size, 4, 4)
    real(ek), intent(in) :: res(group_size, 8, 4)
    real(ek), intent(out) :: fl(group_size, 6, 4)
    real(ek) :: ga, gb, gc, gd, p_xi, p_eta, f1, f2, f4, f5, mx, my, gt(4)
    integer :: i, k, g, ta(4), tb(4)
    do i = 1, m
      ! the forces conjugate to the tying strains
      ga = 0.0_ek
      gb = 0.0_ek
      gc = 0.0_ek
      gd = 0.0_ek
      do g = 1, 4
        p_xi = res(i, 7, g) * jac(i, 4, g) - res(i, 8, g) * jac(i, 3, g)
        p_eta = res(i, 8, g) * jac(i, 1, g) - res(i, 7, g) * jac(i, 2, g)
        ga = ga + 0.5_ek * (1.0_ek - eta_g(g)) * p_xi
        gc = gc + 0.5_ek * (1.0_ek + eta_g(g)) * p_xi
        gd = gd + 0.5_ek * (1.0_ek - xi_g(g)) * p_eta
        gb = gb + 0.5_ek * (1.0_ek + xi_g(g)) * p_eta
      end do
      do k = 1, 4
        f1 = 0.0_ek
        f2 = 0.0_ek
        f4 = 0.0_ek
        f5 = 0.0_ek
        do g = 1, 4
          f1 = f1 + detj(i, g) * (dnx(i, k, g) * res(i, 1, g) + dny(i, k, g) * res(i, 3, g))
          f2 = f2 + detj(i, g) * (dny(i, k, g) * res(i, 2, g) + dnx(i, k, g) * res(i, 3, g))
          f4 = f4 - detj(i, g) * (dny(i, k, g) * res(i, 5, g) + dnx(i, k, g) * res(i, 6, g))
          f5 = f5 + detj(i, g) * (dnx(i, k, g) * res(i, 4, g) + dny(i, k, g) * res(i, 6, g))
        end do
        fl(i, 1, k) = f1
        fl(i, 2, k) = f2
        fl(i, 3, k) = 0.0_ek
        fl(i, 4, k) = f4
        fl(i, 5, k) = f5
        fl(i, 6, k) = 0.0_ek
      end do
      ! the tying strain of the edge a -> b: force -+ gt / 2 on w of a, b; moments
      ! (-(y_b - y_a), x_b - x_a) gt / 4 on both
      ta = [1, 2, 4, 1]
      tb = [2, 3, 3, 4]
      gt = [ga, gb, gc, gd]
      do k = 1, 4
        mx = -0.25_ek * (yl(i, tb(k)) - yl(i, ta(k))) * gt(k)
        my = 0.25_ek * (xl(i, tb(k)) - xl(i, ta(k))) * gt(k)
        fl(i, 3, ta(k)) = fl(i, 3, ta(k)) - 0.5_ek * gt(k)
        fl(i, 3, tb(k)) = fl(i, 3, tb(k)) + 0.5_ek * gt(k)
        fl(i, 4, ta(k)) = fl(i, 4, ta(k)) + mx
        fl(i, 4, tb(k)) = fl(i, 4, tb(k)) + mx
        fl(i, 5, ta(k)) = fl(i, 5, ta(k)) + my
        fl(i, 5, tb(k)) = fl(i, 5, tb(k)) + my
      end do
    end do
  end subroutine nodal_forces

  !> A warped element's terms on its local corner forces fl (shell_warping, as shell_blt's
  !> nodal_forces): the twist's forces dh B and drilling moments dh / 2, and the rigid links'
  !> moments z (f x e3), z = h_k zw; a flat element (zw = 0) keeps its forces bitwise.
  pure subroutine warp_forces(m, zw, dh, b1, b2, fl)
    integer, intent(in) :: m
    real(ek), intent(in) :: zw(group_size), dh(group_size), b1(group_size, 4), b2(group_size, 4)
    real(ek), intent(inout) :: fl(group_size, 6, 4)
    real(ek) :: g1, g2
    integer :: i, k
    do k = 1, 4
      do i = 1, m
        g1 = fl(i, 1, k) + dh(i) * b2(i, k)
        g2 = fl(i, 2, k) - dh(i) * b1(i, k)
        fl(i, 4, k) = merge(fl(i, 4, k) + (hw(k) * zw(i)) * g2, fl(i, 4, k), zw(i) /= 0.0_ek)
        fl(i, 5, k) = merge(fl(i, 5, k) - (hw(k) * zw(i)) * g1, fl(i, 5, k), zw(i) /= 0.0_ek)
        fl(i, 6, k) = merge(fl(i, 6, k) + 0.5_ek * dh(i), fl(i, 6, k), zw(i) /= 0.0_ek)
        fl(i, 1, k) = merge(g1, fl(i, 1, k), zw(i) /= 0.0_ek)
        fl(i, 2, k) = merge(g2, fl(i, 2, k), zw(i) /= 0.0_ek)
      end do
    end do
  end subroutine warp_forces

end module shell_full
