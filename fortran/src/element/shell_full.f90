!> The fully integrated 4-node shell (docs/theory.md, "Fully integrated shell"): the element of
!> LS-DYNA's formulation 16 in kind, without hourglass modes and so without hourglass control.
!>
!> Bilinear quadrilateral in the co-rotational frame of the element (shell_frames: one frame
!> per element and step), 2 x 2 Gauss points in the plane and the part's Gauss points through the
!> thickness, velocity strains at each point (membrane and Mindlin curvature from the exact
!> shape-function derivatives), and transverse shear by assumed natural strains (MITC4, Dvorkin &
!> Bathe 1984; Bathe & Dvorkin 1985): the covariant shear strains are taken at the four edge
!> midpoints (tying points) and interpolated, gamma_xi linearly in eta between the edges eta = -1
!> and eta = 1, gamma_eta linearly in xi, then turned to the local axes by the Jacobian's inverse.
!> That shear field has no spurious stiffness in pure bending, so a thin plate does not lock.
!> Warped elements take shell_warping's corrections as the BLT element does (rigid links to the
!> mean plane, and the twist term with its conjugate from the mean moments), and every node the
!> BLT element's drilling stiffness (shell_hourglass's drilling_penalty: the rotation about the
!> normal tied to the in-plane spin, which kinked facets need), its moments kept in the hourglass
!> array's drilling slots 6:9 and its work counted as internal energy: the element has no
!> hourglass modes, so no hourglass energy.
!>
!> State: stress, back stress, plastic strain and the material's own state at every in-plane and
!> through-thickness point, point p = (g - 1) nip + k for in-plane point g and layer k. Each step
!> the material family's update runs once per in-plane point on the nip m points of its layers
!> (in the state's order) for a batch of m elements.
!> Pure kernels over the elements of a group, element index first, as shell_blt; compiled without
!> FMA contraction (fortran/CMakeLists.txt) so an element's bits do not depend on its group.
module shell_full
  use paradyn_kinds, only: wp, ek
  use element_groups, only: group_size
  use paradyn_schema, only: max_integration_points
  use shell_section, only: shell_properties_t, stress_components, shear_correction, thickness_rule, &
                           hourglass_components
  use shell_hourglass, only: drilling_penalty
  use shell_frames, only: frames, store_corner_forces
  use shell_warping, only: warp_heights, warp_curvature, warp_twist_moment
  use shell_measures, only: frame_time_steps
  use material_model, only: max_state_words
  use element_erosion, only: zero_failed_points
  use shell_full_points, only: full_points, point_geometry, point_rates, nodal_forces
  implicit none
  private
  public :: full_internal_forces
  real(ek), parameter :: hw(4) = [1.0_ek, -1.0_ek, 1.0_ek, -1.0_ek]   !< node heights' pattern of a warped element

contains

  !> Internal nodal forces and moments of a group of fully integrated shells for one time step,
  !> with the arguments of shell_blt's blt_internal_forces less the hourglass energy; the state
  !> arrays hold full_points x integration_points points; hourglass(:, 6:9) the drilling moments. Strain rates on the mid-step geometry,
  !> forces on the end-of-step geometry; an element inverted at mid-step keeps its state.
  pure subroutine full_internal_forces(n, x, v, w, props, dt_step, stress, back, eps_p, state, hourglass, &
                                       force, e_internal, inverted, dt_element)
    integer, intent(in) :: n
    real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
    type(shell_properties_t), intent(in) :: props
    real(wp), intent(in) :: dt_step
    real(ek), intent(inout) :: stress(n, stress_components, full_points * props%integration_points)
    real(ek), intent(inout), contiguous :: back(:, :, :)   !< (n, 3, all points), or no points without kinematic hardening
    real(ek), intent(inout) :: eps_p(n, full_points * props%integration_points)
    real(ek), intent(inout), contiguous :: state(:, :, :)   !< (n, the material's state words, all points)
    real(ek), intent(inout) :: hourglass(n, hourglass_components)   !< 6:9: the drilling moments
    real(wp), intent(out) :: force(6, 4, n)
    real(wp), intent(inout) :: e_internal(n)
    integer, intent(inout) :: inverted
    real(wp), intent(out) :: dt_element(n)

    integer :: first, m, o, i, k, c, g, nip
    real(wp) :: zeta_wp(max_integration_points), wgt_wp(max_integration_points)
    real(ek) :: zeta(max_integration_points), wgt(max_integration_points)
    real(ek) :: dt
    real(wp) :: xg(group_size, 3, 4)
    real(ek) :: e(group_size, 3, 3), xl(group_size, 4), yl(group_size, 4), normal_mid(group_size, 3)
    real(ek) :: area_mid(group_size), area(group_size)
    real(ek) :: vl(group_size, 3, 4), wl(group_size, 3, 4), zw(group_size), dh(group_size)
    !> per in-plane point: shape-function derivatives (element, node, point), Jacobian determinant
    !> and entries x_xi, y_xi, x_eta, y_eta
    real(ek) :: dnx(group_size, 4, 4), dny(group_size, 4, 4), detj(group_size, 4), jac(group_size, 4, 4)
    !> per in-plane point: membrane (1:3), curvature (4:6), transverse shear (7:8) rates; then the
    !> resultants N, M, Q of the end-of-step stresses
    real(ek) :: rates(group_size, 8, 4), res(group_size, 8, 4)
    real(ek) :: twist(group_size, 8), drill(group_size, 9), b1(group_size, 4), b2(group_size, 4)
    real(ek) :: work(group_size, 4), fl(group_size, 6, 4), fg(group_size, 6, 4)

    nip = props%integration_points
    call thickness_rule(nip, zeta_wp(1:nip), wgt_wp(1:nip))
    zeta(1:nip) = real(zeta_wp(1:nip), ek)
    wgt(1:nip) = real(wgt_wp(1:nip), ek)
    dt = real(dt_step, ek)

    do first = 1, n, group_size
      m = min(group_size, n - first + 1)
      o = first - 1

      ! --- strain rates at the in-plane points on the mid-step geometry
      xg(1:m, :, :) = x(o + 1:o + m, :, :) - 0.5_wp * dt_step * v(o + 1:o + m, :, :)
      call frames(m, group_size, 0, xg, e, xl, yl, area_mid)
      normal_mid(1:m, :) = e(1:m, :, 3)
      zw = 0.0_ek
      if (props%warping_correction) call warp_heights(m, group_size, 0, xg, e, area_mid, zw)
      call local_velocities(m, n, o, v, w, e, area_mid, zw, vl, wl)
      call point_geometry(m, xl, yl, dnx, dny, detj, jac)
      call point_rates(m, xl, yl, vl, wl, dnx, dny, detj, jac, rates)
      call centre_gradients(m, xl, yl, area_mid, b1, b2)
      call drilling_rates(m, b1, b2, vl, wl, drill)
      if (props%warping_correction) then
        if (any(zw(1:m) /= 0.0_ek)) then
          twist(1:m, :) = 0.0_ek
          call warp_curvature(m, zw, b1, b2, drill, twist)
          do g = 1, 4
            do c = 4, 6
              rates(1:m, c, g) = rates(1:m, c, g) + twist(1:m, c)
            end do
          end do
        end if
      end if

      ! --- stress update at every point, the end-of-step resultants and the stress work
      call point_stresses(m, n, o, props, dt, zeta, wgt, rates, area_mid, stress, back, eps_p, state, res, work)
      call drilling_update(m, n, o, props, dt, area_mid, drill, detj, work, hourglass, e_internal)

      ! --- nodal forces on the end-of-step geometry
      call frames(m, n, o, x, e, xl, yl, area)
      call frame_time_steps(m, xl, yl, area, props, dt_element(o + 1:o + m))
      call point_geometry(m, xl, yl, dnx, dny, detj, jac)
      call check_end_points(m, area_mid, normal_mid, e, detj, area)
      inverted = inverted + count(.not. (area(1:m) > 0.0_ek))
      zw = 0.0_ek
      dh = 0.0_ek
      call centre_gradients(m, xl, yl, area, b1, b2)
      if (props%warping_correction) then
        ! the twist term's conjugate from the area-weighted mean moments
        do c = 4, 6
          do i = 1, m
            twist(i, c) = ((detj(i, 1) * res(i, c, 1) + detj(i, 2) * res(i, c, 2)) &
                           + (detj(i, 3) * res(i, c, 3) + detj(i, 4) * res(i, c, 4))) &
                          / merge(area(i), 1.0_ek, area(i) > 0.0_ek)
          end do
        end do
        call warp_twist_moment(m, n, o, x, e, area, b1, b2, twist, zw, dh)
      end if
      call nodal_forces(m, xl, yl, dnx, dny, detj, jac, res, fl)
      call add_drilling_forces(m, n, o, hourglass, b1, b2, fl)
      if (any(zw(1:m) /= 0.0_ek)) call warp_forces(m, zw, dh, b1, b2, fl)
      ! to global axes in a loop over the elements (vectorised), then into the corner layout
      do k = 1, 4
        do i = 1, m
          fg(i, 1, k) = merge(e(i, 1, 1) * fl(i, 1, k) + e(i, 1, 2) * fl(i, 2, k) + e(i, 1, 3) * fl(i, 3, k), &
                              0.0_ek, area(i) > 0.0_ek)
          fg(i, 2, k) = merge(e(i, 2, 1) * fl(i, 1, k) + e(i, 2, 2) * fl(i, 2, k) + e(i, 2, 3) * fl(i, 3, k), &
                              0.0_ek, area(i) > 0.0_ek)
          fg(i, 3, k) = merge(e(i, 3, 1) * fl(i, 1, k) + e(i, 3, 2) * fl(i, 2, k) + e(i, 3, 3) * fl(i, 3, k), &
                              0.0_ek, area(i) > 0.0_ek)
          fg(i, 4, k) = merge(e(i, 1, 1) * fl(i, 4, k) + e(i, 1, 2) * fl(i, 5, k) + e(i, 1, 3) * fl(i, 6, k), &
                              0.0_ek, area(i) > 0.0_ek)
          fg(i, 5, k) = merge(e(i, 2, 1) * fl(i, 4, k) + e(i, 2, 2) * fl(i, 5, k) + e(i, 2, 3) * fl(i, 6, k), &
                              0.0_ek, area(i) > 0.0_ek)
          fg(i, 6, k) = merge(e(i, 3, 1) * fl(i, 4, k) + e(i, 3, 2) * fl(i, 5, k) + e(i, 3, 3) * fl(i, 6, k), &
                              0.0_ek, area(i) > 0.0_ek)
        end do
      end do
      call store_corner_forces(m, n, o, 4, fg, force)
    end do
  end subroutine full_internal_forces

  !> An element is inverted (its area set to 0, its forces dropped) when its area at mid-step or
  !> a point's Jacobian determinant at the end of the step is not positive, or its normal turned
  !> over in the step: the quadrature samples the map only at its points, so a corner may pass
  !> beyond convex (as squashed folds do) while every point stays valid.
  pure subroutine check_end_points(m, area_mid, normal_mid, e, detj, area)
    integer, intent(in) :: m
    real(ek), intent(in) :: area_mid(group_size), normal_mid(group_size, 3), e(group_size, 3, 3)
    real(ek), intent(in) :: detj(group_size, 4)
    real(ek), intent(inout) :: area(group_size)
    integer :: i
    do i = 1, m
      area(i) = merge(area(i), 0.0_ek, area_mid(i) > 0.0_ek .and. area(i) > 0.0_ek &
                      .and. min(detj(i, 1), detj(i, 2), detj(i, 3), detj(i, 4)) > 0.0_ek &
                      .and. normal_mid(i, 1) * e(i, 1, 3) + normal_mid(i, 2) * e(i, 2, 3) &
                            + normal_mid(i, 3) * e(i, 3, 3) > 0.0_ek)
    end do
  end subroutine check_end_points

  !> The stress update of elements o+1..o+m at every in-plane and through-thickness point, one
  !> material call per in-plane point g on the nip m points of its layers (row r = (k - 1) m + i),
  !> written back by merge so that an element inverted at mid-step keeps its state; res: the
  !> end-of-step resultants of each in-plane point, work: its stress work per unit area in the
  !> step. The points of one g are adjacent in the state (p = (g - 1) nip + k), so the state
  !> streams through in memory order; each sum runs over the layers in order.
  pure subroutine point_stresses(m, n, o, props, dt, zeta, wgt, rates, area_mid, stress, back, eps_p, state, res, work)
    integer, intent(in) :: m, n, o
    type(shell_properties_t), intent(in) :: props
    real(ek), intent(in) :: dt, zeta(:), wgt(:), rates(group_size, 8, 4), area_mid(group_size)
    real(ek), intent(inout) :: stress(n, stress_components, full_points * props%integration_points)
    real(ek), intent(inout), contiguous :: back(:, :, :), state(:, :, :)
    real(ek), intent(inout) :: eps_p(n, full_points * props%integration_points)
    real(ek), intent(out) :: res(group_size, 8, 4), work(group_size, 4)
    integer, parameter :: rows = max_integration_points * group_size
    real(ek) :: sp(rows, stress_components), deps(rows, 3), bp(rows, 3), ep(rows), stp(rows, max_state_words)
    real(ek) :: half_t, shear_step, z, wz, wzz, s1, s2, s3, s4, s5
    integer :: nip, ns, k, g, p, c, i, j, r
    logical :: history, backs
    nip = props%integration_points
    ns = size(state, 2)
    history = props%material%has_history()
    backs = size(back, 3) > 0
    half_t = 0.5_ek * real(props%thickness, ek)
    shear_step = real(shear_correction * (props%young / (2.0_wp * (1.0_wp + props%poisson))), ek) * dt
    res(1:m, :, :) = 0.0_ek
    work(1:m, :) = 0.0_ek
    do g = 1, 4
      if (history .and. .not. backs) bp(1:nip * m, :) = 0.0_ek   ! no kinematic hardening: zero, unstored
      do k = 1, nip
        z = zeta(k) * half_t
        p = (g - 1) * nip + k
        r = (k - 1) * m
        do c = 1, 3
          do i = 1, m
            deps(r + i, c) = dt * (rates(i, c, g) + z * rates(i, 3 + c, g))
            sp(r + i, c) = stress(o + i, c, p)
          end do
        end do
        if (history) then
          if (backs) bp(r + 1:r + m, :) = back(o + 1:o + m, :, p)
          ep(r + 1:r + m) = eps_p(o + 1:o + m, p)
        end if
        if (ns > 0) stp(r + 1:r + m, 1:ns) = state(o + 1:o + m, 1:ns, p)
      end do
      call props%material%update_points(nip * m, dt, sp, bp, ep, stp(:, 1:ns), deps)
      do k = 1, nip
        z = zeta(k) * half_t
        p = (g - 1) * nip + k
        r = (k - 1) * m
        wz = wgt(k) * half_t
        wzz = wgt(k) * half_t * z
        do c = 1, ns
          state(o + 1:o + m, c, p) = merge(stp(r + 1:r + m, c), state(o + 1:o + m, c, p), area_mid(1:m) > 0.0_ek)
        end do
        if (history) then
          if (backs) then
            do c = 1, 3
              back(o + 1:o + m, c, p) = merge(bp(r + 1:r + m, c), back(o + 1:o + m, c, p), area_mid(1:m) > 0.0_ek)
            end do
          end if
          eps_p(o + 1:o + m, p) = merge(ep(r + 1:r + m), eps_p(o + 1:o + m, p), area_mid(1:m) > 0.0_ek)
        end if
        do i = 1, m   ! the transverse shear, elastic
          sp(r + i, 4) = stress(o + i, 4, p) + shear_step * rates(i, 7, g)
          sp(r + i, 5) = stress(o + i, 5, p) + shear_step * rates(i, 8, g)
        end do
        ! a failed point carries no stress (element_erosion)
        if (props%failure_strain > 0.0_wp) &
          call zero_failed_points(m, props%failure_strain, eps_p(o + 1:o + m, p), sp(r + 1:r + m, :))
        do i = 1, m
          j = r + i
          work(i, g) = work(i, g) + wz * ( &
                       (0.5_ek * (stress(o + i, 1, p) + sp(j, 1)) * deps(j, 1) &
                        + 0.5_ek * (stress(o + i, 2, p) + sp(j, 2)) * deps(j, 2) &
                        + 0.5_ek * (stress(o + i, 3, p) + sp(j, 3)) * deps(j, 3)) &
                       + (0.5_ek * (stress(o + i, 4, p) + sp(j, 4)) * (dt * rates(i, 7, g)) &
                          + 0.5_ek * (stress(o + i, 5, p) + sp(j, 5)) * (dt * rates(i, 8, g))))
          s1 = merge(sp(j, 1), stress(o + i, 1, p), area_mid(i) > 0.0_ek)
          s2 = merge(sp(j, 2), stress(o + i, 2, p), area_mid(i) > 0.0_ek)
          s3 = merge(sp(j, 3), stress(o + i, 3, p), area_mid(i) > 0.0_ek)
          s4 = merge(sp(j, 4), stress(o + i, 4, p), area_mid(i) > 0.0_ek)
          s5 = merge(sp(j, 5), stress(o + i, 5, p), area_mid(i) > 0.0_ek)
          stress(o + i, 1, p) = s1
          stress(o + i, 2, p) = s2
          stress(o + i, 3, p) = s3
          stress(o + i, 4, p) = s4
          stress(o + i, 5, p) = s5
          res(i, 1, g) = res(i, 1, g) + wz * s1
          res(i, 2, g) = res(i, 2, g) + wz * s2
          res(i, 3, g) = res(i, 3, g) + wz * s3
          res(i, 4, g) = res(i, 4, g) + wzz * s1
          res(i, 5, g) = res(i, 5, g) + wzz * s2
          res(i, 6, g) = res(i, 6, g) + wzz * s3
          res(i, 7, g) = res(i, 7, g) + wz * s4
          res(i, 8, g) = res(i, 8, g) + wz * s5
        end do
      end do
    end do
  end subroutine point_stresses

  !> The drilling moments of elements o+1..o+m (shell_hourglass's penalty, E t A drilling_penalty
  !> per radian, on the rotation rates about the normal relative to the spin, drill(:, 6:9)), and
  !> the element's stress work (work at the 4 points, weights detj) and drilling work (midpoint
  !> rule) added to its internal energy; an element inverted at mid-step keeps both.
  pure subroutine drilling_update(m, n, o, props, dt, area_mid, drill, detj, work, hourglass, e_internal)
    integer, intent(in) :: m, n, o
    type(shell_properties_t), intent(in) :: props
    real(ek), intent(in) :: dt, area_mid(group_size), drill(group_size, 9), detj(group_size, 4), work(group_size, 4)
    real(ek), intent(inout) :: hourglass(n, hourglass_components)
    real(wp), intent(inout) :: e_internal(n)
    real(ek) :: kd(group_size), d_work(group_size), q_old, q_new
    integer :: i, k
    do i = 1, m
      kd(i) = drilling_penalty * real(props%young, ek) * real(props%thickness, ek) &
              * merge(area_mid(i), 1.0_ek, area_mid(i) > 0.0_ek) * dt
    end do
    d_work(1:m) = 0.0_ek
    do k = 1, 4   ! (the nodes outside, the elements inside: the loop over elements vectorises)
      do i = 1, m
        q_old = hourglass(o + i, 5 + k)
        q_new = q_old + kd(i) * drill(i, 5 + k)
        d_work(i) = d_work(i) + 0.5_ek * (q_old + q_new) * (dt * drill(i, 5 + k))
        hourglass(o + i, 5 + k) = merge(q_new, q_old, area_mid(i) > 0.0_ek)
      end do
    end do
    do i = 1, m
      e_internal(o + i) = merge(e_internal(o + i) + (((detj(i, 1) * work(i, 1) + detj(i, 2) * work(i, 2)) &
                                                      + (detj(i, 3) * work(i, 3) + detj(i, 4) * work(i, 4))) &
                                                     + d_work(i)), &
                                e_internal(o + i), area_mid(i) > 0.0_ek)
    end do

  end subroutine drilling_update

  !> The drilling moments of elements o+1..o+m on their local corner forces fl, and the forces
  !> conjugate to the in-plane spin the drilling rates are measured from (centre gradients b1, b2).
  pure subroutine add_drilling_forces(m, n, o, hourglass, b1, b2, fl)
    integer, intent(in) :: m, n, o
    real(ek), intent(in) :: hourglass(n, hourglass_components), b1(group_size, 4), b2(group_size, 4)
    real(ek), intent(inout) :: fl(group_size, 6, 4)
    real(ek) :: d_total
    integer :: i, k
    do k = 1, 4
      do i = 1, m
        d_total = (hourglass(o + i, 6) + hourglass(o + i, 7)) + (hourglass(o + i, 8) + hourglass(o + i, 9))
        fl(i, 1, k) = fl(i, 1, k) + 0.5_ek * d_total * b2(i, k)
        fl(i, 2, k) = fl(i, 2, k) - 0.5_ek * d_total * b1(i, k)
        fl(i, 6, k) = hourglass(o + i, 5 + k)
      end do
    end do
  end subroutine add_drilling_forces

  !> Local velocities vl = e^T v, wl = e^T w of elements o+1..o+m (zero for an element inverted at
  !> mid-step: no rates, its state kept); a warped element's nodes moved to the mean plane along
  !> their rigid links (shell_warping): vl - z (wl x e3), z = +-zw.
  pure subroutine local_velocities(m, ld, o, v, w, e, area_mid, zw, vl, wl)
    integer, intent(in) :: m, ld, o
    real(wp), intent(in) :: v(ld, 3, 4), w(ld, 3, 4)
    real(ek), intent(in) :: e(group_size, 3, 3), area_mid(group_size), zw(group_size)
    real(ek), intent(out) :: vl(group_size, 3, 4), wl(group_size, 3, 4)
    real(ek) :: valid(group_size), v1, v2, v3, w1, w2, w3, hk
    integer :: i, k
    ! a product, not merge(v, 0, ...): a masked load of v would stop the vectoriser
    valid(1:m) = merge(1.0_ek, 0.0_ek, area_mid(1:m) > 0.0_ek)
    do k = 1, 4
      hk = hw(k)   ! (hw(k) read inside the loop over elements stops gfortran's vectoriser)
      do i = 1, m
        v1 = valid(i) * real(v(o + i, 1, k), ek)
        v2 = valid(i) * real(v(o + i, 2, k), ek)
        v3 = valid(i) * real(v(o + i, 3, k), ek)
        w1 = valid(i) * real(w(o + i, 1, k), ek)
        w2 = valid(i) * real(w(o + i, 2, k), ek)
        w3 = valid(i) * real(w(o + i, 3, k), ek)
        vl(i, 1, k) = e(i, 1, 1) * v1 + e(i, 2, 1) * v2 + e(i, 3, 1) * v3
        vl(i, 2, k) = e(i, 1, 2) * v1 + e(i, 2, 2) * v2 + e(i, 3, 2) * v3
        vl(i, 3, k) = e(i, 1, 3) * v1 + e(i, 2, 3) * v2 + e(i, 3, 3) * v3
        wl(i, 1, k) = e(i, 1, 1) * w1 + e(i, 2, 1) * w2 + e(i, 3, 1) * w3
        wl(i, 2, k) = e(i, 1, 2) * w1 + e(i, 2, 2) * w2 + e(i, 3, 2) * w3
        wl(i, 3, k) = e(i, 1, 3) * w1 + e(i, 2, 3) * w2 + e(i, 3, 3) * w3
        vl(i, 1, k) = merge(vl(i, 1, k) - (hk * zw(i)) * wl(i, 2, k), vl(i, 1, k), zw(i) /= 0.0_ek)
        vl(i, 2, k) = merge(vl(i, 2, k) + (hk * zw(i)) * wl(i, 1, k), vl(i, 2, k), zw(i) /= 0.0_ek)
      end do
    end do
  end subroutine local_velocities

  !> The centre derivatives B1 = dN/dx, B2 = dN/dy (those of the one-point element) of elements
  !> 1..m, for the twist term of a warped element.
  pure subroutine centre_gradients(m, xl, yl, area, b1, b2)
    integer, intent(in) :: m
    real(ek), intent(in) :: xl(group_size, 4), yl(group_size, 4), area(group_size)
    real(ek), intent(out) :: b1(group_size, 4), b2(group_size, 4)
    real(ek) :: r
    integer :: i
    do i = 1, m
      r = 0.5_ek / merge(area(i), 1.0_ek, area(i) > 0.0_ek)
      b1(i, 1) = r * (yl(i, 2) - yl(i, 4))
      b1(i, 2) = r * (yl(i, 3) - yl(i, 1))
      b1(i, 3) = r * (yl(i, 4) - yl(i, 2))
      b1(i, 4) = r * (yl(i, 1) - yl(i, 3))
      b2(i, 1) = r * (xl(i, 4) - xl(i, 2))
      b2(i, 2) = r * (xl(i, 1) - xl(i, 3))
      b2(i, 3) = r * (xl(i, 2) - xl(i, 4))
      b2(i, 4) = r * (xl(i, 3) - xl(i, 1))
    end do
  end subroutine centre_gradients

  !> Each node's rotation rate about the normal relative to the element's in-plane spin (slots
  !> 6:9, as shell_warping's warp_curvature reads them; 1:5 unused).
  pure subroutine drilling_rates(m, b1, b2, vl, wl, drill)
    integer, intent(in) :: m
    real(ek), intent(in) :: b1(group_size, 4), b2(group_size, 4), vl(group_size, 3, 4), wl(group_size, 3, 4)
    real(ek), intent(out) :: drill(group_size, 9)
    real(ek) :: spin
    integer :: i, k
    drill = 0.0_ek
    do i = 1, m
      spin = 0.0_ek
      do k = 1, 4
        spin = spin + (b1(i, k) * vl(i, 2, k) - b2(i, k) * vl(i, 1, k))
      end do
      do k = 1, 4
        drill(i, 5 + k) = wl(i, 3, k) - 0.5_ek * spin
      end do
    end do
  end subroutine drilling_rates

  !> A warped element's terms on its local corner forces fl (shell_warping, as shell_blt's
  !> nodal_forces): the twist's forces dh B and drilling moments dh / 2, and the rigid links'
  !> moments z (f x e3), z = h_k zw; a flat element (zw = 0) keeps its forces bitwise.
  pure subroutine warp_forces(m, zw, dh, b1, b2, fl)
    integer, intent(in) :: m
    real(ek), intent(in) :: zw(group_size), dh(group_size), b1(group_size, 4), b2(group_size, 4)
    real(ek), intent(inout) :: fl(group_size, 6, 4)
    real(ek) :: g1, g2, hk
    integer :: i, k
    do k = 1, 4
      hk = hw(k)
      do i = 1, m
        g1 = fl(i, 1, k) + dh(i) * b2(i, k)
        g2 = fl(i, 2, k) - dh(i) * b1(i, k)
        fl(i, 4, k) = merge(fl(i, 4, k) + (hk * zw(i)) * g2, fl(i, 4, k), zw(i) /= 0.0_ek)
        fl(i, 5, k) = merge(fl(i, 5, k) - (hk * zw(i)) * g1, fl(i, 5, k), zw(i) /= 0.0_ek)
        fl(i, 6, k) = merge(fl(i, 6, k) + 0.5_ek * dh(i), fl(i, 6, k), zw(i) /= 0.0_ek)
        fl(i, 1, k) = merge(g1, fl(i, 1, k), zw(i) /= 0.0_ek)
        fl(i, 2, k) = merge(g2, fl(i, 2, k), zw(i) /= 0.0_ek)
      end do
    end do
  end subroutine warp_forces

end module shell_full
