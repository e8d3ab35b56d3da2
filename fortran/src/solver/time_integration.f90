!> Explicit central-difference integration of nodal translations and rotations (lumped mass,
!> diagonal rotational inertia, optional mass-proportional damping).
module time_integration
  use paradyn_kinds, only: wp, i8
  use exact_sum, only: exact_add
  implicit none
  private
  public :: update_velocities, update_positions, update_orientations, kinetic_energy, kinetic_energy_by_part, &
            add_constraint_reactions

contains

  !> v(n+1/2) = [(1 - a h/2) v(n-1/2) + h (f_ext - f_int) / m] / (1 + a h/2) for the 3 translations
  !> and, with the inertia, the 3 rotations; fixed dofs get zero velocity. h is the step between
  !> the two half-step velocities. damping_work accumulates the work dissipated by damping on the
  !> nodes with weight 1 (each node is counted by one rank only).
  pure subroutine update_velocities(n, h, damping, mass, inertia, fixed, force_internal, &
                                    force_external, weight, v, w, damping_work)
    integer, intent(in) :: n
    real(wp), intent(in) :: h, damping, mass(n), inertia(n)
    integer, intent(in) :: fixed(6, n)
    real(wp), intent(in) :: force_internal(6, n), force_external(6, n), weight(n)
    real(wp), intent(inout) :: v(3, n), w(3, n), damping_work
    real(wp) :: c_old, c_new, v_old(3)
    integer :: j
    c_old = 1.0_wp - 0.5_wp * damping * h
    c_new = 1.0_wp / (1.0_wp + 0.5_wp * damping * h)
    do j = 1, n
      v_old = v(:, j)
      v(:, j) = c_new * (c_old * v(:, j) + h * (force_external(1:3, j) - force_internal(1:3, j)) / mass(j))
      w(:, j) = c_new * (c_old * w(:, j) + h * (force_external(4:6, j) - force_internal(4:6, j)) / inertia(j))
      where (fixed(1:3, j) /= 0) v(:, j) = 0.0_wp
      where (fixed(4:6, j) /= 0) w(:, j) = 0.0_wp
      if (damping > 0.0_wp) damping_work = damping_work + weight(j) * h * damping * mass(j) &
                                           * sum((0.5_wp * (v_old + v(:, j)))**2)
    end do
  end subroutine update_velocities

  !> Each node's orientation, a unit quaternion q = (cos(a/2), sin(a/2) axis) of its rotation from
  !> the start, turned by the exact rotation of the step, the rotation vector dt w(n+1/2) with w the
  !> angular velocity in global axes: q <- exp(dt w / 2) q (then renormalised). The forces never
  !> read it: it gives the frames the nodal directors behind the surface strains
  !> (shell_field_measures' surface_strains).
  pure subroutine update_orientations(n, dt, w, q)
    integer, intent(in) :: n
    real(wp), intent(in) :: dt, w(3, n)
    real(wp), intent(inout) :: q(4, n)
    real(wp) :: phi(3), angle, c, s(3), r(4)
    integer :: j
    do j = 1, n
      phi = dt * w(:, j)
      angle = norm2(phi)
      if (angle == 0.0_wp) cycle
      c = cos(0.5_wp * angle)
      s = (sin(0.5_wp * angle) / angle) * phi
      r(1) = c * q(1, j) - dot_product(s, q(2:4, j))
      r(2:4) = c * q(2:4, j) + q(1, j) * s + [s(2) * q(4, j) - s(3) * q(3, j), s(3) * q(2, j) - s(1) * q(4, j), &
                                              s(1) * q(3, j) - s(2) * q(2, j)]
      q(:, j) = r / norm2(r)
    end do
  end subroutine update_orientations

  !> The force and moment the constraints put on the nodes of weight 1 in the velocity update over
  !> h, added exactly to acc(:, k): k = 1..3 the force, k = 4..6 its moment about the origin,
  !> sum of x x f over the nodes (at the positions x of the update) plus the moments on rotations.
  !> On a fixed dof the reaction is f_int - f_ext (the update zeroed it); where a constraint stage
  !> changed the updated velocity v_free into v (w_free into w), it is the force (moment) that makes
  !> that change, m (v - v_free) / (c_new h) (inertia (w - w_free) / (c_new h)) with
  !> update_velocities' damping factor c_new. Nodes no constraint touched add nothing, so a model
  !> without constraints reports exactly zero.
  pure subroutine add_constraint_reactions(n, h, damping, x, mass, inertia, fixed, force_internal, &
                                           force_external, v_free, v, w_free, w, weight, acc)
    integer, intent(in) :: n
    real(wp), intent(in) :: h, damping, x(3, n), mass(n), inertia(n), force_internal(6, n), force_external(6, n)
    integer, intent(in) :: fixed(6, n)
    real(wp), intent(in) :: v_free(3, n), v(3, n), w_free(3, n), w(3, n), weight(n)
    integer(i8), intent(inout) :: acc(:, :)
    real(wp) :: c_new, f(3), m(3)
    integer :: j, k
    logical :: touched
    c_new = 1.0_wp / (1.0_wp + 0.5_wp * damping * h)
    do j = 1, n
      if (weight(j) == 0.0_wp) cycle
      touched = .false.
      f = 0.0_wp
      m = 0.0_wp
      do k = 1, 3
        if (fixed(k, j) /= 0) then
          f(k) = force_internal(k, j) - force_external(k, j)
        else if (v(k, j) /= v_free(k, j)) then
          f(k) = mass(j) * (v(k, j) - v_free(k, j)) / (c_new * h)
        else
          cycle
        end if
        touched = .true.
        call exact_add(acc(:, k), f(k))
      end do
      do k = 1, 3
        if (fixed(3 + k, j) /= 0) then
          m(k) = force_internal(3 + k, j) - force_external(3 + k, j)
        else if (w(k, j) /= w_free(k, j)) then
          m(k) = inertia(j) * (w(k, j) - w_free(k, j)) / (c_new * h)
        else
          cycle
        end if
        touched = .true.
      end do
      if (.not. touched) cycle
      m = m + [x(2, j) * f(3) - x(3, j) * f(2), x(3, j) * f(1) - x(1, j) * f(3), x(1, j) * f(2) - x(2, j) * f(1)]
      do k = 1, 3
        call exact_add(acc(:, 3 + k), m(k))
      end do
    end do
  end subroutine add_constraint_reactions

  !> x(n+1) = x(n) + dt v(n+1/2).
  pure subroutine update_positions(n, dt, v, x)
    integer, intent(in) :: n
    real(wp), intent(in) :: dt, v(3, n)
    real(wp), intent(inout) :: x(3, n)
    x = x + dt * v
  end subroutine update_positions

  !> Kinetic energy at t(n) of the nodes with weight 1, as 1/2 m v(n-1/2).v(n+1/2) (translations
  !> and rotations): with the midpoint stress work, the quantity that central differences conserve
  !> exactly for a linear system (Belytschko, Liu & Moran, Nonlinear Finite Elements, sec. 6.2.3).
  pure real(wp) function kinetic_energy(n, mass, inertia, v_before, w_before, v_after, w_after, &
                                        weight) result(energy)
    integer, intent(in) :: n
    real(wp), intent(in) :: mass(n), inertia(n), weight(n)
    real(wp), intent(in) :: v_before(3, n), w_before(3, n), v_after(3, n), w_after(3, n)
    integer :: j
    energy = 0.0_wp
    do j = 1, n
      energy = energy + weight(j) * 0.5_wp * (mass(j) * dot_product(v_before(:, j), v_after(:, j)) &
                                              + inertia(j) * dot_product(w_before(:, j), w_after(:, j)))
    end do
  end function kinetic_energy

  !> kinetic_energy binned by the part of each node (node_part: 1..n_parts).
  pure function kinetic_energy_by_part(n, mass, inertia, v_before, w_before, v_after, w_after, weight, &
                                       node_part, n_parts) result(energy)
    integer, intent(in) :: n, n_parts, node_part(n)
    real(wp), intent(in) :: mass(n), inertia(n), weight(n)
    real(wp), intent(in) :: v_before(3, n), w_before(3, n), v_after(3, n), w_after(3, n)
    real(wp) :: energy(n_parts)
    integer :: j
    energy = 0.0_wp
    do j = 1, n
      energy(node_part(j)) = energy(node_part(j)) + weight(j) * 0.5_wp * &
        (mass(j) * dot_product(v_before(:, j), v_after(:, j)) + inertia(j) * dot_product(w_before(:, j), w_after(:, j)))
    end do
  end function kinetic_energy_by_part

end module time_integration
