!> Measures of Belytschko-Lin-Tsay shells outside the force kernel: the lumped nodal masses and
!> inertias, each element's stable time step (at set-up from the positions, every cycle from the
!> force kernel's end-of-step frame), and the per-element results written in frames.
!> Pure, over groups of n elements with the element index first, like shell_blt.
module shell_measures
  use paradyn_kinds, only: wp, ek
  use paradyn_schema, only: max_integration_points, rotary_inertia_radioss, rotary_inertia_physical
  use plane_stress_returns, only: von_mises_plane_stress
  use shell_section, only: shell_properties_t, stress_components, local_frame, thickness_rule
  implicit none
  private
  public :: blt_lumped_mass, blt_stable_time_step, blt_element_results, frame_time_steps, part_wave_speed
  public :: triangle_lumped_mass, triangle_stable_time_step, triangle_frame_time_steps
  public :: shell_rotary_inertia, rotational_length

contains

  !> Lumped mass: a quarter of the element mass at each node, and a rotational inertia scaled so
  !> that rotations never govern the time step: I = m (t^2 + A) / 4 (after Key & Beisinger 1971
  !> and Hughes, Liu & Levit 1981, who scale the rotary inertia up for the same reason). The
  !> fastest rotational mode, rotation coupled with w through transverse shear, has
  !> omega ~ sqrt(5 (1 - nu) / 3) c / h with this inertia, below the membrane limit for every nu;
  !> with A / 12 it exceeded that limit for nu < 0.12 (docs/theory.md). rule: the part's
  !> rotary_inertia (shell_rotary_inertia).
  pure subroutine blt_lumped_mass(n, x, thickness, density, rule, node_mass, node_inertia)
    integer, intent(in) :: n, rule
    real(wp), intent(in) :: x(n, 3, 4), thickness, density
    real(wp), intent(out) :: node_mass(n), node_inertia(n)
    real(wp) :: e(3, 3), xl(4), yl(4), area
    integer :: i
    do i = 1, n
      call local_frame(x(i, :, :), e, xl, yl, area)
      node_mass(i) = 0.25_wp * density * thickness * abs(area)
      node_inertia(i) = shell_rotary_inertia(rule, node_mass(i), thickness, abs(area))
    end do
  end subroutine blt_lumped_mass

  !> The rotary inertia a shell element of area A gives a node with its share m of the mass:
  !> scaled (the default), m (t^2 + A) / 4; radioss, m (t^2 + A) / 12 (OpenRadioss's rule for its
  !> QBAT and QEPH shells, m (A / 12 + t^2 / 12); it tends to the physical m t^2 / 12 as the mesh
  !> is refined); physical, m t^2 / 12. docs/theory.md, "Mass and time step".
  pure real(wp) function shell_rotary_inertia(rule, m, thickness, area) result(inertia)
    integer, intent(in) :: rule
    real(wp), intent(in) :: m, thickness, area
    if (rule == rotary_inertia_radioss) then
      inertia = m * (thickness**2 + area) / 12.0_wp
    else if (rule == rotary_inertia_physical) then
      inertia = m * thickness**2 / 12.0_wp
    else
      inertia = m * (thickness**2 + area) / 4.0_wp
    end if
  end function shell_rotary_inertia

  !> The longest length L an element of the part may have in its step L / c: huge, except with
  !> the physical rotary inertia m t^2 / 12, whose mode coupling the rotations with w through the
  !> transverse shear has omega ~ sqrt(5 (1 - nu)) c / t (the estimate of scaled's, with t^2 + A
  !> reduced to t^2); a step 2 / omega caps L at 2 t / sqrt(5 (1 - nu)).
  pure real(wp) function rotational_length(props) result(length)
    type(shell_properties_t), intent(in) :: props
    length = huge(1.0_wp)
    if (props%rotary_inertia == rotary_inertia_physical .and. .not. props%truss) &
      length = 2.0_wp * props%thickness / sqrt(5.0_wp * (1.0_wp - props%poisson))
  end function rotational_length

  !> Stable time step of each element: L / c with L = area / longest side and
  !> c = sqrt(E / (rho (1 - nu^2))) the plate wave speed (Hallquist, LS-DYNA Theory Manual).
  pure subroutine blt_stable_time_step(n, x, props, dt_element)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(out) :: dt_element(n)
    real(wp) :: e(3, 3), xl(4), yl(4), area, longest, c, lrot
    integer :: i, k
    c = part_wave_speed(props)
    lrot = rotational_length(props)
    do i = 1, n
      call local_frame(x(i, :, :), e, xl, yl, area)
      longest = 0.0_wp
      do k = 1, 4
        longest = max(longest, norm2(x(i, :, modulo(k, 4) + 1) - x(i, :, k)))
      end do
      dt_element(i) = abs(area) / longest
      if (dt_element(i) > lrot) dt_element(i) = lrot   ! the physical rotary inertia's cap
      dt_element(i) = dt_element(i) / c
    end do
  end subroutine blt_stable_time_step

  !> The wave speed of a part's material (unscaled density): the plate wave speed
  !> c = sqrt(E / (rho (1 - nu^2))) unless the member bounds the step otherwise; a truss's the bar
  !> wave speed sqrt(E / rho). With the radioss rotary inertia, m (t^2 + A) / 12, the mode that
  !> couples the rotations with w through the transverse shear has omega ~ sqrt(5 (1 - nu)) c / h,
  !> above the membrane limit 2 c / h for nu < 0.2: c is raised by sqrt(5 (1 - nu)) / 2 there, so
  !> that the step L / c keeps that mode below the limit (docs/theory.md, "Mass and time step").
  pure real(wp) function part_wave_speed(props) result(c)
    type(shell_properties_t), intent(in) :: props
    if (props%truss) then
      c = sqrt(props%young / props%density)
      return
    end if
    c = props%material%wave_speed(props%density)
    if (props%rotary_inertia == rotary_inertia_radioss) &
      c = c * max(1.0_wp, sqrt(5.0_wp * (1.0_wp - props%poisson)) / 2.0_wp)
  end function part_wave_speed

  !> The stable step L / c of elements 1..m from their co-rotational frame, as the force kernel
  !> has it at the end of a step: local node coordinates xl, yl and projected area, with the same
  !> L = area / longest side as blt_stable_time_step (the sides measured in the element's plane).
  !> An element whose step is not a number (a NaN in the positions) gets huge: the history's NaN
  !> check names that failure. The frame is in the kernel's kind ek; the step, double.
  pure subroutine frame_time_steps(m, xl, yl, area, props, dt_element)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(:, :), yl(:, :), area(:)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(out) :: dt_element(m)
    real(wp) :: c, lrot
    real(ek) :: longest
    integer :: i, k, k1
    c = part_wave_speed(props)
    lrot = rotational_length(props)
    do i = 1, m
      longest = 0.0_ek
      do k = 1, 4
        k1 = modulo(k, 4) + 1
        longest = max(longest, (xl(i, k1) - xl(i, k))**2 + (yl(i, k1) - yl(i, k))**2)
      end do
      dt_element(i) = abs(area(i)) / sqrt(longest)
      if (dt_element(i) > lrot) dt_element(i) = lrot   ! the physical rotary inertia's cap
      dt_element(i) = dt_element(i) / c
      if (.not. (dt_element(i) >= 0.0_wp)) dt_element(i) = huge(1.0_wp)
    end do
  end subroutine frame_time_steps

  !> Per-element output: mid-surface membrane stress N / t (local frame), the largest von Mises
  !> stress and effective plastic strain over the through-thickness points (from the element
  !> state, of the kernel's kind ek).
  pure subroutine blt_element_results(n, nip, stress, eps_p, membrane, von_mises, plastic_strain)
    integer, intent(in) :: n, nip
    real(ek), intent(in) :: stress(n, stress_components, nip), eps_p(n, nip)
    real(wp), intent(out) :: membrane(n, 3), von_mises(n), plastic_strain(n)
    real(wp) :: zeta(max_integration_points), wgt(max_integration_points)
    integer :: i, k
    call thickness_rule(nip, zeta(1:nip), wgt(1:nip))
    do i = 1, n
      membrane(i, :) = 0.0_wp
      von_mises(i) = 0.0_wp
      do k = 1, nip
        membrane(i, :) = membrane(i, :) + 0.5_wp * wgt(k) * stress(i, 1:3, k)
        von_mises(i) = max(von_mises(i), real(von_mises_plane_stress(stress(i, 1:3, k)), wp))
      end do
      plastic_strain(i) = maxval(eps_p(i, :))
    end do
  end subroutine blt_element_results

  !> Lumped mass of C0 triangles (corners 1..3; corner 4 repeats corner 3 and gets none): a third
  !> of the element mass at each node, and the rotational inertia of blt_lumped_mass,
  !> I = m (t^2 + A) / 4 of the node's share m (docs/theory.md, "C0 triangle"), or the rule's.
  pure subroutine triangle_lumped_mass(n, x, thickness, density, rule, node_mass, node_inertia)
    integer, intent(in) :: n, rule
    real(wp), intent(in) :: x(n, 3, 4), thickness, density
    real(wp), intent(out) :: node_mass(n), node_inertia(n)
    real(wp) :: area
    integer :: i
    do i = 1, n
      area = triangle_area(x(i, :, 1:3))
      node_mass(i) = density * thickness * area / 3.0_wp
      node_inertia(i) = shell_rotary_inertia(rule, node_mass(i), thickness, area)
    end do
  end subroutine triangle_lumped_mass

  !> Stable time step of C0 triangles: L / c with L = 2 A / longest side, the smallest altitude
  !> (LS-DYNA's characteristic length of a triangular shell), c as blt_stable_time_step's.
  pure subroutine triangle_stable_time_step(n, x, props, dt_element)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(out) :: dt_element(n)
    real(wp) :: longest, c, lrot
    integer :: i, k
    c = part_wave_speed(props)
    lrot = rotational_length(props)
    do i = 1, n
      longest = 0.0_wp
      do k = 1, 3
        longest = max(longest, norm2(x(i, :, modulo(k, 3) + 1) - x(i, :, k)))
      end do
      dt_element(i) = 2.0_wp * triangle_area(x(i, :, 1:3)) / longest
      if (dt_element(i) > lrot) dt_element(i) = lrot   ! the physical rotary inertia's cap
      dt_element(i) = dt_element(i) / c
    end do
  end subroutine triangle_stable_time_step

  !> The stable step 2 A / longest side / c of triangles 1..m from the force kernel's end-of-step
  !> frame (local corners xl, yl of 3 nodes and area), as frame_time_steps for quadrilaterals.
  pure subroutine triangle_frame_time_steps(m, xl, yl, area, props, dt_element)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(:, :), yl(:, :), area(:)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(out) :: dt_element(m)
    real(wp) :: c, lrot
    real(ek) :: longest
    integer :: i
    c = part_wave_speed(props)
    lrot = rotational_length(props)
    do i = 1, m
      longest = max((xl(i, 2) - xl(i, 1))**2 + (yl(i, 2) - yl(i, 1))**2, &
                    (xl(i, 3) - xl(i, 2))**2 + (yl(i, 3) - yl(i, 2))**2, &
                    (xl(i, 1) - xl(i, 3))**2 + (yl(i, 1) - yl(i, 3))**2)
      dt_element(i) = 2.0_wp * abs(area(i)) / sqrt(longest)
      if (dt_element(i) > lrot) dt_element(i) = lrot   ! the physical rotary inertia's cap
      dt_element(i) = dt_element(i) / c
      if (.not. (dt_element(i) >= 0.0_wp)) dt_element(i) = huge(1.0_wp)
    end do
  end subroutine triangle_frame_time_steps

  !> Area of the triangle x(:, 1:3).
  pure real(wp) function triangle_area(x) result(area)
    real(wp), intent(in) :: x(3, 3)
    real(wp) :: a(3), b(3)
    a = x(:, 2) - x(:, 1)
    b = x(:, 3) - x(:, 1)
    area = 0.5_wp * norm2([a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)])
  end function triangle_area

end module shell_measures
