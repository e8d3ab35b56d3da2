!> The truss, the 2-node member of the element family beside the shells (shell_blt, shell_c0_triangle):
!> a bar that carries axial force only (wires, cables; LS-DYNA's *SECTION_BEAM ELFORM 3), of
!> cross-section A (the part's /parts/cross_section_area), with one stress point, the axial stress.
!>
!> The deck stores a truss as an element N1 N2 N2 N2 of a truss part, so the kernel takes the quad's
!> arrays of its group (corners 1 and 2; corners 3 and 4 get no force). Co-rotational and exact for
!> any rigid rotation: the strain increment comes from the change of the current length over the
!> step, d eps = (L_new - L_old) / L_mid with L_old the length at the start of the step
!> (x - dt v), and the force N = sigma A acts along the current axis e = (x2 - x1) / L_new:
!> f_int(node 1) = -N e, f_int(node 2) = N e. L_new - L_old is taken as
!> dt (v2 - v1) . (d_new + d_old) / (L_new + L_old), which has no cancellation for small steps.
!> The stress update is the material family's uniaxial form (update_uniaxial: elastic, J2, the
!> piecewise-linear curve, with their rate laws). Internal energy: the midpoint stress work
!> A L_mid (sigma_old + sigma_new) / 2 d eps = (N_old + N_new) / 2 (L_new - L_old), the work the
!> nodal forces do, so it enters the energy balance like the shells'. Stable step: L / c with the
!> bar wave speed c = sqrt(E / rho); lumped mass rho A L / 2 at each node (Belytschko, Liu & Moran,
!> Nonlinear Finite Elements, 2000, sec. 2.5 and 6.3). docs/theory.md, "Truss".
!>
!> Pure kernels over a group of n elements, element index first, like the shells'.
module truss_element
  use paradyn_kinds, only: wp, ek
  use element_groups, only: group_size
  use shell_section, only: shell_properties_t, stress_components
  use material_model, only: max_state_words
  use element_erosion, only: point_failed
  implicit none
  private
  public :: truss_internal_forces, truss_lumped_mass, truss_stable_time_step, truss_length

contains

  !> Internal nodal forces of a group of n trusses for one step dt_step (x, v: positions at the end
  !> of the step and the velocities over it), the axial stress in stress(:, 1, 1) (the other
  !> components stay zero), the back stress in back(:, 1, 1) where the material keeps one, the
  !> plastic strain eps_p(:, 1), the material's own state(:, :, 1); e_internal += the step's work,
  !> dt_element = L / c at the end of the step. A truss of zero length gets no strain and no force.
  pure subroutine truss_internal_forces(n, x, v, props, dt_step, stress, back, eps_p, state, force, &
                                        e_internal, dt_element)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(in) :: dt_step
    real(ek), intent(inout) :: stress(n, stress_components, 1), back(:, :, :), eps_p(n, 1), state(:, :, :)
    real(wp), intent(out) :: force(6, 4, n)
    real(wp), intent(inout) :: e_internal(n)
    real(wp), intent(out) :: dt_element(n)
    real(wp) :: d_new(3), d_old(3), l_new(group_size), change(group_size), c, axial
    real(ek) :: sp(group_size), bp(group_size), ep(group_size), deps(group_size), stp(group_size, max_state_words)
    logical :: kinematic, history
    integer :: first, m, o, i, ns
    c = sqrt(props%young / props%density)
    kinematic = size(back, 3) > 0
    history = props%material%has_history()
    ns = size(state, 2)
    do first = 1, n, group_size
      m = min(group_size, n - first + 1)
      o = first - 1
      do i = 1, m
        d_new = x(o + i, :, 2) - x(o + i, :, 1)
        d_old = d_new - dt_step * (v(o + i, :, 2) - v(o + i, :, 1))
        l_new(i) = norm2(d_new)
        change(i) = 0.0_wp
        if (l_new(i) + norm2(d_old) > 0.0_wp) &
          change(i) = dt_step * dot_product(v(o + i, :, 2) - v(o + i, :, 1), d_new + d_old) / (l_new(i) + norm2(d_old))
        deps(i) = 0.0_ek
        if (l_new(i) + norm2(d_old) > 0.0_wp) deps(i) = real(2.0_wp * change(i) / (l_new(i) + norm2(d_old)), ek)
        sp(i) = stress(o + i, 1, 1)
        bp(i) = 0.0_ek
        if (kinematic) bp(i) = back(o + i, 1, 1)
        ep(i) = eps_p(o + i, 1)
      end do
      if (ns > 0) stp(1:m, 1:ns) = state(o + 1:o + m, 1:ns, 1)
      call props%material%update_uniaxial(m, real(dt_step, ek), sp(1:m), bp(1:merge(m, 0, kinematic)), ep(1:m), &
                                          stp(1:m, 1:ns), deps(1:m))
      ! a failed point carries no stress (element_erosion; the truss's one point erodes it too)
      if (props%failure_strain > 0.0_wp) where (point_failed(ep(1:m), props%failure_strain)) sp(1:m) = 0.0_ek
      do i = 1, m
        e_internal(o + i) = e_internal(o + i) + props%area * 0.5_wp * real(stress(o + i, 1, 1) + sp(i), wp) * change(i)
        stress(o + i, 1, 1) = sp(i)
        if (kinematic) back(o + i, 1, 1) = bp(i)
        if (history) eps_p(o + i, 1) = ep(i)
        axial = 0.0_wp
        if (l_new(i) > 0.0_wp) axial = props%area * real(sp(i), wp) / l_new(i)
        force(1:3, 2, o + i) = axial * (x(o + i, :, 2) - x(o + i, :, 1))
        force(1:3, 1, o + i) = -force(1:3, 2, o + i)
        force(4:6, 1:2, o + i) = 0.0_wp
        force(:, 3:4, o + i) = 0.0_wp
        dt_element(o + i) = huge(1.0_wp)
        if (l_new(i) > 0.0_wp) dt_element(o + i) = l_new(i) / c
      end do
      if (ns > 0) state(o + 1:o + m, 1:ns, 1) = stp(1:m, 1:ns)
    end do
  end subroutine truss_internal_forces

  !> Lumped mass rho A L / 2 at each end of trusses 1..n (x: the quad's corners, 1 and 2 the
  !> ends). A truss has no rotary inertia of its own; node_inertia: that of a rod about its end,
  !> m L^2 / 12 per node, which lumped_masses gives only to nodes of trusses alone (nothing turns
  !> them: their rotations carry no load).
  pure subroutine truss_lumped_mass(n, x, props, node_mass, node_inertia)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(out) :: node_mass(n), node_inertia(n)
    integer :: i
    do i = 1, n
      node_mass(i) = 0.5_wp * props%density * props%area * truss_length(x(i, :, 1:2))
      node_inertia(i) = node_mass(i) * truss_length(x(i, :, 1:2))**2 / 12.0_wp
    end do
  end subroutine truss_lumped_mass

  !> Stable step L / c of trusses 1..n, c = sqrt(E / rho) the bar wave speed (huge for L = 0).
  pure subroutine truss_stable_time_step(n, x, props, dt_element)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(out) :: dt_element(n)
    real(wp) :: length
    integer :: i
    do i = 1, n
      length = truss_length(x(i, :, 1:2))
      dt_element(i) = huge(1.0_wp)
      if (length > 0.0_wp) dt_element(i) = length / sqrt(props%young / props%density)
    end do
  end subroutine truss_stable_time_step

  !> The length of the truss between the ends x(:, 1) and x(:, 2).
  pure real(wp) function truss_length(x) result(length)
    real(wp), intent(in) :: x(3, 2)
    length = norm2(x(:, 2) - x(:, 1))
  end function truss_length

end module truss_element
