!> The co-rotational frames of a group of quadrilaterals, shared by the one-point element (shell_blt)
!> and the fully integrated one (shell_full): each element's mid-surface frame, its nodes' local
!> coordinates and its projected area, vectorised over the group, and the check that keeps the area
!> only for elements that are sound at mid-step and at the end of the step; and the store of the
!> elements' corner forces, computed element first, into the engine's corner layout (the triangle
!> uses it too). Pure, no module state.
module shell_frames
  use paradyn_kinds, only: wp, ek
  use element_groups, only: group_size
  implicit none
  private
  public :: frames, check_end_frames, store_corner_forces

contains

  !> (The frame of the one-point element, shell_blt, and of the fully integrated one, shell_full.)
  !> local_frame of elements o+1..o+m of x (mid-surface frame, local node coordinates, projected
  !> area), with |a| = sqrt(a . a) in place of norm2 and a unit vector a * (1 / |a|): one division
  !> per vector, not three; results for 1..m. The positions are double (wp); every measure is a
  !> difference of them, taken in double and then rounded to the kernel's kind: in the mixed
  !> engine single precision resolves the element's size, not its distance from the origin.
  pure subroutine frames(m, ld, o, x, e, xl, yl, area)
    integer, intent(in) :: m, ld, o
    real(wp), intent(in) :: x(ld, 3, 4)
    real(ek), intent(out) :: e(group_size, 3, 3), xl(group_size, 4), yl(group_size, 4), area(group_size)
    real(ek) :: d31x, d31y, d31z, d42x, d42y, d42z, nx, ny, nz, gx, gy, gz, r, cx, cy, cz
    real(ek) :: e11, e21, e31, e12, e22, e32
    real(wp) :: mx, my, mz
    integer :: i, k
    ! one pass: the frame, then each node's local coordinates from the centre computed once
    do i = 1, m
      d31x = real(x(o + i, 1, 3) - x(o + i, 1, 1), ek)
      d31y = real(x(o + i, 2, 3) - x(o + i, 2, 1), ek)
      d31z = real(x(o + i, 3, 3) - x(o + i, 3, 1), ek)
      d42x = real(x(o + i, 1, 4) - x(o + i, 1, 2), ek)
      d42y = real(x(o + i, 2, 4) - x(o + i, 2, 2), ek)
      d42z = real(x(o + i, 3, 4) - x(o + i, 3, 2), ek)
      nx = d31y * d42z - d31z * d42y
      ny = d31z * d42x - d31x * d42z
      nz = d31x * d42y - d31y * d42x
      r = 1.0_ek / sqrt(nx * nx + ny * ny + nz * nz)
      nx = nx * r
      ny = ny * r
      nz = nz * r
      gx = real(x(o + i, 1, 2) + x(o + i, 1, 3) - x(o + i, 1, 1) - x(o + i, 1, 4), ek)
      gy = real(x(o + i, 2, 2) + x(o + i, 2, 3) - x(o + i, 2, 1) - x(o + i, 2, 4), ek)
      gz = real(x(o + i, 3, 2) + x(o + i, 3, 3) - x(o + i, 3, 1) - x(o + i, 3, 4), ek)
      r = gx * nx + gy * ny + gz * nz
      gx = gx - r * nx
      gy = gy - r * ny
      gz = gz - r * nz
      r = 1.0_ek / sqrt(gx * gx + gy * gy + gz * gz)
      e11 = gx * r
      e21 = gy * r
      e31 = gz * r
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
      mx = 0.25_wp * (x(o + i, 1, 1) + x(o + i, 1, 2) + x(o + i, 1, 3) + x(o + i, 1, 4))
      my = 0.25_wp * (x(o + i, 2, 1) + x(o + i, 2, 2) + x(o + i, 2, 3) + x(o + i, 2, 4))
      mz = 0.25_wp * (x(o + i, 3, 1) + x(o + i, 3, 2) + x(o + i, 3, 3) + x(o + i, 3, 4))
      do k = 1, 4   ! unrolled by the compiler: the loop over i vectorises
        cx = real(x(o + i, 1, k) - mx, ek)
        cy = real(x(o + i, 2, k) - my, ek)
        cz = real(x(o + i, 3, k) - mz, ek)
        xl(i, k) = cx * e11 + cy * e21 + cz * e31
        yl(i, k) = cx * e12 + cy * e22 + cz * e32
      end do
      area(i) = 0.5_ek * ((xl(i, 3) - xl(i, 1)) * (yl(i, 4) - yl(i, 2)) &
                          - (xl(i, 4) - xl(i, 2)) * (yl(i, 3) - yl(i, 1)))
    end do
  end subroutine frames

  !> Keeps area > 0 only for elements valid at mid-step and at the end of the step: positive
  !> area, the normal not flipped, and every corner of the projected quad turning the same way as
  !> the normal (positive corner Jacobians). An element turned inside out during a step fails
  !> this, or flips its normal.
  pure subroutine check_end_frames(m, area_mid, normal_mid, e, xl, yl, area)
    integer, intent(in) :: m
    real(ek), intent(in) :: area_mid(group_size), normal_mid(group_size, 3), e(group_size, 3, 3)
    real(ek), intent(in) :: xl(group_size, 4), yl(group_size, 4)
    real(ek), intent(inout) :: area(group_size)
    real(ek) :: turn(group_size)
    integer :: i, k, next, prev
    turn = huge(1.0_ek)
    do k = 1, 4
      next = modulo(k, 4) + 1
      prev = modulo(k + 2, 4) + 1
      do i = 1, m
        turn(i) = min(turn(i), (xl(i, next) - xl(i, k)) * (yl(i, prev) - yl(i, k)) &
                               - (yl(i, next) - yl(i, k)) * (xl(i, prev) - xl(i, k)))
      end do
    end do
    do i = 1, m
      area(i) = merge(area(i), 0.0_ek, area_mid(i) > 0.0_ek .and. area(i) > 0.0_ek .and. turn(i) > 0.0_ek &
                      .and. normal_mid(i, 1) * e(i, 1, 3) + normal_mid(i, 2) * e(i, 2, 3) &
                            + normal_mid(i, 3) * e(i, 3, 3) > 0.0_ek)
    end do
  end subroutine check_end_frames

  !> The corner forces and moments of elements o+1..o+m, local(i, c, k) element first as the
  !> kernels compute them, into the engine's corner layout force(c, k, o + i) for corners 1..corners
  !> (through a local array: stored straight into force, gfortran needs too many alias checks).
  pure subroutine store_corner_forces(m, n, o, corners, local, force)
    integer, intent(in) :: m, n, o, corners
    real(ek), intent(in) :: local(group_size, 6, corners)
    real(wp), intent(inout) :: force(6, 4, n)
    integer :: i, k, c
    do i = 1, m
      do k = 1, corners
        do c = 1, 6
          force(c, k, o + i) = local(i, c, k)
        end do
      end do
    end do
  end subroutine store_corner_forces

end module shell_frames
