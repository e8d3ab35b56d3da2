!> Hourglass control of the one-point Belytschko-Lin-Tsay shell: the resultants that resist the
!> element's zero-energy modes, and the drilling moments. Three forms (docs/theory.md, Hourglass):
!>
!> - viscous and stiffness (Flanagan & Belytschko 1981; Belytschko, Lin & Tsay 1984): resultants
!>   proportional to the hourglass rates, or integrated from them, scaled by a coefficient;
!> - physical (the default): the stiffness of the strain fields the one-point rule misses, from
!>   the section's elastic constants, with no coefficient. Membrane and bending follow the
!>   assumed-strain stabilisation of Belytschko & Bindeman (1991) for bending-exact quadrilaterals
!>   (no parasitic in-plane shear, the Poisson coupling kept); transverse shear follows the edge
!>   tying of Bathe & Dvorkin (1985), as Belytschko & Leviathan (1994) stabilise the shell, so that
!>   a twisted element has no shear strain and a thin plate does not lock.
!>
!> Pure kernels over groups of m elements, element index first, like shell_blt.
module shell_hourglass
  use paradyn_kinds, only: wp, ek
  use element_groups, only: group_size
  use paradyn_schema, only: hourglass_viscous, hourglass_physical
  use shell_section, only: shell_properties_t, hourglass_components, shear_correction
  implicit none
  private
  public :: hourglass_update, add_shear_hourglass_moments, tangent_work, tangent_share, drilling_penalty

  !> drilling stiffness per node, as a fraction of E t A per radian (after the drilling penalty
  !> of Hughes & Brezzi 1989): small enough to leave membrane and bending response alone, large
  !> enough that the rotation about the normal of kinked facets is tied to the in-plane spin
  real(ek), parameter :: drilling_penalty = 1.0e-4_ek

  !> |h,x| integrates to sqrt(3) / 2 sqrt(A C_xx) over a rectangle: the fully plastic field's share
  real(ek), parameter :: plastic_shape = 0.5_ek * sqrt(3.0_ek)

  !> the least share of the elastic stiffness the physical form keeps in a yielding element,
  !> so that its hourglass modes stay stable in perfectly plastic flow
  real(ek), parameter :: tangent_floor = 0.05_ek

  !> natural coordinates of the corners (counter-clockwise from (-1, -1))
  real(ek), parameter :: xi_node(4) = [-1.0_ek, 1.0_ek, 1.0_ek, -1.0_ek]
  real(ek), parameter :: eta_node(4) = [-1.0_ek, -1.0_ek, 1.0_ek, 1.0_ek]

contains

  !> Hourglass resultants hg of elements 1..m, updated in place, and their work in the step.
  !> qrate: the hourglass rates (5 modes, the 4 drilling rates); grad_w: the centre gradients of
  !> the rotation rates (d/dx theta_x, d/dy theta_y, d/dx theta_y, d/dy theta_x); xl, yl: the
  !> local node coordinates of the geometry of the rates.
  pure subroutine hourglass_update(m, props, dt, area, b1, b2, xl, yl, qrate, grad_w, tangent, hg, work)
    integer, intent(in) :: m
    type(shell_properties_t), intent(in) :: props
    real(ek), intent(in) :: dt, area(group_size), b1(group_size, 4), b2(group_size, 4)
    real(ek), intent(in) :: xl(group_size, 4), yl(group_size, 4)
    real(ek), intent(in) :: qrate(group_size, hourglass_components), grad_w(group_size, 4)
    real(ek), intent(in) :: tangent(group_size)   !< the element's tangent share of its elastic stiffness
    real(ek), intent(inout) :: hg(group_size, hourglass_components)
    real(ek), intent(out) :: work(group_size)
    real(ek) :: drill(group_size), power(group_size), power_drill(group_size)
    real(ek) :: t, young, q_old
    integer :: i, c
    t = real(props%thickness, ek)
    young = real(props%young, ek)
    if (props%hourglass_form == hourglass_physical) then
      ! no coefficient, but 0 still means off ([effects] hourglass = false): no resultants, no work
      power = 0.0_ek
      if (props%hourglass_coefficient > 0.0_ek) &
        call physical_update(m, props, dt, area, xl, yl, qrate, grad_w, tangent, hg, power)
    else
      call coefficient_update(m, props, dt, area, b1, b2, qrate, hg, power)
    end if
    do i = 1, m
      drill(i) = drilling_penalty * young * t * merge(area(i), 1.0_ek, area(i) > 0.0_ek) * dt
    end do
    power_drill = 0.0_ek
    do c = 6, 9
      do i = 1, m
        q_old = hg(i, c)
        hg(i, c) = hg(i, c) + drill(i) * qrate(i, c)
        power_drill(i) = power_drill(i) + 0.5_ek * (q_old + hg(i, c)) * qrate(i, c)
      end do
    end do
    if (props%hourglass_form == hourglass_viscous) then
      work(1:m) = dt * power(1:m) + dt * power_drill(1:m)
    else
      work(1:m) = dt * (power(1:m) + power_drill(1:m))
    end if
  end subroutine hourglass_update

  !> The viscous and stiffness forms: the stiffness form integrates k q, the viscous form is
  !> sqrt(k m) q, both scaled by the part's coefficient; power is that of the 5 modes.
  pure subroutine coefficient_update(m, props, dt, area, b1, b2, qrate, hg, power)
    integer, intent(in) :: m
    type(shell_properties_t), intent(in) :: props
    real(ek), intent(in) :: dt, area(group_size), b1(group_size, 4), b2(group_size, 4)
    real(ek), intent(in) :: qrate(group_size, hourglass_components)
    real(ek), intent(inout) :: hg(group_size, hourglass_components)
    real(ek), intent(out) :: power(group_size)
    real(ek) :: factor(group_size, 5)
    real(ek) :: t, a, bb, mass, rotary, q_old, density, young, coefficient
    integer :: i, c
    t = real(props%thickness, ek)
    density = real(props%density, ek)
    young = real(props%young, ek)
    coefficient = real(props%hourglass_coefficient, ek)
    ! one loop per form: a logical tested inside a loop stops gfortran's vectoriser
    if (props%hourglass_form == hourglass_viscous) then
      do i = 1, m
        a = merge(area(i), 1.0_ek, area(i) > 0.0_ek)
        bb = (b1(i, 1)**2 + b1(i, 2)**2 + b1(i, 3)**2 + b1(i, 4)**2) &
             + (b2(i, 1)**2 + b2(i, 2)**2 + b2(i, 3)**2 + b2(i, 4)**2)
        ! element mass for translations, its scaled rotary inertia for rotations (as the lumped mass)
        mass = density * t * a
        rotary = density * t * a * (t**2 + a) / 12.0_ek
        factor(i, 1) = coefficient * sqrt(young * t * a * bb / 8.0_ek * mass)
        factor(i, 3) = coefficient &
                       * sqrt(young * t**3 * a * bb / 192.0_ek * rotary)
        factor(i, 5) = coefficient &
                       * sqrt(young * t**3 * a * bb**2 / 192.0_ek * mass)
      end do
    else
      do i = 1, m
        a = merge(area(i), 1.0_ek, area(i) > 0.0_ek)
        bb = (b1(i, 1)**2 + b1(i, 2)**2 + b1(i, 3)**2 + b1(i, 4)**2) &
             + (b2(i, 1)**2 + b2(i, 2)**2 + b2(i, 3)**2 + b2(i, 4)**2)
        factor(i, 1) = coefficient * (young * t * a * bb / 8.0_ek) * dt
        factor(i, 3) = coefficient * (young * t**3 * a * bb / 192.0_ek) * dt
        factor(i, 5) = coefficient * (young * t**3 * a * bb**2 / 192.0_ek) * dt
      end do
    end if
    do i = 1, m
      factor(i, 2) = factor(i, 1)
      factor(i, 4) = factor(i, 3)
    end do
    power = 0.0_ek
    if (props%hourglass_form == hourglass_viscous) then
      do c = 1, 5
        do i = 1, m
          hg(i, c) = factor(i, c) * qrate(i, c)
          power(i) = power(i) + hg(i, c) * qrate(i, c)
        end do
      end do
    else
      do c = 1, 5
        do i = 1, m
          q_old = hg(i, c)
          hg(i, c) = hg(i, c) + factor(i, c) * qrate(i, c)
          power(i) = power(i) + 0.5_ek * (q_old + hg(i, c)) * qrate(i, c)
        end do
      end do
    end if
  end subroutine coefficient_update

  !> The physical form. The hourglass field q xi eta of a velocity component has the gradient
  !> J^-T (eta, xi); with the centre Jacobian J = [a1 a2] its squares integrate to
  !> C_xx = int (dh/dx)^2 dA = 16 / (3 A) (a1y^2 + a2y^2), C_yy likewise with x, and
  !> C_xy = -16 / (3 A) (a1x a1y + a2x a2y). The assumed strains eps_xx = h,x q_x - nu h,y q_y,
  !> eps_yy = h,y q_y - nu h,x q_x, gamma_xy = 0 bend the element exactly and store
  !> U = E t / 2 (C_xx q_x^2 + C_yy q_y^2 - 2 nu C_xy q_x q_y), with q = Q / 4 of the rates Q =
  !> gamma . v; bending is the same with E t^3 / 12 and the slopes (theta_y, -theta_x) for (u, v).
  !> Transverse shear: the covariant shear along xi tied at the edge midpoints varies as
  !> eta H_xi, H_xi = (Q_w + sum eta_I a1 . phi_I) / 4 with phi = (theta_y, -theta_x), and along
  !> eta as xi H_eta; U = k G t / 2 (C |a2|^2 H_xi^2 + C |a1|^2 H_eta^2), C = 16 / (3 A).
  !> sum eta_I f_I = 4 (a2 . grad f) exactly for a bilinear element, so the centre gradients give
  !> the sums. Resultants are integrated from the rates (an elastic stiffness form).
  pure subroutine physical_update(m, props, dt, area, xl, yl, qrate, grad_w, tangent, hg, power)
    integer, intent(in) :: m
    type(shell_properties_t), intent(in) :: props
    real(ek), intent(in) :: dt, area(group_size), xl(group_size, 4), yl(group_size, 4)
    real(ek), intent(in) :: qrate(group_size, hourglass_components), grad_w(group_size, 4)
    real(ek), intent(in) :: tangent(group_size)
    real(ek), intent(inout) :: hg(group_size, hourglass_components)
    real(ek), intent(out) :: power(group_size)
    real(ek) :: membrane, bending, shear, nu, a1x, a1y, a2x, a2y, c, cxx, cyy, cxy
    real(ek) :: d1, d2, d3, d4, h_xi, h_eta, old1, old2, old3, old4, old5, old10, a, cap, yield, thick
    logical :: plastic
    integer :: i
    ! the part's constants in the kernel's kind, once (huge, an elastic part's yield, stays finite)
    plastic = props%hourglass_yield < huge(1.0_wp)
    yield = real(min(props%hourglass_yield, real(huge(1.0_ek), wp)), ek)
    thick = real(props%thickness, ek)
    membrane = real(props%young * props%thickness / 16.0_wp, ek)
    bending = real(props%young * props%thickness**3 / 192.0_wp, ek)
    shear = real(shear_correction * props%young / (2.0_wp * (1.0_wp + props%poisson)) * props%thickness, ek)
    nu = real(props%poisson, ek)
    do i = 1, m
      a1x = 0.25_ek * (-xl(i, 1) + xl(i, 2) + xl(i, 3) - xl(i, 4))
      a1y = 0.25_ek * (-yl(i, 1) + yl(i, 2) + yl(i, 3) - yl(i, 4))
      a2x = 0.25_ek * (-xl(i, 1) - xl(i, 2) + xl(i, 3) + xl(i, 4))
      a2y = 0.25_ek * (-yl(i, 1) - yl(i, 2) + yl(i, 3) + yl(i, 4))
      a = merge(area(i), 1.0_ek, area(i) > 0.0_ek)
      c = 16.0_ek / (3.0_ek * a)
      cxx = c * (a1y * a1y + a2y * a2y)
      cyy = c * (a1x * a1x + a2x * a2x)
      cxy = -c * (a1x * a1y + a2x * a2y)
      d1 = tangent(i) * dt * qrate(i, 1)
      d2 = tangent(i) * dt * qrate(i, 2)
      d3 = tangent(i) * dt * qrate(i, 3)
      d4 = tangent(i) * dt * qrate(i, 4)
      h_xi = 0.25_ek * qrate(i, 5) + (a1x * (a2x * grad_w(i, 3) + a2y * grad_w(i, 2)) &
                                      - a1y * (a2x * grad_w(i, 1) + a2y * grad_w(i, 4)))
      h_eta = 0.25_ek * qrate(i, 5) + (a2x * (a1x * grad_w(i, 3) + a1y * grad_w(i, 2)) &
                                       - a2y * (a1x * grad_w(i, 1) + a1y * grad_w(i, 4)))
      old1 = hg(i, 1)
      old2 = hg(i, 2)
      old3 = hg(i, 3)
      old4 = hg(i, 4)
      old5 = hg(i, 5)
      old10 = hg(i, 10)
      hg(i, 1) = old1 + membrane * (cxx * d1 - nu * cxy * d2)
      hg(i, 2) = old2 + membrane * (cyy * d2 - nu * cxy * d1)
      hg(i, 3) = old3 + bending * (cyy * d3 + nu * cxy * d4)
      hg(i, 4) = old4 + bending * (cxx * d4 + nu * cxy * d3)
      hg(i, 5) = old5 + shear * c * (a2x * a2x + a2y * a2y) * (tangent(i) * dt * h_xi)
      hg(i, 10) = old10 + shear * c * (a1x * a1x + a1y * a1y) * (tangent(i) * dt * h_eta)
      if (plastic) then   ! the fully plastic hourglass stress fields bound the resultants
        cap = yield * thick * sqrt(a * cxx) * plastic_shape / 4.0_ek
        hg(i, 1) = max(-cap, min(cap, hg(i, 1)))
        hg(i, 4) = max(-cap * thick / 4.0_ek, min(cap * thick / 4.0_ek, hg(i, 4)))
        cap = yield * thick * sqrt(a * cyy) * plastic_shape / 4.0_ek
        hg(i, 2) = max(-cap, min(cap, hg(i, 2)))
        hg(i, 3) = max(-cap * thick / 4.0_ek, min(cap * thick / 4.0_ek, hg(i, 3)))
        cap = yield / sqrt(3.0_ek) * thick * plastic_shape
        hg(i, 5) = max(-cap * sqrt(a * c * (a2x * a2x + a2y * a2y)), min(cap * sqrt(a * c * (a2x * a2x + a2y * a2y)), hg(i, 5)))
        hg(i, 10) = max(-cap * sqrt(a * c * (a1x * a1x + a1y * a1y)), min(cap * sqrt(a * c * (a1x * a1x + a1y * a1y)), hg(i, 10)))
      end if
      power(i) = 0.5_ek * ((old1 + hg(i, 1)) * qrate(i, 1) + (old2 + hg(i, 2)) * qrate(i, 2) &
                           + (old3 + hg(i, 3)) * qrate(i, 3) + (old4 + hg(i, 4)) * qrate(i, 4) &
                           + (old5 + hg(i, 5)) * h_xi + (old10 + hg(i, 10)) * h_eta)
    end do
  end subroutine physical_update

  !> Adds one through-thickness point (weight w) to the work of its stress increment sp - old
  !> against the work the increment deps would do elastically (plane stress): their ratio over
  !> the points is the element's tangent share of its elastic stiffness in this step.
  pure subroutine tangent_work(m, w, props, deps, old, sp, actual_work, elastic_work)
    integer, intent(in) :: m
    real(ek), intent(in) :: w
    type(shell_properties_t), intent(in) :: props
    real(ek), intent(in) :: deps(group_size, 3), old(:, :), sp(group_size, 5)
    real(ek), intent(inout) :: actual_work(group_size), elastic_work(group_size)
    real(ek) :: plane_modulus, nu
    integer :: i
    nu = real(props%poisson, ek)
    plane_modulus = real(props%young, ek) / (1.0_ek - nu * nu)
    do i = 1, m
      actual_work(i) = actual_work(i) + w * ((sp(i, 1) - old(i, 1)) * deps(i, 1) + (sp(i, 2) - old(i, 2)) * deps(i, 2) &
                                             + (sp(i, 3) - old(i, 3)) * deps(i, 3))
      elastic_work(i) = elastic_work(i) + w * plane_modulus * (deps(i, 1) * deps(i, 1) + deps(i, 2) * deps(i, 2) &
                                                               + 2.0_ek * nu * deps(i, 1) * deps(i, 2) &
                                                               + 0.5_ek * (1.0_ek - nu) * deps(i, 3) * deps(i, 3))
    end do
  end subroutine tangent_work

  !> The tangent share in [tangent_floor, 1]: 1 where the step did no elastic work to compare.
  pure function tangent_share(m, actual_work, elastic_work) result(share)
    integer, intent(in) :: m
    real(ek), intent(in) :: actual_work(group_size), elastic_work(group_size)
    real(ek) :: share(m)
    integer :: i
    do i = 1, m
      share(i) = merge(max(tangent_floor, min(1.0_ek, actual_work(i) / merge(elastic_work(i), 1.0_ek, &
                                                                               elastic_work(i) > 0.0_ek))), &
                       1.0_ek, elastic_work(i) > 0.0_ek)
    end do
  end function tangent_share

  !> The physical form's transverse shear resultants S_xi = hg(5), S_eta = hg(10) act on the
  !> lateral velocity through (S_xi + S_eta) / 4 gamma_I, which the caller puts in hg(5) for
  !> the common nodal forces, and on the slopes phi_I = (theta_y, -theta_x) through
  !> (S_xi eta_I a1 + S_eta xi_I a2) / 4: those moments are added here (global axes, end-of-step
  !> frame e and coordinates xl, yl; nothing for an element of area <= 0).
  pure subroutine add_shear_hourglass_moments(m, e, area, xl, yl, s_xi, s_eta, force)
    integer, intent(in) :: m
    real(ek), intent(in) :: e(group_size, 3, 3), area(group_size), xl(group_size, 4), yl(group_size, 4)
    real(ek), intent(in) :: s_xi(group_size), s_eta(group_size)
    real(ek), intent(inout) :: force(group_size, 6, 4)
    real(ek) :: a1x(group_size), a1y(group_size), a2x(group_size), a2y(group_size), mx, my
    integer :: i, k
    do i = 1, m
      a1x(i) = 0.25_ek * (-xl(i, 1) + xl(i, 2) + xl(i, 3) - xl(i, 4))
      a1y(i) = 0.25_ek * (-yl(i, 1) + yl(i, 2) + yl(i, 3) - yl(i, 4))
      a2x(i) = 0.25_ek * (-xl(i, 1) - xl(i, 2) + xl(i, 3) + xl(i, 4))
      a2y(i) = 0.25_ek * (-yl(i, 1) - yl(i, 2) + yl(i, 3) + yl(i, 4))
    end do
    do k = 1, 4
      do i = 1, m
        ! moment about local y (conjugate to theta_y = phi_x) and about local x (to theta_x = -phi_y)
        my = 0.25_ek * (s_xi(i) * eta_node(k) * a1x(i) + s_eta(i) * xi_node(k) * a2x(i))
        mx = -0.25_ek * (s_xi(i) * eta_node(k) * a1y(i) + s_eta(i) * xi_node(k) * a2y(i))
        force(i, 4, k) = force(i, 4, k) + merge(e(i, 1, 1) * mx + e(i, 1, 2) * my, 0.0_ek, area(i) > 0.0_ek)
        force(i, 5, k) = force(i, 5, k) + merge(e(i, 2, 1) * mx + e(i, 2, 2) * my, 0.0_ek, area(i) > 0.0_ek)
        force(i, 6, k) = force(i, 6, k) + merge(e(i, 3, 1) * mx + e(i, 3, 2) * my, 0.0_ek, area(i) > 0.0_ek)
      end do
    end do
  end subroutine add_shear_hourglass_moments

end module shell_hourglass
