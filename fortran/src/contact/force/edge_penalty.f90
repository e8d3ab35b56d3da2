!> The penalty law of edge-to-edge contact between thick shells (as LS-DYNA's edge-to-edge check of
!> its automatic contacts; Hallquist, LS-DYNA Theory Manual, contact): two straight element edges,
!> a1-a2 of one surface and b1-b2 of the other, meet where their closest points P = a1 + s (a2 - a1)
!> and Q = b1 + u (b2 - b1) are nearer than the sum of the two half thicknesses. The edge then
!> carries a penalty force along P - Q, shared out to its two nodes by the segment parameters, so
!> that the forces sum to zero and, being along the line through P and Q, have no moment: linear and
!> angular momentum are conserved. Node-to-segment contact sees a node against a face; two thin
!> walls that cross edge against edge between their nodes are only seen here.
!>
!> Only crossings count (0 < s < 1 and 0 < u < 1): where a closest point is an end of an edge the
!> contact is a node against a face or an edge, which node-to-segment contact with rounded edges
!> already carries (counting it twice would double its stiffness); parallel edges likewise.
!>
!> Pure: no MPI, no I/O, no module state.
module edge_penalty
  use paradyn_kinds, only: wp
  use vector_algebra, only: cross
  implicit none
  private
  public :: closest_points_of_edges, edge_edge_force

contains

  !> The parameters s, u in [0, 1] of the closest points P = a1 + s (a2 - a1), Q = b1 + u (b2 - b1)
  !> of the segments a1-a2 and b1-b2 (clamped to the ends; for parallel edges s = 0 and Q the point
  !> of b nearest a1). The standard construction: minimise |P - Q|^2 over the square, first without
  !> bounds, then along the sides the unbounded minimum falls beyond (Ericson, Real-Time Collision
  !> Detection, 2005, section 5.1.9).
  pure subroutine closest_points_of_edges(a1, a2, b1, b2, s, u)
    real(wp), intent(in) :: a1(3), a2(3), b1(3), b2(3)
    real(wp), intent(out) :: s, u
    real(wp) :: d1(3), d2(3), r(3), a, e, f, b, c, denominator, tiny_length
    d1 = a2 - a1
    d2 = b2 - b1
    r = a1 - b1
    a = dot_product(d1, d1)
    e = dot_product(d2, d2)
    f = dot_product(d2, r)
    tiny_length = 1.0e-30_wp
    s = 0.0_wp
    u = 0.0_wp
    if (a <= tiny_length .and. e <= tiny_length) return
    if (a <= tiny_length) then
      u = clamp01(f / e)
      return
    end if
    c = dot_product(d1, r)
    if (e <= tiny_length) then
      s = clamp01(-c / a)
      return
    end if
    b = dot_product(d1, d2)
    denominator = a * e - b * b
    ! nearly parallel (sin^2 of the angle below 1e-12): any s is as close; take a1's end
    if (denominator > 1.0e-12_wp * a * e) s = clamp01((b * f - c * e) / denominator)
    u = (b * s + f) / e
    if (u < 0.0_wp) then
      u = 0.0_wp
      s = clamp01(-c / a)
    else if (u > 1.0_wp) then
      u = 1.0_wp
      s = clamp01((b - c) / a)
    end if
  end subroutine closest_points_of_edges

  pure real(wp) function clamp01(x)
    real(wp), intent(in) :: x
    clamp01 = min(1.0_wp, max(0.0_wp, x))
  end function clamp01

  !> The penalty force between the edge a1-a2 (shell thickness t_a) and the edge b1-b2 (t_b) of
  !> stiffness k. With P, Q the closest points (closest_points_of_edges), the gap is
  !> g = |P - Q| - (t_a + t_b) / 2; if g < 0 and both points lie inside their edges (a crossing),
  !> the force on P is f = -k g n, n = (P - Q) / |P - Q| (where P = Q the unit normal of the two
  !> edges, a x b, turned towards a's midpoint from b's), and force(:, 1:4) on a1, a2, b1, b2 is
  !> ((1 - s) f, s f, -(1 - u) f, -u f). penetration = -g (0 when not in contact).
  pure subroutine edge_edge_force(a1, a2, b1, b2, t_a, t_b, k, force, penetration, in_contact)
    real(wp), intent(in) :: a1(3), a2(3), b1(3), b2(3), t_a, t_b, k
    real(wp), intent(out) :: force(3, 4), penetration
    logical, intent(out) :: in_contact
    real(wp) :: s, u, p(3), q(3), d(3), distance, gap, normal(3), f(3)
    force = 0.0_wp
    penetration = 0.0_wp
    in_contact = .false.
    call closest_points_of_edges(a1, a2, b1, b2, s, u)
    if (.not. (s > 0.0_wp .and. s < 1.0_wp .and. u > 0.0_wp .and. u < 1.0_wp)) return
    p = a1 + s * (a2 - a1)
    q = b1 + u * (b2 - b1)
    d = p - q
    distance = norm2(d)
    gap = distance - 0.5_wp * (t_a + t_b)
    if (.not. (gap < 0.0_wp)) return
    if (distance > 0.0_wp) then
      normal = d / distance
    else
      normal = cross(a2 - a1, b2 - b1)
      if (.not. (norm2(normal) > 0.0_wp)) return
      normal = normal / norm2(normal)
      if (dot_product(normal, (a1 + a2) - (b1 + b2)) < 0.0_wp) normal = -normal
    end if
    in_contact = .true.
    penetration = -gap
    f = -k * gap * normal
    force(:, 2) = s * f
    force(:, 1) = f - force(:, 2)
    force(:, 4) = -u * f
    force(:, 3) = -f - force(:, 4)
  end subroutine edge_edge_force

end module edge_penalty
