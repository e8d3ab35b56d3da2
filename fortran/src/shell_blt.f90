!> The Belytschko-Lin-Tsay shell (Belytschko, Lin & Tsay 1984; Hallquist, LS-DYNA Theory Manual).
!>
!> Four-node quadrilateral, one-point quadrature in the plane, Gauss points through the thickness,
!> co-rotational local frame per element and step, velocity-strain formulation (membrane, bending,
!> transverse shear), stresses stored in the co-rotational frame (an objective rate), and
!> stiffness- or viscous-form hourglass control in the manner of Flanagan & Belytschko (1981).
!>
!> Kernels work on a group of n elements whose arrays put the element index first (structure of
!> arrays). They are pure: no MPI, no I/O, no module state.
module shell_blt
  use paradyn_kinds, only: wp
  use material_j2, only: elastic_plane_stress_update, j2_plane_stress_update, von_mises_plane_stress
  implicit none
  private
  public :: shell_properties_t, material_elastic, material_j2_plastic, max_integration_points
  public :: stress_components, hourglass_components, shear_correction
  public :: hourglass_viscous, hourglass_stiffness
  public :: blt_internal_forces, blt_lumped_mass, blt_stable_time_step, blt_element_results
  public :: thickness_rule, local_frame

  integer, parameter :: material_elastic = 1
  integer, parameter :: material_j2_plastic = 2
  integer, parameter :: max_integration_points = 9
  integer, parameter :: hourglass_viscous = 1     !< resultants proportional to the hourglass rates
  integer, parameter :: hourglass_stiffness = 2   !< resultants integrated from the rates (elastic)
  integer, parameter :: stress_components = 5     !< sxx, syy, sxy, sxz, syz (local frame)
  !> membrane x, y; rotation x, y; transverse w; then the drilling moments of the 4 nodes
  integer, parameter :: hourglass_components = 9
  !> drilling stiffness per node, as a fraction of E t A per radian (after the drilling penalty
  !> of Hughes & Brezzi 1989): small enough to leave membrane and bending response alone, large
  !> enough that the rotation about the normal of kinked facets is tied to the in-plane spin
  real(wp), parameter :: drilling_penalty = 1.0e-4_wp
  real(wp), parameter :: shear_correction = 5.0_wp / 6.0_wp
  real(wp), parameter :: hourglass_vector(4) = [1.0_wp, -1.0_wp, 1.0_wp, -1.0_wp]

  !> Section and material of one element group (one part).
  type :: shell_properties_t
    real(wp) :: thickness = 0.0_wp
    real(wp) :: density = 0.0_wp
    real(wp) :: young = 0.0_wp
    real(wp) :: poisson = 0.0_wp
    real(wp) :: yield_stress = 0.0_wp
    real(wp) :: tangent_modulus = 0.0_wp
    real(wp) :: hardening_mixing = 1.0_wp
    real(wp) :: hourglass_coefficient = 0.1_wp
    integer :: model = material_elastic
    integer :: integration_points = 5
    integer :: hourglass_form = hourglass_stiffness
  end type shell_properties_t

contains

  !> Gauss-Legendre points (in [-1, 1]) and weights (summing to 2) for n = 1..9 points.
  pure subroutine thickness_rule(n, zeta, weight)
    integer, intent(in) :: n
    real(wp), intent(out) :: zeta(n), weight(n)
    real(wp), parameter :: pi = acos(-1.0_wp)
    real(wp) :: x, p0, p1, p2, dp
    integer :: i, k, iter
    do i = 1, n
      x = -cos(pi * (real(i, wp) - 0.25_wp) / (real(n, wp) + 0.5_wp))
      do iter = 1, 100
        p0 = 1.0_wp
        p1 = x
        do k = 2, n
          p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
          p0 = p1
          p1 = p2
        end do
        if (n == 1) p0 = 1.0_wp
        dp = n * (x * p1 - p0) / (x * x - 1.0_wp)
        if (abs(p1 / dp) < 1.0e-16_wp) exit
        x = x - p1 / dp
      end do
      zeta(i) = x
      weight(i) = 2.0_wp / ((1.0_wp - x * x) * dp * dp)
    end do
  end subroutine thickness_rule

  !> Co-rotational frame of a quadrilateral: e3 normal to both diagonals, e1 along the mean of the
  !> two sides 1-2 and 4-3 projected into the plane, e2 = e3 x e1. Also the local in-plane
  !> coordinates of the nodes (origin at the centroid) and the area of the projected quad.
  pure subroutine local_frame(x, e, xl, yl, area)
    real(wp), intent(in) :: x(3, 4)
    real(wp), intent(out) :: e(3, 3), xl(4), yl(4), area
    real(wp) :: d31(3), d42(3), g(3), c(3)
    integer :: k
    d31 = x(:, 3) - x(:, 1)
    d42 = x(:, 4) - x(:, 2)
    e(:, 3) = cross(d31, d42)
    e(:, 3) = e(:, 3) / norm2(e(:, 3))
    g = x(:, 2) + x(:, 3) - x(:, 1) - x(:, 4)
    g = g - dot_product(g, e(:, 3)) * e(:, 3)
    e(:, 1) = g / norm2(g)
    e(:, 2) = cross(e(:, 3), e(:, 1))
    c = 0.25_wp * (x(:, 1) + x(:, 2) + x(:, 3) + x(:, 4))
    do k = 1, 4
      xl(k) = dot_product(x(:, k) - c, e(:, 1))
      yl(k) = dot_product(x(:, k) - c, e(:, 2))
    end do
    area = 0.5_wp * ((xl(3) - xl(1)) * (yl(4) - yl(2)) - (xl(4) - xl(2)) * (yl(3) - yl(1)))
  end subroutine local_frame

  !> Every corner of the projected quad turns the same way as the normal (positive corner
  !> Jacobians). An element turned inside out during a step fails this, or flips its normal.
  pure logical function corners_convex(xl, yl)
    real(wp), intent(in) :: xl(4), yl(4)
    integer :: k, next, prev
    corners_convex = .true.
    do k = 1, 4
      next = modulo(k, 4) + 1
      prev = modulo(k + 2, 4) + 1
      if ((xl(next) - xl(k)) * (yl(prev) - yl(k)) - (yl(next) - yl(k)) * (xl(prev) - xl(k)) <= 0.0_wp) then
        corners_convex = .false.
      end if
    end do
  end function corners_convex

  pure function cross(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)
    real(wp) :: c(3)
    c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
  end function cross

  !> Shape-function derivatives at the centre (B1 = dN/dx, B2 = dN/dy) and the hourglass shape
  !> vector gamma = h - (h.x) B1 - (h.y) B2, orthogonal to the linear velocity fields.
  pure subroutine gradient_operators(xl, yl, area, b1, b2, gamma)
    real(wp), intent(in) :: xl(4), yl(4), area
    real(wp), intent(out) :: b1(4), b2(4), gamma(4)
    real(wp) :: r
    r = 0.5_wp / area
    b1 = r * [yl(2) - yl(4), yl(3) - yl(1), yl(4) - yl(2), yl(1) - yl(3)]
    b2 = r * [xl(4) - xl(2), xl(1) - xl(3), xl(2) - xl(4), xl(3) - xl(1)]
    gamma = hourglass_vector - dot_product(hourglass_vector, xl) * b1 &
            - dot_product(hourglass_vector, yl) * b2
  end subroutine gradient_operators

  !> Internal nodal forces and moments of a group of BLT shells for one time step.
  !>
  !> x: node positions at t(n+1); v, w: velocities and angular velocities at t(n+1/2).
  !> Strain rates use the mid-step geometry x - dt/2 v (exact for rigid rotation to second
  !> order); forces use the end-of-step geometry. State arrays are updated in place:
  !> stress (local frame), back stress, effective plastic strain, hourglass resultants.
  !> Element energies accumulate the stress and hourglass work of the step (midpoint rule).
  !> force(i, 1:3, k) is the internal force, force(i, 4:6, k) the internal moment, global axes.
  pure subroutine blt_internal_forces(n, x, v, w, props, dt, stress, back, eps_p, hourglass, &
                                      force, e_internal, e_hourglass, inverted)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(in) :: dt
    real(wp), intent(inout) :: stress(n, stress_components, props%integration_points)
    real(wp), intent(inout) :: back(n, 3, props%integration_points)
    real(wp), intent(inout) :: eps_p(n, props%integration_points)
    real(wp), intent(inout) :: hourglass(n, hourglass_components)
    real(wp), intent(out) :: force(n, 6, 4)
    real(wp), intent(inout) :: e_internal(n), e_hourglass(n)
    integer, intent(inout) :: inverted

    integer :: i, k, nip
    real(wp) :: zeta(max_integration_points), wgt(max_integration_points)
    real(wp) :: xe(3, 4), e(3, 3), xl(4), yl(4), area, b1(4), b2(4), gamma(4)
    real(wp) :: vl(3, 4), wl(3, 4), dm(3), kappa(3), gs(2), qrate(hourglass_components), spin
    real(wp) :: t, half_t, shear, z, deps(3), s_old(stress_components), work, bb, stiff(5), inertia(5)
    real(wp) :: drill_total
    real(wp) :: q_old(hourglass_components), res_n(3), res_m(3), res_q(2), fl(6, 4), normal_mid(3)

    nip = props%integration_points
    call thickness_rule(nip, zeta(1:nip), wgt(1:nip))
    t = props%thickness
    half_t = 0.5_wp * t
    shear = props%young / (2.0_wp * (1.0_wp + props%poisson))

    do i = 1, n
      ! --- strain rates on the mid-step geometry
      xe = x(i, :, :) - 0.5_wp * dt * v(i, :, :)
      call local_frame(xe, e, xl, yl, area)
      if (.not. (area > 0.0_wp)) then
        inverted = inverted + 1
        force(i, :, :) = 0.0_wp
        cycle
      end if
      call gradient_operators(xl, yl, area, b1, b2, gamma)
      vl = matmul(transpose(e), v(i, :, :))
      wl = matmul(transpose(e), w(i, :, :))
      dm = [dot_product(b1, vl(1, :)), dot_product(b2, vl(2, :)), &
            dot_product(b2, vl(1, :)) + dot_product(b1, vl(2, :))]
      kappa = [dot_product(b1, wl(2, :)), -dot_product(b2, wl(1, :)), &
               dot_product(b2, wl(2, :)) - dot_product(b1, wl(1, :))]
      gs = [dot_product(b1, vl(3, :)) + 0.25_wp * sum(wl(2, :)), &
            dot_product(b2, vl(3, :)) - 0.25_wp * sum(wl(1, :))]

      ! --- stress update at each through-thickness point
      work = 0.0_wp
      do k = 1, nip
        z = zeta(k) * half_t
        deps = dt * (dm + z * kappa)
        s_old = stress(i, :, k)
        if (props%model == material_j2_plastic) then
          call j2_plane_stress_update(stress(i, 1:3, k), back(i, :, k), eps_p(i, k), deps, &
                                      props%young, props%poisson, props%yield_stress, &
                                      props%tangent_modulus, props%hardening_mixing)
        else
          call elastic_plane_stress_update(stress(i, 1:3, k), deps, props%young, props%poisson)
        end if
        stress(i, 4:5, k) = stress(i, 4:5, k) + shear_correction * shear * dt * gs
        work = work + wgt(k) * half_t * ( &
               dot_product(0.5_wp * (s_old(1:3) + stress(i, 1:3, k)), deps) + &
               dot_product(0.5_wp * (s_old(4:5) + stress(i, 4:5, k)), dt * gs))
      end do
      e_internal(i) = e_internal(i) + area * work

      ! --- hourglass resultants: stiffness form integrates k q; viscous form is sqrt(k m) q
      spin = 0.5_wp * (dot_product(b1, vl(2, :)) - dot_product(b2, vl(1, :)))
      qrate = [dot_product(gamma, vl(1, :)), dot_product(gamma, vl(2, :)), &
               dot_product(gamma, wl(1, :)), dot_product(gamma, wl(2, :)), &
               dot_product(gamma, vl(3, :)), wl(3, :) - spin]
      bb = sum(b1**2) + sum(b2**2)
      stiff(1:2) = props%young * t * area * bb / 8.0_wp
      stiff(3:4) = props%young * t**3 * area * bb / 192.0_wp
      stiff(5) = props%young * t**3 * area * bb**2 / 192.0_wp
      q_old = hourglass(i, :)
      if (props%hourglass_form == hourglass_viscous) then
        ! element mass for translations, its scaled rotary inertia for rotations (as the lumped mass)
        inertia(1:2) = props%density * t * area
        inertia(3:4) = props%density * t * area * (t**2 + area) / 12.0_wp
        inertia(5) = props%density * t * area
        hourglass(i, 1:5) = props%hourglass_coefficient * sqrt(stiff * inertia) * qrate(1:5)
      else
        hourglass(i, 1:5) = hourglass(i, 1:5) + props%hourglass_coefficient * stiff * dt * qrate(1:5)
      end if
      ! drilling moments: elastic, resisting node rotation about the normal relative to the spin
      hourglass(i, 6:9) = hourglass(i, 6:9) + drilling_penalty * props%young * t * area * dt * qrate(6:9)
      if (props%hourglass_form == hourglass_viscous) then
        e_hourglass(i) = e_hourglass(i) + dt * dot_product(hourglass(i, 1:5), qrate(1:5)) &
                         + dt * dot_product(0.5_wp * (q_old(6:9) + hourglass(i, 6:9)), qrate(6:9))
      else
        e_hourglass(i) = e_hourglass(i) + dt * dot_product(0.5_wp * (q_old + hourglass(i, :)), qrate)
      end if

      ! --- resultants and nodal forces on the end-of-step geometry
      normal_mid = e(:, 3)
      xe = x(i, :, :)
      call local_frame(xe, e, xl, yl, area)
      if (.not. (area > 0.0_wp .and. dot_product(normal_mid, e(:, 3)) > 0.0_wp &
                 .and. corners_convex(xl, yl))) then
        inverted = inverted + 1
        force(i, :, :) = 0.0_wp
        cycle
      end if
      call gradient_operators(xl, yl, area, b1, b2, gamma)
      res_n = 0.0_wp
      res_m = 0.0_wp
      res_q = 0.0_wp
      do k = 1, nip
        z = zeta(k) * half_t
        res_n = res_n + wgt(k) * half_t * stress(i, 1:3, k)
        res_m = res_m + wgt(k) * half_t * z * stress(i, 1:3, k)
        res_q = res_q + wgt(k) * half_t * stress(i, 4:5, k)
      end do
      drill_total = sum(hourglass(i, 6:9))
      fl(1, :) = area * (b1 * res_n(1) + b2 * res_n(3)) + gamma * hourglass(i, 1) + 0.5_wp * drill_total * b2
      fl(2, :) = area * (b2 * res_n(2) + b1 * res_n(3)) + gamma * hourglass(i, 2) - 0.5_wp * drill_total * b1
      fl(3, :) = area * (b1 * res_q(1) + b2 * res_q(2)) + gamma * hourglass(i, 5)
      fl(4, :) = -area * (b2 * res_m(2) + b1 * res_m(3) + 0.25_wp * res_q(2)) + gamma * hourglass(i, 3)
      fl(5, :) = area * (b1 * res_m(1) + b2 * res_m(3) + 0.25_wp * res_q(1)) + gamma * hourglass(i, 4)
      fl(6, :) = hourglass(i, 6:9)
      force(i, 1:3, :) = matmul(e, fl(1:3, :))
      force(i, 4:6, :) = matmul(e, fl(4:6, :))
    end do
  end subroutine blt_internal_forces

  !> Lumped mass: a quarter of the element mass at each node, and a rotational inertia scaled so
  !> that rotations never govern the time step: I = m (t^2 + A) / 4 (after Key & Beisinger 1971
  !> and Hughes, Liu & Levit 1981, who scale the rotary inertia up for the same reason). The
  !> fastest rotational mode, rotation coupled with w through transverse shear, has
  !> omega ~ sqrt(5 (1 - nu) / 3) c / h with this inertia, below the membrane limit for every nu;
  !> with A / 12 it exceeded that limit for nu < 0.12 (docs/theory.md).
  pure subroutine blt_lumped_mass(n, x, thickness, density, node_mass, node_inertia)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4), thickness, density
    real(wp), intent(out) :: node_mass(n), node_inertia(n)
    real(wp) :: e(3, 3), xl(4), yl(4), area
    integer :: i
    do i = 1, n
      call local_frame(x(i, :, :), e, xl, yl, area)
      node_mass(i) = 0.25_wp * density * thickness * abs(area)
      node_inertia(i) = node_mass(i) * (thickness**2 + abs(area)) / 4.0_wp
    end do
  end subroutine blt_lumped_mass

  !> Stable time step of each element: L / c with L = area / longest side and
  !> c = sqrt(E / (rho (1 - nu^2))) the plate wave speed (Hallquist, LS-DYNA Theory Manual).
  pure subroutine blt_stable_time_step(n, x, props, dt_element)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(out) :: dt_element(n)
    real(wp) :: e(3, 3), xl(4), yl(4), area, longest, c
    integer :: i, k
    c = sqrt(props%young / (props%density * (1.0_wp - props%poisson**2)))
    do i = 1, n
      call local_frame(x(i, :, :), e, xl, yl, area)
      longest = 0.0_wp
      do k = 1, 4
        longest = max(longest, norm2(x(i, :, modulo(k, 4) + 1) - x(i, :, k)))
      end do
      dt_element(i) = abs(area) / longest / c
    end do
  end subroutine blt_stable_time_step

  !> Per-element output: mid-surface membrane stress N / t (local frame), the largest von Mises
  !> stress and effective plastic strain over the through-thickness points.
  pure subroutine blt_element_results(n, nip, stress, eps_p, membrane, von_mises, plastic_strain)
    integer, intent(in) :: n, nip
    real(wp), intent(in) :: stress(n, stress_components, nip), eps_p(n, nip)
    real(wp), intent(out) :: membrane(n, 3), von_mises(n), plastic_strain(n)
    real(wp) :: zeta(max_integration_points), wgt(max_integration_points)
    integer :: i, k
    call thickness_rule(nip, zeta(1:nip), wgt(1:nip))
    do i = 1, n
      membrane(i, :) = 0.0_wp
      von_mises(i) = 0.0_wp
      do k = 1, nip
        membrane(i, :) = membrane(i, :) + 0.5_wp * wgt(k) * stress(i, 1:3, k)
        von_mises(i) = max(von_mises(i), von_mises_plane_stress(stress(i, 1:3, k)))
      end do
      plastic_strain(i) = maxval(eps_p(i, :))
    end do
  end subroutine blt_element_results

end module shell_blt
