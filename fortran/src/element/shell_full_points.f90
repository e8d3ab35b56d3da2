!> The in-plane point kernels of the fully integrated shell (shell_full): the bilinear map's
!> Jacobian and shape-function derivatives at the 2 x 2 Gauss points, the strain rates there with
!> the MITC4 transverse shear (Dvorkin & Bathe 1984: covariant shear strains tied at the edge
!> midpoints), and the nodal forces and moments, their transposes. Pure, over the elements of a
!> group, element index first; local frame of shell_blt's frames.
module shell_full_points
  use paradyn_kinds, only: ek
  use element_groups, only: group_size
  implicit none
  private
  public :: full_points, point_geometry, point_rates, nodal_forces

  integer, parameter :: full_points = 4   !< in-plane Gauss points
  real(ek), parameter :: gq = 0.57735026918962576_ek   !< 1 / sqrt(3)
  !> the in-plane points (counter-clockwise from node 1's corner) and the nodes' natural coordinates
  real(ek), parameter :: xi_g(4) = [-gq, gq, gq, -gq], eta_g(4) = [-gq, -gq, gq, gq]
  real(ek), parameter :: xi_n(4) = [-1.0_ek, 1.0_ek, 1.0_ek, -1.0_ek], eta_n(4) = [-1.0_ek, -1.0_ek, 1.0_ek, 1.0_ek]
  !> the edges of the tying points A, B, C, D: from node tying_from to node tying_to
  integer, parameter :: tying_from(4) = [1, 2, 4, 1], tying_to(4) = [2, 3, 3, 4]

contains

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
    integer :: i, k, g, a, b
    ! the covariant transverse shear rate at the midpoint of each tying edge, from node a to b
    do k = 1, 4
      a = tying_from(k)
      b = tying_to(k)
      do i = 1, m
        tie(i, k) = 0.5_ek * (vl(i, 3, b) - vl(i, 3, a)) &
                    + 0.25_ek * ((xl(i, b) - xl(i, a)) * (wl(i, 2, a) + wl(i, 2, b)) &
                                 - (yl(i, b) - yl(i, a)) * (wl(i, 1, a) + wl(i, 1, b)))
      end do
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
  end subroutine point_rates

  !> Local nodal forces (1:3) and moments (4:6) of elements 1..m from the resultants at the 4
  !> in-plane points: the transposes of point_rates' maps, the Gauss weights being the Jacobian
  !> determinants (the shear's cancel against its inverse Jacobian).
  pure subroutine nodal_forces(m, xl, yl, dnx, dny, detj, jac, res, fl)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(group_size, 4), yl(group_size, 4)
    real(ek), intent(in) :: dnx(group_size, 4, 4), dny(group_size, 4, 4), detj(group_size, 4), jac(group_size, 4, 4)
    real(ek), intent(in) :: res(group_size, 8, 4)
    real(ek), intent(out) :: fl(group_size, 6, 4)
    real(ek) :: tie(group_size, 4)   !< the forces conjugate to the tying strains A, B, C, D
    real(ek) :: ga, gb, gc, gd, p_xi, p_eta, f1, f2, f4, f5, mx, my
    integer :: i, k, g, a, b
    do i = 1, m
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
      tie(i, 1) = ga
      tie(i, 2) = gb
      tie(i, 3) = gc
      tie(i, 4) = gd
    end do
    do k = 1, 4
      do i = 1, m
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
    end do
    ! the tying strain of the edge a -> b: force -+ tie / 2 on w of a, b; moments
    ! (-(y_b - y_a), x_b - x_a) tie / 4 on both
    do k = 1, 4
      a = tying_from(k)
      b = tying_to(k)
      do i = 1, m
        mx = -0.25_ek * (yl(i, b) - yl(i, a)) * tie(i, k)
        my = 0.25_ek * (xl(i, b) - xl(i, a)) * tie(i, k)
        fl(i, 3, a) = fl(i, 3, a) - 0.5_ek * tie(i, k)
        fl(i, 3, b) = fl(i, 3, b) + 0.5_ek * tie(i, k)
        fl(i, 4, a) = fl(i, 4, a) + mx
        fl(i, 4, b) = fl(i, 4, b) + mx
        fl(i, 5, a) = fl(i, 5, a) + my
        fl(i, 5, b) = fl(i, 5, b) + my
      end do
    end do
  end subroutine nodal_forces

end module shell_full_points
