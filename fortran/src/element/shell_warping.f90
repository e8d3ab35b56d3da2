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
!> so a flat mesh gives bitwise the results of the uncorrected element. This module gives the
!> per-element terms (zw, the twist of the curvature rates, D); the per-node terms ride in
!> shell_blt's own loops over the local velocities (strain_rates) and local forces
!> (nodal_forces), where they cost a few operations and no extra memory traffic. Pure kernels
!> over the elements of a group, element index innermost, as shell_blt.
module shell_warping
  use paradyn_kinds, only: wp, ek
  use element_groups, only: group_size
  implicit none
  private
  public :: warp_heights, warp_curvature, warp_twist_moment

  !> warp |zw| / sqrt(area) below which an element counts as flat (rounding of a planar quad):
  !> 1e-10 in double; in single (the mixed engine) the rounding of the positions alone is near
  !> 1e-7, so there it is a hundred times the kind's epsilon (1.2e-5)
  real(ek), parameter :: flat_warp = max(1.0e-10_ek, 100 * epsilon(1.0_ek))

contains

  !> zw of elements o+1..o+m of x (node heights z_I = zw h_I above the mean plane of normal e3
  !> through the centroid); zero for a flat element or one of area <= 0. The positions are double
  !> (wp), their differences rounded to the kernel's kind.
  pure subroutine warp_heights(m, ld, o, x, e, area, zw)
    integer, intent(in) :: m, ld, o
    real(wp), intent(in) :: x(ld, 3, 4)
    real(ek), intent(in) :: e(group_size, 3, 3), area(group_size)
    real(ek), intent(out) :: zw(group_size)
    real(ek) :: hx, hy, hz, a
    integer :: i
    do i = 1, m
      hx = real((x(o + i, 1, 1) - x(o + i, 1, 2)) + (x(o + i, 1, 3) - x(o + i, 1, 4)), ek)
      hy = real((x(o + i, 2, 1) - x(o + i, 2, 2)) + (x(o + i, 2, 3) - x(o + i, 2, 4)), ek)
      hz = real((x(o + i, 3, 1) - x(o + i, 3, 2)) + (x(o + i, 3, 3) - x(o + i, 3, 4)), ek)
      a = merge(area(i), 1.0_ek, area(i) > 0.0_ek)
      zw(i) = 0.25_ek * (hx * e(i, 1, 3) + hy * e(i, 2, 3) + hz * e(i, 3, 3))
      zw(i) = merge(zw(i), 0.0_ek, area(i) > 0.0_ek .and. abs(zw(i)) > flat_warp * sqrt(a))
    end do
  end subroutine warp_heights

  !> Reference curvature (b_xx, b_yy, b_xy) of the twisted mid-surface z = zw xi eta at the centre,
  !> from the shape-function derivatives (xi_x = sum xi_I B1_I, ...).
  elemental subroutine twist_curvature(zw, b11, b12, b13, b14, b21, b22, b23, b24, bxx, byy, bxy)
    real(ek), intent(in) :: zw, b11, b12, b13, b14, b21, b22, b23, b24
    real(ek), intent(out) :: bxx, byy, bxy
    real(ek) :: xi_x, xi_y, eta_x, eta_y
    xi_x = (b12 - b11) + (b13 - b14)
    xi_y = (b22 - b21) + (b23 - b24)
    eta_x = (b13 - b11) + (b14 - b12)
    eta_y = (b23 - b21) + (b24 - b22)
    bxx = 2.0_ek * zw * (xi_x * eta_x)
    byy = 2.0_ek * zw * (xi_y * eta_y)
    bxy = zw * (xi_x * eta_y + xi_y * eta_x)
  end subroutine twist_curvature

  !> Mid-step: the twist term b (wz - spin) added to the curvature rates (rates 4:6) of elements
  !> 1..m; wz - spin is the mean of the drilling rates qrate(6:9).
  pure subroutine warp_curvature(m, zw, b1, b2, qrate, rates)
    integer, intent(in) :: m
    real(ek), intent(in) :: zw(group_size), b1(group_size, 4), b2(group_size, 4), qrate(group_size, 9)
    real(ek), intent(inout) :: rates(group_size, 8)
    real(ek) :: bxx, byy, bxy, d
    integer :: i
    if (.not. any(zw(1:m) /= 0.0_ek)) return
    do i = 1, m
      call twist_curvature(zw(i), b1(i, 1), b1(i, 2), b1(i, 3), b1(i, 4), b2(i, 1), b2(i, 2), b2(i, 3), b2(i, 4), &
                           bxx, byy, bxy)
      d = 0.25_ek * ((qrate(i, 6) + qrate(i, 7)) + (qrate(i, 8) + qrate(i, 9)))
      rates(i, 4) = merge(rates(i, 4) + bxy * d, rates(i, 4), zw(i) /= 0.0_ek)
      rates(i, 5) = merge(rates(i, 5) - bxy * d, rates(i, 5), zw(i) /= 0.0_ek)
      rates(i, 6) = merge(rates(i, 6) + (byy - bxx) * d, rates(i, 6), zw(i) /= 0.0_ek)
    end do
  end subroutine warp_curvature

  !> End of step: zw of elements o+1..o+m of x and half the conjugate of their twist term,
  !> dh = D / 2 = A (M_xx b_xy - M_yy b_xy + M_xy (b_yy - b_xx)) / 2, for the nodal forces
  !> (shell_blt's nodal_forces adds the moments of the rigid links and the twist's forces).
  pure subroutine warp_twist_moment(m, ld, o, x, e, area, b1, b2, res, zw, dh)
    integer, intent(in) :: m, ld, o
    real(wp), intent(in) :: x(ld, 3, 4)
    real(ek), intent(in) :: e(group_size, 3, 3), area(group_size)
    real(ek), intent(in) :: b1(group_size, 4), b2(group_size, 4), res(group_size, 8)
    real(ek), intent(out) :: zw(group_size), dh(group_size)
    real(ek) :: bxx, byy, bxy
    integer :: i
    call warp_heights(m, ld, o, x, e, area, zw)
    dh = 0.0_ek
    if (.not. any(zw(1:m) /= 0.0_ek)) return
    do i = 1, m
      call twist_curvature(zw(i), b1(i, 1), b1(i, 2), b1(i, 3), b1(i, 4), b2(i, 1), b2(i, 2), b2(i, 3), b2(i, 4), &
                           bxx, byy, bxy)
      dh(i) = 0.5_ek * area(i) * ((res(i, 4) - res(i, 5)) * bxy + res(i, 6) * (byy - bxx))
    end do
  end subroutine warp_twist_moment

end module shell_warping
