!> Warping correction of the Belytschko-Lin-Tsay shell (docs/theory.md, "Warping correction").
!>
!> The plain BLT element treats its four nodes as if they lay in the element's mean plane. With
!> the normal e3 taken normal to both diagonals, the nodes of a warped element sit at heights
!> z_I = zw h_I above that plane (h = 1, -1, 1, -1): the mid-surface is the hyperbolic paraboloid
!> z = zw xi eta, twisted. Two corrections follow, in the manner of Belytschko, Wong & Chiang
!> (1992) and of the rigid-body projection of Belytschko & Leviathan (1994):
!>
!> - offsets: each node is tied to its projection onto the mean plane by a rigid link of length
!>   z_I along e3, so the flat element sees the velocities v_I - z_I (w_I x e3); the links carry
!>   the moments z_I (f_I x e3) back to the nodes. A rigid rotation of a warped element is then a
!>   rigid motion of the flat one: no strain, no hourglass or drilling rate.
!> - twist: the curvature rate gains b (wz - spin), the reference curvature b of the twisted
!>   surface (b_xx = 2 zw xi_x eta_x, b_yy = 2 zw xi_y eta_y, b_xy = zw (xi_x eta_y + xi_y eta_x))
!>   times the element's mean nodal rotation about e3 relative to its in-plane spin:
!>   kappa_xx += b_xy d, kappa_yy -= b_xy d, 2 kappa_xy += (b_yy - b_xx) d, the term theta x dn/dx
!>   that a flat element drops. Its conjugate acts like a drilling moment D/4 at each node,
!>   D = A (M_xx b_xy - M_yy b_xy + M_xy (b_yy - b_xx)).
!>
!> Both vanish for a flat element (zw = 0). An element whose warp is below flat_warp of the
!> square root of its area counts as flat, and its values are passed through untouched (merge),
!> so a flat mesh gives bitwise the results of the uncorrected element. Pure kernels over the
!> elements of a group, element index innermost, as shell_blt.
module shell_warping
  use paradyn_kinds, only: wp
  use element_groups, only: group_size
  implicit none
  private
  public :: warp_velocities, warp_curvature, warp_forces

  !> warp |zw| / sqrt(area) below which an element counts as flat (rounding of a planar quad)
  real(wp), parameter :: flat_warp = 1.0e-10_wp

contains

  !> zw of elements o+1..o+m of x (node heights z_I = zw h_I above the mean plane of normal e3
  !> through the centroid); zero for a flat element or one of area <= 0.
  pure subroutine warp_heights(m, ld, o, x, e, area, zw)
    integer, intent(in) :: m, ld, o
    real(wp), intent(in) :: x(ld, 3, 4), e(group_size, 3, 3), area(group_size)
    real(wp), intent(out) :: zw(group_size)
    real(wp) :: hx, hy, hz, a
    integer :: i
    do i = 1, m
      hx = (x(o + i, 1, 1) - x(o + i, 1, 2)) + (x(o + i, 1, 3) - x(o + i, 1, 4))
      hy = (x(o + i, 2, 1) - x(o + i, 2, 2)) + (x(o + i, 2, 3) - x(o + i, 2, 4))
      hz = (x(o + i, 3, 1) - x(o + i, 3, 2)) + (x(o + i, 3, 3) - x(o + i, 3, 4))
      a = merge(area(i), 1.0_wp, area(i) > 0.0_wp)
      zw(i) = 0.25_wp * (hx * e(i, 1, 3) + hy * e(i, 2, 3) + hz * e(i, 3, 3))
      zw(i) = merge(zw(i), 0.0_wp, area(i) > 0.0_wp .and. abs(zw(i)) > flat_warp * sqrt(a))
    end do
  end subroutine warp_heights

  !> Mid-step: zw of the elements 1..m of xg, and their velocities v moved to the mean plane,
  !> v_I - z_I (w_I x e3), in place.
  pure subroutine warp_velocities(m, xg, e, area, w, v, zw)
    integer, intent(in) :: m
    real(wp), intent(in) :: xg(group_size, 3, 4), e(group_size, 3, 3), area(group_size)
    real(wp), intent(in) :: w(group_size, 3, 4)
    real(wp), intent(inout) :: v(group_size, 3, 4)
    real(wp), intent(out) :: zw(group_size)
    real(wp) :: z, h
    integer :: i, k
    call warp_heights(m, group_size, 0, xg, e, area, zw)
    if (.not. any(zw(1:m) /= 0.0_wp)) return
    do k = 1, 4
      h = merge(1.0_wp, -1.0_wp, k == 1 .or. k == 3)
      do i = 1, m
        z = h * zw(i)
        v(i, 1, k) = merge(v(i, 1, k) - z * (w(i, 2, k) * e(i, 3, 3) - w(i, 3, k) * e(i, 2, 3)), v(i, 1, k), z /= 0.0_wp)
        v(i, 2, k) = merge(v(i, 2, k) - z * (w(i, 3, k) * e(i, 1, 3) - w(i, 1, k) * e(i, 3, 3)), v(i, 2, k), z /= 0.0_wp)
        v(i, 3, k) = merge(v(i, 3, k) - z * (w(i, 1, k) * e(i, 2, 3) - w(i, 2, k) * e(i, 1, 3)), v(i, 3, k), z /= 0.0_wp)
      end do
    end do
  end subroutine warp_velocities

  !> Reference curvature (b_xx, b_yy, b_xy) of the twisted mid-surface z = zw xi eta at the centre,
  !> from the shape-function derivatives (xi_x = sum xi_I B1_I, ...).
  elemental subroutine twist_curvature(zw, b11, b12, b13, b14, b21, b22, b23, b24, bxx, byy, bxy)
    real(wp), intent(in) :: zw, b11, b12, b13, b14, b21, b22, b23, b24
    real(wp), intent(out) :: bxx, byy, bxy
    real(wp) :: xi_x, xi_y, eta_x, eta_y
    xi_x = (b12 - b11) + (b13 - b14)
    xi_y = (b22 - b21) + (b23 - b24)
    eta_x = (b13 - b11) + (b14 - b12)
    eta_y = (b23 - b21) + (b24 - b22)
    bxx = 2.0_wp * zw * (xi_x * eta_x)
    byy = 2.0_wp * zw * (xi_y * eta_y)
    bxy = zw * (xi_x * eta_y + xi_y * eta_x)
  end subroutine twist_curvature

  !> Mid-step: the twist term b (wz - spin) added to the curvature rates (rates 4:6) of elements
  !> 1..m; wz - spin is the mean of the drilling rates qrate(6:9).
  pure subroutine warp_curvature(m, zw, b1, b2, qrate, rates)
    integer, intent(in) :: m
    real(wp), intent(in) :: zw(group_size), b1(group_size, 4), b2(group_size, 4), qrate(group_size, 9)
    real(wp), intent(inout) :: rates(group_size, 8)
    real(wp) :: bxx, byy, bxy, d
    integer :: i
    if (.not. any(zw(1:m) /= 0.0_wp)) return
    do i = 1, m
      call twist_curvature(zw(i), b1(i, 1), b1(i, 2), b1(i, 3), b1(i, 4), b2(i, 1), b2(i, 2), b2(i, 3), b2(i, 4), &
                           bxx, byy, bxy)
      d = 0.25_wp * ((qrate(i, 6) + qrate(i, 7)) + (qrate(i, 8) + qrate(i, 9)))
      rates(i, 4) = merge(rates(i, 4) + bxy * d, rates(i, 4), zw(i) /= 0.0_wp)
      rates(i, 5) = merge(rates(i, 5) - bxy * d, rates(i, 5), zw(i) /= 0.0_wp)
      rates(i, 6) = merge(rates(i, 6) + (byy - bxx) * d, rates(i, 6), zw(i) /= 0.0_wp)
    end do
  end subroutine warp_curvature

  !> End of step: the forces of the corrections added to the nodal forces and moments f (global
  !> axes) of elements o+1..o+m of x: first the conjugate of the twist term (a drilling moment
  !> D/4 at each node with its in-plane forces D/2 (B2, -B1)), then the moments of the rigid links,
  !> z_I (f_I x e3).
  pure subroutine warp_forces(m, ld, o, x, e, area, b1, b2, res, f)
    integer, intent(in) :: m, ld, o
    real(wp), intent(in) :: x(ld, 3, 4), e(group_size, 3, 3), area(group_size)
    real(wp), intent(in) :: b1(group_size, 4), b2(group_size, 4), res(group_size, 8)
    real(wp), intent(inout) :: f(group_size, 6, 4)
    real(wp) :: zw(group_size), dm(group_size)
    real(wp) :: bxx, byy, bxy, f1, f2, fx, fy, fz, z, h
    integer :: i, k
    call warp_heights(m, ld, o, x, e, area, zw)
    if (.not. any(zw(1:m) /= 0.0_wp)) return
    do i = 1, m
      call twist_curvature(zw(i), b1(i, 1), b1(i, 2), b1(i, 3), b1(i, 4), b2(i, 1), b2(i, 2), b2(i, 3), b2(i, 4), &
                           bxx, byy, bxy)
      dm(i) = area(i) * ((res(i, 4) - res(i, 5)) * bxy + res(i, 6) * (byy - bxx))
    end do
    do k = 1, 4
      h = merge(1.0_wp, -1.0_wp, k == 1 .or. k == 3)
      do i = 1, m
        f1 = 0.5_wp * dm(i) * b2(i, k)
        f2 = -0.5_wp * dm(i) * b1(i, k)
        fx = f(i, 1, k) + (e(i, 1, 1) * f1 + e(i, 1, 2) * f2)
        fy = f(i, 2, k) + (e(i, 2, 1) * f1 + e(i, 2, 2) * f2)
        fz = f(i, 3, k) + (e(i, 3, 1) * f1 + e(i, 3, 2) * f2)
        z = h * zw(i)
        f(i, 4, k) = merge(f(i, 4, k) + 0.25_wp * dm(i) * e(i, 1, 3) + z * (fy * e(i, 3, 3) - fz * e(i, 2, 3)), &
                           f(i, 4, k), z /= 0.0_wp)
        f(i, 5, k) = merge(f(i, 5, k) + 0.25_wp * dm(i) * e(i, 2, 3) + z * (fz * e(i, 1, 3) - fx * e(i, 3, 3)), &
                           f(i, 5, k), z /= 0.0_wp)
        f(i, 6, k) = merge(f(i, 6, k) + 0.25_wp * dm(i) * e(i, 3, 3) + z * (fx * e(i, 2, 3) - fy * e(i, 1, 3)), &
                           f(i, 6, k), z /= 0.0_wp)
        f(i, 1, k) = merge(fx, f(i, 1, k), z /= 0.0_wp)
        f(i, 2, k) = merge(fy, f(i, 2, k), z /= 0.0_wp)
        f(i, 3, k) = merge(fz, f(i, 3, k), z /= 0.0_wp)
      end do
    end do
  end subroutine warp_forces

end module shell_warping
