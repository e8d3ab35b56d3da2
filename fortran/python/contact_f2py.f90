! f2py wrappers of the edge-to-edge contact kernels (edge_penalty): plain procedures with explicit
! shapes, as in kernels_f2py.f90.

! The parameters s, u of the closest points of the segments a1-a2 and b1-b2.
subroutine contact_edge_closest(a1, a2, b1, b2, s, u)
  use paradyn_kinds, only: wp
  use edge_penalty, only: closest_points_of_edges
  implicit none
  real(wp), intent(in) :: a1(3), a2(3), b1(3), b2(3)
  real(wp), intent(out) :: s, u
  call closest_points_of_edges(a1, a2, b1, b2, s, u)
end subroutine contact_edge_closest

! The penalty forces on a1, a2, b1, b2 (columns of force) of two crossing edges, their penetration
! and in_contact (1: they touch).
subroutine contact_edge_force(a1, a2, b1, b2, t_a, t_b, k, force, penetration, in_contact)
  use paradyn_kinds, only: wp
  use edge_penalty, only: edge_edge_force
  implicit none
  real(wp), intent(in) :: a1(3), a2(3), b1(3), b2(3), t_a, t_b, k
  real(wp), intent(out) :: force(3, 4), penetration
  integer, intent(out) :: in_contact
  logical :: touching
  call edge_edge_force(a1, a2, b1, b2, t_a, t_b, k, force, penetration, touching)
  in_contact = merge(1, 0, touching)
end subroutine contact_edge_force
