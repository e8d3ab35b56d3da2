!> The penalty force law of node-to-segment contact on shell segments (Hallquist, Goudreau & Benson
!> 1985; Hallquist, LS-DYNA Theory Manual): the penalty stiffness of a segment, and the force on a
!> slave node and the segment's four nodes once the local search (contact_search) has found the
!> segment and its closest point. Shells are two-sided and thick: the contact surfaces lie half a
!> thickness off each mid-surface, with rounded edges where asked for, and regularised Coulomb
!> friction acts on the relative tangential velocity. The face test's edge_tolerance is the force
!> law's: the local search prunes by it, so that it skips only segments this law would not touch.
!> The local search's stage (contact_stages) and the start-up check of initial penetrations
!> (initial_penetration: unit stiffness, the force is the depth along the push) call it.
!>
!> Pure: no MPI, no I/O, no module state.
module contact_penalty
  use paradyn_kinds, only: wp
  use vector_algebra, only: cross
  use segment_projection, only: closest_point_on_segment, segment_shape_functions
  implicit none
  private
  public :: shell_penalty_stiffness, penalty_force, friction_coefficient
  public :: default_penalty_scale, edge_tolerance

  !> LS-DYNA's default scale factor of the penalty stiffness.
  real(wp), parameter :: default_penalty_scale = 0.1_wp
  !> A slave point whose closest point on a segment is off the segment's normal by more than
  !> this fraction of the longer diagonal (it lies beyond an edge) is not in contact with that
  !> segment, unless rounded edges are asked for. The margin keeps a node that slides over the
  !> ridge between two faceted segments from slipping through the gap between their normals.
  real(wp), parameter :: edge_tolerance = 0.05_wp

contains

  !> Penalty stiffness of a shell master segment, LS-DYNA's shell form k = scale K A / d_max:
  !> K = E / (3 (1 - 2 nu)) the bulk modulus, A the segment area (half the cross product of the
  !> diagonals, exact for a flat quadrilateral), d_max the longer diagonal. scale is usually
  !> default_penalty_scale (0.1).
  pure real(wp) function shell_penalty_stiffness(xseg, young, poisson, scale) result(k)
    real(wp), intent(in) :: xseg(3, 4), young, poisson, scale
    real(wp) :: d13(3), d24(3), bulk, area, diagonal
    d13 = xseg(:, 3) - xseg(:, 1)
    d24 = xseg(:, 4) - xseg(:, 2)
    bulk = young / (3.0_wp * (1.0_wp - 2.0_wp * poisson))
    area = 0.5_wp * norm2(cross(d13, d24))
    diagonal = max(norm2(d13), norm2(d24))
    k = 0.0_wp
    if (diagonal > 0.0_wp) k = scale * bulk * area / diagonal
  end function shell_penalty_stiffness

  !> Friction coefficient at slip speed v: mu = mu_d + (mu_s - mu_d) exp(-decay v) (LS-DYNA's
  !> exponential interpolation from the static to the dynamic coefficient).
  pure real(wp) function friction_coefficient(mu_static, mu_dynamic, decay, v) result(mu)
    real(wp), intent(in) :: mu_static, mu_dynamic, decay, v
    mu = mu_dynamic + (mu_static - mu_dynamic) * exp(-decay * v)
  end function friction_coefficient

  !> Penalty contact force between a slave node at p (shell thickness t_slave) and a master
  !> segment xseg (thickness t_master), both two-sided.
  !>
  !> With xc the closest point of the segment, n its unit normal there and d = (p - xc).n, the
  !> contact surfaces are half a thickness off the mid-surfaces, so the gap is
  !> g = |d| - (t_slave + t_master) / 2. If g < 0 the slave gets f = -k g sign(d) n (pushed out
  !> on the side it is on; d = 0 counts as the +n side) and master node I gets -f N_I(xi, eta),
  !> so the forces sum to zero and have no moment about xc. penetration = -g (0 when not in
  !> contact).
  !>
  !> Only points whose closest point lies on the segment count: the offset of p - xc from the
  !> normal line must be within edge_tolerance of the longer diagonal. With rounded_edges, a
  !> point beyond an edge or corner instead meets the edge rounded with radius
  !> (t_slave + t_master) / 2: g = |p - xc| - (t_slave + t_master) / 2 along (p - xc) / |p - xc|,
  !> continuous with the face value where the projection leaves the segment.
  !>
  !> Friction (optional, when v_slave, v_master and the coefficients are given): regularised
  !> Coulomb friction on the relative tangential velocity v_t = v_rel - (v_rel.e) e,
  !> v_rel = v_slave - sum_I N_I v_master_I, e the force direction:
  !>   f_t = -mu |f_n| v_t / max(|v_t|, v_slip),  mu = mu_d + (mu_s - mu_d) exp(-decay |v_t|).
  !> Above the slip velocity v_slip this is Coulomb friction at the cap mu |f_n| opposing the
  !> slip; below it the force falls linearly to zero with the slip speed (a viscous
  !> regularisation of stick). We chose this velocity form over LS-DYNA's elastic trial force
  !> (k times the tangential slip increment, returned to the cap) because it needs no history
  !> per contact pair; the price is that a body at rest on a slope creeps at a speed of order
  !> v_slip. v_slip = 0 gives the pure sign form. The friction force is shared out like the
  !> normal force (slave node; master nodes by N_I), so it is also equal and opposite; the slave
  !> node sits a distance d off xc along the normal, so the friction pair leaves a couple
  !> d x f_t that is not applied to the shell rotations (as in usual node-to-segment contact).
  pure subroutine penalty_force(p, t_slave, xseg, t_master, k, f_slave, f_master, penetration, &
                                in_contact, v_slave, v_master, mu_static, mu_dynamic, decay, &
                                v_slip, rounded_edges, closest)
    real(wp), intent(in) :: p(3), t_slave, xseg(3, 4), t_master, k
    real(wp), intent(out) :: f_slave(3), f_master(3, 4), penetration
    logical, intent(out) :: in_contact
    real(wp), intent(in), optional :: v_slave(3), v_master(3, 4)
    real(wp), intent(in), optional :: mu_static, mu_dynamic, decay, v_slip
    logical, intent(in), optional :: rounded_edges
    !> the closest point of p on the segment already found: xi, eta, xc(3), normal(3)
    real(wp), intent(in), optional :: closest(8)
    real(wp) :: xi, eta, xc(3), normal(3), dvec(3), d, offset(3), reach, gap, direction(3), dist
    real(wp) :: diagonal, shape(4), v_rel(3), v_t(3), speed, mu, fn, regular
    logical :: rounded, on_edge
    integer :: i

    f_slave = 0.0_wp
    f_master = 0.0_wp
    penetration = 0.0_wp
    in_contact = .false.
    rounded = .false.
    if (present(rounded_edges)) rounded = rounded_edges

    if (present(closest)) then
      xi = closest(1)
      eta = closest(2)
      xc = closest(3:5)
      normal = closest(6:8)
    else
      call closest_point_on_segment(xseg, p, xi, eta, xc, normal)
    end if
    dvec = p - xc
    d = dot_product(dvec, normal)
    offset = dvec - d * normal
    reach = 0.5_wp * (t_slave + t_master)
    diagonal = max(norm2(xseg(:, 3) - xseg(:, 1)), norm2(xseg(:, 4) - xseg(:, 2)))
    if (.not. (diagonal > 0.0_wp)) return          ! collapsed segment: no normal, no contact
    on_edge = abs(xi) >= 1.0_wp .or. abs(eta) >= 1.0_wp
    dist = norm2(dvec)

    if (rounded .and. on_edge .and. dist > 0.0_wp) then
      gap = dist - reach
      direction = dvec / dist
    else if (norm2(offset) <= edge_tolerance * diagonal) then
      gap = abs(d) - reach
      if (d >= 0.0_wp) then
        direction = normal
      else
        direction = -normal
      end if
    else
      return
    end if
    if (.not. (gap < 0.0_wp)) return

    in_contact = .true.
    penetration = -gap
    fn = -k * gap
    f_slave = fn * direction
    shape = segment_shape_functions(xi, eta)

    if (present(v_slave) .and. present(v_master) .and. present(mu_static) .and. &
        present(mu_dynamic)) then
      v_rel = v_slave - matmul(v_master, shape)
      v_t = v_rel - dot_product(v_rel, direction) * direction
      speed = norm2(v_t)
      if (speed > 0.0_wp) then
        mu = mu_dynamic
        if (present(decay)) mu = friction_coefficient(mu_static, mu_dynamic, decay, speed)
        regular = 0.0_wp
        if (present(v_slip)) regular = v_slip
        f_slave = f_slave - mu * abs(fn) * v_t / max(speed, regular)
      end if
    end if

    do i = 1, 4
      f_master(:, i) = -shape(i) * f_slave
    end do
  end subroutine penalty_force

end module contact_penalty
