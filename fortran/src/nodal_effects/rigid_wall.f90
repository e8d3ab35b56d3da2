!> Rigid walls (LS-DYNA's *RIGIDWALL_PLANAR, _FINITE, _MOVING and *RIGIDWALL_GEOMETRIC_CYLINDER,
!> SPHERE, FLAT, PRISM, _MOTION): a surface moving at a constant velocity that pushes back every
!> node of its list that is inside it with a penalty spring of stiffness k = scale m / dt^2 along
!> the surface's outward normal, and holds it by Coulomb friction (docs/theory.md, "Rigid walls").
!> A shape is a case of wall_gap: the signed distance of a point to the surface and the outward
!> normal there.
!>
!> Compiled without floating-point contraction (fortran/CMakeLists.txt): a node must get the same
!> force wherever it falls in the loop, whatever the layout.
module rigid_wall
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: wall_plane, wall_finite_plane, wall_cylinder, wall_sphere, wall_box
  use exact_sum, only: exact_width, exact_add
  use vector_algebra, only: cross
  implicit none
  private
  public :: wall_t, wall_make, wall_position, wall_gap, rigid_wall_forces, no_contact, wall_requirement

  !> a gap no node reaches: the node is outside the part of space where the wall acts
  real(wp), parameter :: no_contact = huge(1.0_wp)

  !> One wall: its shape and geometry in unit vectors, its motion and its laws.
  type :: wall_t
    integer :: shape = wall_plane
    real(wp) :: point(3) = 0.0_wp      !< at time 0 (wall_position moves it)
    real(wp) :: normal(3) = 0.0_wp     !< unit: a plane's normal, a cylinder's axis
    real(wp) :: edge(3) = 0.0_wp       !< unit, normal to normal: a finite plane's or box's first side
    real(wp) :: side(3) = 0.0_wp       !< normal x edge: the second side
    real(wp) :: size(3) = 0.0_wp       !< sides along edge and side, a box's depth
    real(wp) :: radius = 0.0_wp, length = 0.0_wp
    real(wp) :: velocity(3) = 0.0_wp
    real(wp) :: stiffness_per_mass = 0.0_wp   !< scale / dt^2: k = this times the node's mass
    real(wp) :: stick_per_mass = 0.0_wp       !< 1 / dt: the force m v_t / dt stops a sliding node in a step
    real(wp) :: friction = 0.0_wp
  end type wall_t

contains

  !> A wall from the deck's values (normal and edge of any length, the edge not parallel to the
  !> normal where the shape uses it: the deck checks both) for a run of first step dt.
  pure function wall_make(shape, point, normal, edge, sides, radius, length, velocity, penalty_scale, friction, &
                          dt) result(w)
    integer, intent(in) :: shape
    real(wp), intent(in) :: point(3), normal(3), edge(3), sides(3), radius, length, velocity(3)
    real(wp), intent(in) :: penalty_scale, friction, dt
    type(wall_t) :: w
    real(wp) :: l(3)
    w%shape = shape
    w%point = point
    w%velocity = velocity
    w%size = sides
    w%radius = radius
    w%length = length
    w%friction = friction
    w%stiffness_per_mass = penalty_scale / dt**2
    w%stick_per_mass = 1.0_wp / dt
    if (norm2(normal) > 0.0_wp) w%normal = normal / norm2(normal)
    l = edge - dot_product(edge, w%normal) * w%normal
    if (norm2(l) > 0.0_wp) then
      w%edge = l / norm2(l)
      w%side = cross(w%normal, w%edge)
    end if
  end function wall_make

  !> What a wall of shape lacks of its geometry (normal, edge, sides (3), radius as in the deck),
  !> as the words 'needs ...' of the relation rigid_wall_geometry; '' when it has all it needs.
  pure function wall_requirement(shape, normal, edge, sides, radius) result(words)
    integer, intent(in) :: shape
    real(wp), intent(in) :: normal(3), edge(3), sides(3), radius
    character(len=:), allocatable :: words
    logical :: across
    words = ''
    across = norm2(cross(normal, edge)) > 1.0e-9_wp * norm2(normal) * norm2(edge)
    select case (shape)
    case (wall_finite_plane)
      if (.not. (across .and. sides(1) > 0.0_wp .and. sides(2) > 0.0_wp)) &
        words = 'finite_plane needs an edge not parallel to its normal and sides size[0], size[1] > 0'
    case (wall_box)
      if (.not. (across .and. all(sides > 0.0_wp))) &
        words = 'box needs an edge not parallel to its normal and size > 0 (both sides and the depth)'
    case (wall_cylinder)
      if (.not. radius > 0.0_wp) words = 'cylinder needs a radius > 0'
    case (wall_sphere)
      if (.not. radius > 0.0_wp) words = 'sphere needs a radius > 0'
    end select
  end function wall_requirement

  !> The wall's point at time t: it moves with the wall, the directions stay.
  pure function wall_position(point, velocity, time) result(p)
    real(wp), intent(in) :: point(3), velocity(3), time
    real(wp) :: p(3)
    p = point + time * velocity
  end function wall_position

  !> The signed gap d of the point p + y to the wall whose point is p (d < 0 inside or behind it)
  !> and the unit outward normal n there; d = no_contact where the wall does not act (beyond a
  !> finite plane's edges, beyond a finite cylinder's ends; a cylinder's or sphere's centre).
  pure subroutine wall_gap(w, y, d, n)
    type(wall_t), intent(in) :: w
    real(wp), intent(in) :: y(3)
    real(wp), intent(out) :: d, n(3)
    real(wp) :: a, b, c, r(3), faces(6)
    integer :: k
    d = no_contact
    n = w%normal
    select case (w%shape)
    case (wall_plane)
      d = y(1) * n(1) + y(2) * n(2) + y(3) * n(3)
    case (wall_finite_plane)
      a = dot_product(y, w%edge)
      b = dot_product(y, w%side)
      if (a >= 0.0_wp .and. a <= w%size(1) .and. b >= 0.0_wp .and. b <= w%size(2)) d = dot_product(y, n)
    case (wall_cylinder)
      c = dot_product(y, w%normal)
      if (w%length > 0.0_wp .and. (c < 0.0_wp .or. c > w%length)) return
      r = y - c * w%normal
      if (.not. norm2(r) > 0.0_wp) return
      d = norm2(r) - w%radius
      n = r / norm2(r)
    case (wall_sphere)
      if (.not. norm2(y) > 0.0_wp) return
      d = norm2(y) - w%radius
      n = y / norm2(y)
    case (wall_box)   ! inside, the nearest face: the largest of the six (negative) gaps
      a = dot_product(y, w%edge)
      b = dot_product(y, w%side)
      c = dot_product(y, w%normal)
      faces = [c, -w%size(3) - c, -a, a - w%size(1), -b, b - w%size(2)]
      k = maxloc(faces, 1)
      if (faces(k) >= 0.0_wp) return
      d = faces(k)
      select case (k)
      case (1)
        n = w%normal
      case (2)
        n = -w%normal
      case (3)
        n = -w%edge
      case (4)
        n = w%edge
      case (5)
        n = -w%side
      case default
        n = w%side
      end select
    end select
  end subroutine wall_gap

  !> Adds to force(1:3, j) the wall's force on every node j of nodes inside it at time t: the
  !> penalty force -k_j d_j n (k_j = stiffness_per_mass m_j) and, with friction, the force against
  !> the node's sliding velocity v_t relative to the wall, min(mu k_j |d_j|, m_j |v_t| / dt): stick
  !> below the Coulomb limit, slide at it. Adds the forces on the owned nodes (weight /= 0) to the
  !> exact accumulators sums(:, 1:3). Rotations feel nothing (the wall acts on the node).
  pure subroutine rigid_wall_forces(w, nodes, x, v, mass, weight, time, force, sums)
    type(wall_t), intent(in) :: w
    integer, intent(in) :: nodes(:)
    real(wp), intent(in) :: x(:, :), v(:, :), mass(:), weight(:), time
    real(wp), intent(inout) :: force(:, :)
    integer(i8), intent(inout) :: sums(exact_width, 3)
    real(wp) :: p(3), d, n(3), f(3), vt(3), slip, limit
    integer :: k, j, i
    p = wall_position(w%point, w%velocity, time)
    do k = 1, size(nodes)
      j = nodes(k)
      call wall_gap(w, x(:, j) - p, d, n)
      if (.not. d < 0.0_wp) cycle
      f = -(w%stiffness_per_mass * mass(j) * d) * n
      force(1:3, j) = force(1:3, j) + f
      if (weight(j) /= 0.0_wp) then
        do i = 1, 3
          call exact_add(sums(:, i), f(i))
        end do
      end if
      if (w%friction > 0.0_wp) then
        vt = v(:, j) - w%velocity
        vt = vt - dot_product(vt, n) * n
        slip = norm2(vt)
        if (.not. slip > 0.0_wp) cycle
        limit = min(w%friction * norm2(f), w%stick_per_mass * mass(j) * slip)
        f = -(limit / slip) * vt
        force(1:3, j) = force(1:3, j) + f
        if (weight(j) /= 0.0_wp) then
          do i = 1, 3
            call exact_add(sums(:, i), f(i))
          end do
        end if
      end if
    end do
  end subroutine rigid_wall_forces

end module rigid_wall
