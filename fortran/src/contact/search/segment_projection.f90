!> The closest point of a bilinear shell segment to a point (the contact's stage 3; Hallquist,
!> Goudreau & Benson 1985), in isoparametric coordinates, with the normal there.
!>
!> A master segment is a four-node quadrilateral with the bilinear surface
!>   x(xi, eta) = sum_I N_I(xi, eta) x_I,  N_I = (1 + xi xi_I)(1 + eta eta_I) / 4,
!> nodes 1..4 at (xi, eta) = (-1,-1), (1,-1), (1,1), (-1,1). A triangle is a quadrilateral with
!> nodes 3 and 4 equal. Pure: no MPI, no I/O, no module state.
module segment_projection
  use paradyn_kinds, only: wp
  use vector_algebra, only: cross
  implicit none
  private
  public :: closest_point_on_segment, segment_shape_functions, segment_distance_bound

  integer, parameter :: max_iterations = 100
  integer, parameter :: max_halvings = 60

contains

  !> Bilinear shape functions of the segment at (xi, eta).
  pure function segment_shape_functions(xi, eta) result(n)
    real(wp), intent(in) :: xi, eta
    real(wp) :: n(4)
    n = 0.25_wp * [(1.0_wp - xi) * (1.0_wp - eta), (1.0_wp + xi) * (1.0_wp - eta), &
                   (1.0_wp + xi) * (1.0_wp + eta), (1.0_wp - xi) * (1.0_wp + eta)]
  end function segment_shape_functions

  !> x(xi, eta) = a0 + a1 xi + a2 eta + a3 xi eta.
  pure subroutine bilinear_coefficients(xseg, a)
    real(wp), intent(in) :: xseg(3, 4)
    real(wp), intent(out) :: a(3, 0:3)
    a(:, 0) = 0.25_wp * (xseg(:, 1) + xseg(:, 2) + xseg(:, 3) + xseg(:, 4))
    a(:, 1) = 0.25_wp * (-xseg(:, 1) + xseg(:, 2) + xseg(:, 3) - xseg(:, 4))
    a(:, 2) = 0.25_wp * (-xseg(:, 1) - xseg(:, 2) + xseg(:, 3) + xseg(:, 4))
    a(:, 3) = 0.25_wp * (xseg(:, 1) - xseg(:, 2) + xseg(:, 3) - xseg(:, 4))
  end subroutine bilinear_coefficients

  !> |x(xi, eta) - p|^2 / 2 with a(:, 0) already taken relative to p.
  pure real(wp) function half_distance2(a, xi, eta) result(f)
    real(wp), intent(in) :: a(3, 0:3), xi, eta
    f = 0.5_wp * sum((a(:, 0) + a(:, 1) * xi + a(:, 2) * eta + a(:, 3) * (xi * eta))**2)
  end function half_distance2

  pure real(wp) function clamp(x)
    real(wp), intent(in) :: x
    clamp = min(1.0_wp, max(-1.0_wp, x))
  end function clamp

  !> Backtracking along the projected path clamp(x + alpha d): the first alpha = 1, 1/2, 1/4, ...
  !> that does not increase the distance by more than its round-off noise. Near the solution f
  !> is dominated by the normal distance and the tangential progress of a Newton step is below
  !> the resolution of f, so those steps must not be refused. ok is false when none passes.
  !> a(:, 0) is taken relative to p (p = 0 here); sizes is the sum of the norms of a(:, 0:3).
  pure subroutine projected_search(a, sizes, xi, eta, d, f, xi_new, eta_new, f_new, ok)
    real(wp), intent(in) :: a(3, 0:3), sizes, xi, eta, d(2), f
    real(wp), intent(out) :: xi_new, eta_new, f_new
    logical, intent(out) :: ok
    real(wp) :: alpha, noise
    integer :: k
    noise = 8.0_wp * epsilon(1.0_wp) * sqrt(2.0_wp * f) * sizes
    alpha = 1.0_wp
    ok = .false.
    do k = 1, max_halvings
      xi_new = clamp(xi + alpha * d(1))
      eta_new = clamp(eta + alpha * d(2))
      f_new = half_distance2(a, xi_new, eta_new)
      if (f_new <= f + noise) then
        ok = .true.
        return
      end if
      alpha = 0.5_wp * alpha
    end do
  end subroutine projected_search

  !> Closest point xc = x(xi, eta) of the bilinear segment to the point p, with (xi, eta) in
  !> [-1, 1]^2, and the unit normal dx/dxi x dx/deta there.
  !>
  !> Minimises f = |x(xi, eta) - p|^2 / 2 over the square: Newton on the two tangency
  !> equations (x - p).dx/dxi = 0, (x - p).dx/deta = 0 with an active set. A coordinate on a
  !> bound whose derivative pushes outward is held there and Newton continues along the free
  !> one, so a point beyond an edge lands on the edge and one beyond a corner on the corner.
  !> Steps follow the projected path and are halved until f does not increase; where the
  !> Hessian is not positive definite (far from a strongly warped segment) the diagonally scaled
  !> gradient is used instead. The start is the best of the 3 x 3 points (corners, mid-sides,
  !> centre), which on warped segments keeps the search in the basin of the global minimum.
  pure subroutine closest_point_on_segment(xseg, p, xi, eta, xc, normal)
    real(wp), intent(in) :: xseg(3, 4), p(3)
    real(wp), intent(out) :: xi, eta, xc(3), normal(3)
    real(wp) :: a(3, 0:3), r(3), xa(3), xb(3), g(2), h11, h12, h22, det, d(2), f, f_new
    real(wp) :: xi_new, eta_new, size2, trial, nn, sizes, shape(4)
    logical :: free(2), ok
    integer :: i, j, iter

    call bilinear_coefficients(xseg, a)
    a(:, 0) = a(:, 0) - p               ! work relative to p: less cancellation in x - p
    size2 = sum(a(:, 1:3)**2)
    ! the same for every step of the search (its round-off noise), so summed once
    sizes = norm2(a(:, 0)) + norm2(a(:, 1)) + norm2(a(:, 2)) + norm2(a(:, 3))

    xi = 0.0_wp
    eta = 0.0_wp
    f = huge(1.0_wp)
    do j = -1, 1
      do i = -1, 1
        trial = half_distance2(a, real(i, wp), real(j, wp))
        if (trial < f) then
          f = trial
          xi = real(i, wp)
          eta = real(j, wp)
        end if
      end do
    end do

    do iter = 1, max_iterations
      xa = a(:, 1) + a(:, 3) * eta
      xb = a(:, 2) + a(:, 3) * xi
      r = a(:, 0) + a(:, 1) * xi + a(:, 2) * eta + a(:, 3) * (xi * eta)
      f = 0.5_wp * sum(r**2)
      g = [dot_product(r, xa), dot_product(r, xb)]
      h11 = dot_product(xa, xa)
      h22 = dot_product(xb, xb)
      h12 = dot_product(xa, xb) + dot_product(r, a(:, 3))
      ! a coordinate is held when it sits on a bound and f decreases outward, or when the
      ! surface does not depend on it here (the collapsed side of a triangle)
      free(1) = h11 > 1.0e-14_wp * size2 .and. &
                .not. ((xi <= -1.0_wp .and. g(1) > 0.0_wp) .or. (xi >= 1.0_wp .and. g(1) < 0.0_wp))
      free(2) = h22 > 1.0e-14_wp * size2 .and. &
                .not. ((eta <= -1.0_wp .and. g(2) > 0.0_wp) .or. (eta >= 1.0_wp .and. g(2) < 0.0_wp))
      d = 0.0_wp
      if (free(1) .and. free(2)) then
        det = h11 * h22 - h12**2
        if (det > 1.0e-10_wp * h11 * h22) then
          d(1) = (h12 * g(2) - h22 * g(1)) / det
          d(2) = (h12 * g(1) - h11 * g(2)) / det
        else
          d = [-g(1) / h11, -g(2) / h22]
        end if
      else if (free(1)) then
        d(1) = -g(1) / h11
      else if (free(2)) then
        d(2) = -g(2) / h22
      end if
      if (all(d == 0.0_wp)) exit

      call projected_search(a, sizes, xi, eta, d, f, xi_new, eta_new, f_new, ok)
      if (.not. ok) then
        ! the projected Newton path can climb where a bound cuts it: fall back to the
        ! diagonally scaled gradient of the free coordinates, a descent path for small steps
        d = 0.0_wp
        if (free(1)) d(1) = -g(1) / h11
        if (free(2)) d(2) = -g(2) / h22
        call projected_search(a, sizes, xi, eta, d, f, xi_new, eta_new, f_new, ok)
        if (.not. ok) exit
      end if
      trial = max(abs(xi_new - xi), abs(eta_new - eta))
      xi = xi_new
      eta = eta_new
      if (trial <= 1.0e-15_wp) exit
    end do

    shape = segment_shape_functions(xi, eta)    ! (a temporary of its own would be on the heap)
    xc = matmul(xseg, shape)
    normal = cross(a(:, 1) + a(:, 3) * eta, a(:, 2) + a(:, 3) * xi)
    nn = norm2(normal)
    if (.not. (nn > 1.0e-12_wp * size2)) then
      ! collapsed corner of a triangle: the normal of the diagonals
      normal = cross(xseg(:, 3) - xseg(:, 1), xseg(:, 4) - xseg(:, 2))
      nn = norm2(normal)
    end if
    if (nn > 0.0_wp) normal = normal / nn
  end subroutine closest_point_on_segment

  !> A lower bound of the distance from p to every point of the bilinear segment xseg, cheap next
  !> to closest_point_on_segment. The segment lies in the convex hull of its nodes (its shape
  !> functions are nonnegative and sum to one), so in the slab between the planes normal to
  !> n = (x3 - x1) x (x4 - x2) through its highest and lowest node, and, for each edge, on the
  !> inner side of the plane that contains n and the farthest node out from that edge. Those
  !> planes' normals are orthogonal to n, so the distance a beyond the slab and the largest
  !> distance b beyond an edge plane combine to sqrt(a^2 + b^2). Less a round-off allowance of
  !> 1e-10 of the coordinates, so that the true distance is never below it; 0 for a segment
  !> without a normal. Squared distances throughout and one square root. With enough, a slab bound
  !> beyond it is returned as it is (still a lower bound, and all a caller who asks whether the
  !> segment is within `enough` needs).
  pure real(wp) function segment_distance_bound(xseg, p, enough) result(bound)
    real(wp), intent(in) :: xseg(3, 4), p(3)
    !> a bound beyond this is enough: the edge planes are then left out (the slab's bound is returned)
    real(wp), intent(in), optional :: enough
    real(wp) :: y(3, 4), d13(3), d24(3), n(3), h(4), nn, a2, b2, scale
    integer :: k
    do k = 1, 4
      y(:, k) = xseg(:, k) - p
    end do
    bound = 0.0_wp
    d13 = y(:, 3) - y(:, 1)
    d24 = y(:, 4) - y(:, 2)
    n(1) = d13(2) * d24(3) - d13(3) * d24(2)
    n(2) = d13(3) * d24(1) - d13(1) * d24(3)
    n(3) = d13(1) * d24(2) - d13(2) * d24(1)
    nn = n(1) * n(1) + n(2) * n(2) + n(3) * n(3)
    if (.not. (nn > 0.0_wp)) return
    do k = 1, 4
      h(k) = n(1) * y(1, k) + n(2) * y(2, k) + n(3) * y(3, k)
    end do
    a2 = max(0.0_wp, min(h(1), h(2), h(3), h(4)), -max(h(1), h(2), h(3), h(4)))**2 / nn
    scale = max(abs(p(1)), abs(p(2)), abs(p(3))) &
            + max(abs(y(1, 1)), abs(y(2, 1)), abs(y(3, 1)), abs(y(1, 2)), abs(y(2, 2)), abs(y(3, 2)), &
                  abs(y(1, 3)), abs(y(2, 3)), abs(y(3, 3)), abs(y(1, 4)), abs(y(2, 4)), abs(y(3, 4)))
    if (present(enough)) then
      bound = max(0.0_wp, sqrt(a2) - 2.0e-10_wp * scale)
      if (bound > enough) return
    end if
    b2 = max(edge_excess2(y(:, 1), y(:, 2), y(:, 3), y(:, 4), n), edge_excess2(y(:, 2), y(:, 3), y(:, 4), y(:, 1), n), &
             edge_excess2(y(:, 3), y(:, 4), y(:, 1), y(:, 2), n), edge_excess2(y(:, 4), y(:, 1), y(:, 2), y(:, 3), n))
    bound = max(0.0_wp, sqrt(a2 + b2) - 2.0e-10_wp * scale)
  end function segment_distance_bound

  !> The squared distance of the origin beyond the plane through the edge ya-yb that contains n,
  !> pushed out to the farthest of the nodes (ya, yb on it; yc, yd the others); 0 inside it or
  !> for a collapsed edge. The plane's normal m = (yb - ya) x n points out of the segment for
  !> nodes counter-clockwise about n; the farthest node makes the bound hold for either order.
  pure real(wp) function edge_excess2(ya, yb, yc, yd, n) result(b2)
    real(wp), intent(in) :: ya(3), yb(3), yc(3), yd(3), n(3)
    real(wp) :: e(3), m(3), out, mm
    e = yb - ya
    m(1) = e(2) * n(3) - e(3) * n(2)
    m(2) = e(3) * n(1) - e(1) * n(3)
    m(3) = e(1) * n(2) - e(2) * n(1)
    out = max(m(1) * ya(1) + m(2) * ya(2) + m(3) * ya(3), m(1) * yc(1) + m(2) * yc(2) + m(3) * yc(3), &
              m(1) * yd(1) + m(2) * yd(2) + m(3) * yd(3))
    mm = m(1) * m(1) + m(2) * m(2) + m(3) * m(3)
    b2 = 0.0_wp
    if (out < 0.0_wp .and. mm > 0.0_wp) b2 = out * out / mm
  end function edge_excess2

end module segment_projection
