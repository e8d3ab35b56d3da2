!> The motion of one rigid body (docs/theory.md, "Rigid bodies"): its mass properties from the
!> lumped masses of its nodes (so that its kinetic energy is the one the nodes carry, and the energy
!> balance holds; the inertia converges to the continuum's as the mesh refines), the Newton-Euler update of central differences, and the velocities that
!> carry its nodes with it. Pure: the plumbing (rigid_body_effect) gathers the sums over the ranks.
!>
!> State at the half step n+1/2: the velocity V of the centre and the angular momentum L about it
!> (world axes); at the whole step n: the centre X and the rotation R from the body's axes at t = 0
!> (the world's) to the world's now. The inertia about the centre in the world is R I0 R^T.
module rigid_body_motion
  use paradyn_kinds, only: wp
  use vector_algebra, only: cross
  implicit none
  private
  public :: rigid_body_t, body_from_sums, body_advance, body_omega, carry_nodes, rotation_step, &
            body_with_given_mass, inertia_is_positive, n_mass_sums

  !> the sums over a body's nodes that give its mass properties: mass, first moment (3), second
  !> moments about the first pass's centre (xx, yy, zz, xy, yz, zx) and the nodes' rotary inertia
  integer, parameter :: n_mass_sums = 11
  !> fixed-point passes for omega at the half step's rotation: the kinetic energy of a free spin
  !> then drifts 1e-6 over 1e5 steps instead of 3e-4 with the rotation at the step's start
  integer, parameter :: midpoint_passes = 3

  type :: rigid_body_t
    real(wp) :: mass = 0
    real(wp) :: inertia0(3, 3) = 0     !< about the centre, in the body's axes (the world's at t = 0)
    real(wp) :: centre(3) = 0          !< X at the whole step
    real(wp) :: rotation(3, 3) = 0     !< R at the whole step
    real(wp) :: velocity(3) = 0        !< V at the half step
    real(wp) :: momentum(3) = 0        !< L about the centre at the half step (world axes)
    real(wp) :: omega(3) = 0           !< the angular velocity that L gives (world axes)
    integer :: given(6) = 0            !< 1: the velocity of the translation along x, y, z or of the
                                       !< rotation about them is given (held at 0, or prescribed)
    real(wp) :: target(6) = 0          !< the given velocities at this half step (0 where held)
  end type rigid_body_t

contains

  !> A body at rest at time 0 from its sums (the second moments taken about `origin`, the
  !> centre of a first pass, so that a body far from the world's origin keeps its digits).
  pure function body_from_sums(sums, origin, given) result(b)
    real(wp), intent(in) :: sums(n_mass_sums), origin(3)
    integer, intent(in) :: given(6)
    type(rigid_body_t) :: b
    real(wp) :: d(3), second(3, 3)
    integer :: k
    b%mass = sums(1)
    d = sums(2:4) / b%mass                 ! the centre relative to origin
    b%centre = origin + d
    second = reshape([sums(5), sums(8), sums(10), sums(8), sums(6), sums(9), sums(10), sums(9), sums(7)], [3, 3])
    second = second - b%mass * outer(d, d)   ! about the centre (parallel axes)
    b%inertia0 = -second
    do k = 1, 3
      b%inertia0(k, k) = second(1, 1) + second(2, 2) + second(3, 3) - second(k, k) + sums(11)
    end do
    b%rotation = identity()
    b%given = given
  end function body_from_sums

  !> The moving body b (its velocity, angular momentum and omega set from its nodes) with the mass,
  !> centre and inertia given instead (LS-DYNA *PART_INERTIA; inertia: xx, yy, zz, xy, yz, zx about
  !> centre, world axes at t = 0): the same rigid velocity field, V taken at the new centre, and
  !> the angular momentum the given inertia gives omega.
  pure subroutine body_with_given_mass(b, mass, centre, inertia)
    type(rigid_body_t), intent(inout) :: b
    real(wp), intent(in) :: mass, centre(3), inertia(6)
    real(wp) :: moved(3)
    moved = b%velocity + cross(b%omega, centre - b%centre)
    b%velocity = merge(b%velocity, moved, b%given(1:3) /= 0)
    b%mass = mass
    b%centre = centre
    b%inertia0 = reshape([inertia(1), inertia(4), inertia(6), inertia(4), inertia(2), inertia(5), &
                          inertia(6), inertia(5), inertia(3)], [3, 3])
    b%momentum = matmul(b%inertia0, b%omega)   ! the rotation is the identity at t = 0
  end subroutine body_with_given_mass

  !> Whether the tensor (xx, yy, zz, xy, yz, zx) is positive definite (Sylvester's criterion).
  pure logical function inertia_is_positive(inertia) result(positive)
    real(wp), intent(in) :: inertia(6)
    real(wp) :: minor2, det
    minor2 = inertia(1) * inertia(2) - inertia(4)**2
    det = inertia(1) * (inertia(2) * inertia(3) - inertia(5)**2) - inertia(4) * (inertia(4) * inertia(3) &
          - inertia(5) * inertia(6)) + inertia(6) * (inertia(4) * inertia(5) - inertia(2) * inertia(6))
    positive = inertia(1) > 0.0_wp .and. minor2 > 0.0_wp .and. det > 0.0_wp
  end function inertia_is_positive

  !> The half-step velocities from the force and torque (about the centre) at the whole step
  !> over h = (dt_previous + dt) / 2, then the centre and rotation at the next whole step. A dof with
  !> a given velocity (held: 0; prescribed: b%target) takes it: a translation's V directly; a
  !> rotation's omega component, the others solving the free rows of I omega = L, whose constraint
  !> torque takes the rest of L. work: what the constraint impulses do over the step (the impulse
  !> times the mean of the velocities before and after it), 0 for a held dof.
  pure subroutine body_advance(b, force, torque, h, dt, work)
    type(rigid_body_t), intent(inout) :: b
    real(wp), intent(in) :: force(3), torque(3), h, dt
    real(wp), intent(out) :: work
    real(wp) :: before(6), free_momentum(3), free_velocity(3)
    integer :: k
    before = [b%velocity, b%omega]
    free_velocity = b%velocity + h * force / b%mass
    b%velocity = merge(b%target(1:3), free_velocity, b%given(1:3) /= 0)
    b%momentum = b%momentum + h * torque
    free_momentum = b%momentum
    do k = 1, midpoint_passes   ! omega with the inertia of the rotation half a step on (implicit midpoint)
      b%momentum = free_momentum
      call body_omega(b, matmul(rotation_step(0.5_wp * dt * b%omega), b%rotation))
    end do
    work = 0.5_wp * (sum(b%mass * (b%velocity - free_velocity) * (before(1:3) + b%velocity)) &
                     + sum((b%momentum - free_momentum) * (before(4:6) + b%omega)))
    b%centre = b%centre + dt * b%velocity
    b%rotation = matmul(rotation_step(dt * b%omega), b%rotation)
  end subroutine body_advance

  !> omega from L and the inertia in the world at rotation: a rotation with a given velocity takes
  !> it (b%target, 0 when held), the others solve their rows of I omega = L; L becomes I omega.
  pure subroutine body_omega(b, rotation)
    type(rigid_body_t), intent(inout) :: b
    real(wp), intent(in) :: rotation(3, 3)
    real(wp) :: inertia(3, 3), a(3, 3), rhs(3), known(3)
    logical :: given(3)
    integer :: k
    inertia = matmul(rotation, matmul(b%inertia0, transpose(rotation)))
    given = b%given(4:6) /= 0
    known = merge(b%target(4:6), 0.0_wp, given)
    a = inertia
    rhs = b%momentum - matmul(inertia, known)   ! the known components moved to the right
    do k = 1, 3   ! a given rotation: the equation omega_k = 0 (then + known) instead of row k
      if (.not. given(k)) cycle
      a(k, :) = 0.0_wp
      a(:, k) = 0.0_wp
      a(k, k) = 1.0_wp
      rhs(k) = 0.0_wp
    end do
    b%omega = solve3(a, rhs) + known
    if (any(given)) b%momentum = matmul(inertia, b%omega)
  end subroutine body_omega

  !> The half-step velocities that move each node(j) with the body from the last whole step
  !> (centre_before, rotation_before) to this one: (X' - X + (R' - R) s) / dt, s its offset at t = 0,
  !> so a body that does not move leaves its nodes exactly where they are; w is omega.
  pure subroutine carry_nodes(b, centre_before, rotation_before, offset, node, dt, v, w)
    type(rigid_body_t), intent(in) :: b
    real(wp), intent(in) :: centre_before(3), rotation_before(3, 3)
    real(wp), intent(in) :: offset(:, :)   !< per node(j): x at t = 0 less the centre at t = 0
    integer, intent(in) :: node(:)
    real(wp), intent(in) :: dt
    real(wp), intent(inout) :: v(:, :), w(:, :)
    real(wp) :: shift(3), turn(3, 3)
    integer :: j, k
    shift = b%centre - centre_before
    turn = b%rotation - rotation_before
    do j = 1, size(node)
      k = node(j)
      v(:, k) = (shift + matmul(turn, offset(:, j))) / dt
      w(:, k) = b%omega
    end do
  end subroutine carry_nodes

  !> The rotation by the vector phi (angle |phi| about its direction; Rodrigues' formula).
  pure function rotation_step(phi) result(r)
    real(wp), intent(in) :: phi(3)
    real(wp) :: r(3, 3), k(3, 3), theta2, s, c
    theta2 = dot_product(phi, phi)
    if (theta2 < 1.0e-8_wp) then   ! series: the error of the truncation is below rounding
      s = 1.0_wp - theta2 / 6.0_wp * (1.0_wp - theta2 / 20.0_wp)
      c = 0.5_wp - theta2 / 24.0_wp * (1.0_wp - theta2 / 30.0_wp)
    else
      s = sin(sqrt(theta2)) / sqrt(theta2)
      c = (1.0_wp - cos(sqrt(theta2))) / theta2
    end if
    k = reshape([0.0_wp, phi(3), -phi(2), -phi(3), 0.0_wp, phi(1), phi(2), -phi(1), 0.0_wp], [3, 3])
    r = identity() + s * k + c * matmul(k, k)
  end function rotation_step

  pure function identity() result(e)
    real(wp) :: e(3, 3)
    e = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
  end function identity

  pure function outer(a, b) result(m)
    real(wp), intent(in) :: a(3), b(3)
    real(wp) :: m(3, 3)
    m = spread(a, 2, 3) * spread(b, 1, 3)
  end function outer

  !> a^-1 rhs by the adjugate (a is symmetric positive definite: an inertia).
  pure function solve3(a, rhs) result(x)
    real(wp), intent(in) :: a(3, 3), rhs(3)
    real(wp) :: x(3), adj(3, 3), det
    adj(1, 1) = a(2, 2) * a(3, 3) - a(2, 3) * a(3, 2)
    adj(1, 2) = a(1, 3) * a(3, 2) - a(1, 2) * a(3, 3)
    adj(1, 3) = a(1, 2) * a(2, 3) - a(1, 3) * a(2, 2)
    adj(2, 1) = a(2, 3) * a(3, 1) - a(2, 1) * a(3, 3)
    adj(2, 2) = a(1, 1) * a(3, 3) - a(1, 3) * a(3, 1)
    adj(2, 3) = a(1, 3) * a(2, 1) - a(1, 1) * a(2, 3)
    adj(3, 1) = a(2, 1) * a(3, 2) - a(2, 2) * a(3, 1)
    adj(3, 2) = a(1, 2) * a(3, 1) - a(1, 1) * a(3, 2)
    adj(3, 3) = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
    det = a(1, 1) * adj(1, 1) + a(1, 2) * adj(2, 1) + a(1, 3) * adj(3, 1)
    x = matmul(adj, rhs) / det
  end function solve3

end module rigid_body_motion
