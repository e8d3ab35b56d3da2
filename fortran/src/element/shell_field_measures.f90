!> Per-element fields of the frames beyond blt_element_results' resultants: the stress at the
!> bottom, middle and top of the shell, the mid-surface membrane strain, the strains at the
!> bottom and top surfaces, the current thickness, and the initial volume
!> by which the internal energy becomes a density. Computed at frames only, never in the time loop.
!> Pure, over groups of n elements with the element index first, like shell_blt.
module shell_field_measures
  use paradyn_kinds, only: wp, ek
  use shell_section, only: stress_components, local_frame, thickness_rule
  use vector_algebra, only: cross
  implicit none
  private
  public :: layer_stresses, membrane_green_strain, surface_strains, initial_volumes, in_plane_means, &
            current_thicknesses

  integer, parameter, public :: n_layers = 3   !< bottom, middle, top
  real(wp), parameter :: mid_tolerance = 1.0e-12_wp   ! a point this close to zeta = 0 is the mid-surface's

contains

  !> A fully integrated element's state (element/shell_full: 4 in-plane points of nip layers,
  !> point (g - 1) nip + k) as one point's for the frames' fields: the mean stress of each layer
  !> over the in-plane points, and the largest plastic strain of each layer.
  pure subroutine in_plane_means(n, nip, stress, eps_p, mean_stress, most_eps_p)
    integer, intent(in) :: n, nip
    real(ek), intent(in) :: stress(n, stress_components, 4 * nip), eps_p(n, 4 * nip)
    real(ek), intent(out) :: mean_stress(n, stress_components, nip), most_eps_p(n, nip)
    integer :: k
    do k = 1, nip
      mean_stress(:, :, k) = 0.25_ek * ((stress(:, :, k) + stress(:, :, nip + k)) &
                                        + (stress(:, :, 2 * nip + k) + stress(:, :, 3 * nip + k)))
      most_eps_p(:, k) = max(eps_p(:, k), eps_p(:, nip + k), eps_p(:, 2 * nip + k), eps_p(:, 3 * nip + k))
    end do
  end subroutine in_plane_means

  !> The five stress components (sxx, syy, sxy, sxz, syz in the element's co-rotational frame) at
  !> the bottom (zeta = -1 side), middle and top of each element: the outermost points, as LS-DYNA
  !> writes its lower and upper surfaces, and the mid-surface interpolated linearly in zeta between
  !> the two points around it (the middle point itself for an odd rule).
  pure subroutine layer_stresses(n, nip, stress, layers)
    integer, intent(in) :: n, nip
    real(ek), intent(in) :: stress(n, stress_components, nip)
    real(wp), intent(out) :: layers(stress_components, n_layers, n)
    real(wp) :: zeta(nip), weight(nip), a
    integer :: i, below
    call thickness_rule(nip, zeta, weight)
    below = max(1, count(zeta < -mid_tolerance))   ! the last point under the mid-surface
    if (nip == 1 .or. abs(zeta(min(below + 1, nip))) <= mid_tolerance) below = min(below + 1, nip)
    a = 0.0_wp
    if (below < nip .and. abs(zeta(below)) > mid_tolerance) a = -zeta(below) / (zeta(below + 1) - zeta(below))
    do i = 1, n
      layers(:, 1, i) = real(stress(i, :, 1), wp)
      layers(:, 3, i) = real(stress(i, :, nip), wp)
      layers(:, 2, i) = real(stress(i, :, below), wp)
      if (a > 0.0_wp) layers(:, 2, i) = (1.0_wp - a) * layers(:, 2, i) + a * real(stress(i, :, below + 1), wp)
    end do
  end subroutine layer_stresses

  !> Green-Lagrange membrane strain (exx, eyy, exy: tensor components) at each element's centre,
  !> E = (F^T F - I) / 2 with F the in-plane gradient of the bilinear map from the element's
  !> initial co-rotational coordinates (x0) to its current ones (x), both frames by the same rule
  !> (shell_section's local_frame): zero for any rigid motion, the engineering strain to first
  !> order. A triangle is its degenerate quadrilateral (corner 4 = corner 3), for which the
  !> gradient at the centre is the triangle's exact constant one.
  pure subroutine membrane_green_strain(n, x0, x, strain)
    integer, intent(in) :: n
    real(wp), intent(in) :: x0(n, 3, 4), x(n, 3, 4)
    real(wp), intent(out) :: strain(3, n)
    real(wp), parameter :: d_xi(4) = [-0.25_wp, 0.25_wp, 0.25_wp, -0.25_wp]
    real(wp), parameter :: d_eta(4) = [-0.25_wp, -0.25_wp, 0.25_wp, 0.25_wp]
    real(wp) :: e(3, 3), xl(4), yl(4), area, j0(2, 2), jc(2, 2), j0_inverse(2, 2), f(2, 2), c(2, 2)
    integer :: i
    do i = 1, n
      call local_frame(x0(i, :, :), e, xl, yl, area)
      j0 = reshape([sum(d_xi * xl), sum(d_xi * yl), sum(d_eta * xl), sum(d_eta * yl)], [2, 2])
      call local_frame(x(i, :, :), e, xl, yl, area)
      jc = reshape([sum(d_xi * xl), sum(d_xi * yl), sum(d_eta * xl), sum(d_eta * yl)], [2, 2])
      j0_inverse = reshape([j0(2, 2), -j0(2, 1), -j0(1, 2), j0(1, 1)], [2, 2]) &
                   / (j0(1, 1) * j0(2, 2) - j0(1, 2) * j0(2, 1))
      f = matmul(jc, j0_inverse)
      c = matmul(transpose(f), f)
      strain(:, i) = [0.5_wp * (c(1, 1) - 1.0_wp), 0.5_wp * (c(2, 2) - 1.0_wp), 0.5_wp * c(1, 2)]
    end do
  end subroutine membrane_green_strain

  !> The in-plane strain (exx, eyy, exy: tensor components) at the bottom (z = -t/2, the side
  !> opposite the normal) and top (z = +t/2) surface of each element, surface(:, 1, i) and
  !> surface(:, 2, i): the membrane strain plus z times the change of curvature, E(z) = E_m + z k.
  !> The curvature comes, as in the force kernels, from the nodal rotations: each node's director
  !> for this element is the element's initial normal n0 turned by the node's rotation since the
  !> start (its orientation quaternion q, nodal_state), d_a = R(q_a) n0; its components along the
  !> current co-rotational axes, d1 = d . e1 and d2 = d . e2, are the tilt of the director against
  !> the element (zero in any rigid motion and at the start), and their gradient at the centre,
  !> over the initial corners as the membrane strain's, gives k_xx = d1,x, k_yy = d2,y and
  !> k_xy = (d1,y + d2,x) / 2. Linear in z, as the strain of a Mindlin plate; a triangle is its
  !> degenerate quadrilateral, as in membrane_green_strain.
  pure subroutine surface_strains(n, x0, x, q, thickness, membrane, surface)
    integer, intent(in) :: n
    real(wp), intent(in) :: x0(n, 3, 4), x(n, 3, 4), q(n, 4, 4), thickness, membrane(3, n)
    real(wp), intent(out) :: surface(3, 2, n)
    real(wp), parameter :: d_xi(4) = [-0.25_wp, 0.25_wp, 0.25_wp, -0.25_wp]
    real(wp), parameter :: d_eta(4) = [-0.25_wp, -0.25_wp, 0.25_wp, 0.25_wp]
    real(wp) :: e0(3, 3), e(3, 3), xl(4), yl(4), area, j0(2, 2), j0_inverse(2, 2), d(3), d1(4), d2(4)
    real(wp) :: g1(2), g2(2), kappa(3)
    integer :: i, a
    do i = 1, n
      call local_frame(x0(i, :, :), e0, xl, yl, area)
      j0 = reshape([sum(d_xi * xl), sum(d_xi * yl), sum(d_eta * xl), sum(d_eta * yl)], [2, 2])
      j0_inverse = reshape([j0(2, 2), -j0(2, 1), -j0(1, 2), j0(1, 1)], [2, 2]) &
                   / (j0(1, 1) * j0(2, 2) - j0(1, 2) * j0(2, 1))
      call local_frame(x(i, :, :), e, xl, yl, area)
      do a = 1, 4
        d = rotated(q(i, :, a), e0(:, 3))
        d1(a) = dot_product(d, e(:, 1))
        d2(a) = dot_product(d, e(:, 2))
      end do
      ! gradients in the initial local axes: (d/dx, d/dy) = J0^-T (d/dxi, d/deta)
      g1 = matmul(transpose(j0_inverse), [sum(d_xi * d1), sum(d_eta * d1)])
      g2 = matmul(transpose(j0_inverse), [sum(d_xi * d2), sum(d_eta * d2)])
      kappa = [g1(1), g2(2), 0.5_wp * (g1(2) + g2(1))]
      surface(:, 1, i) = membrane(:, i) - 0.5_wp * thickness * kappa
      surface(:, 2, i) = membrane(:, i) + 0.5_wp * thickness * kappa
    end do
  end subroutine surface_strains

  !> The vector v turned by the unit quaternion q = (q0, qv): v + 2 qv x (qv x v + q0 v).
  pure function rotated(q, v) result(r)
    real(wp), intent(in) :: q(4), v(3)
    real(wp) :: r(3)
    r = v + 2.0_wp * cross(q(2:4), cross(q(2:4), v) + q(1) * v)
  end function rotated

  !> The current thickness of each shell element, t = t0 exp(eps_z), from the thickness strain at
  !> its mid-surface for an isotropic elastic material whose plastic flow keeps the volume (J2)
  !> under plane stress: eps_z = -ln(A / A0) + (1 - 2 nu) / E (sxx + syy) (docs/theory.md, "Shell
  !> thickness"), with A0 and A the initial and current mid-surface areas (half the cross product
  !> of the diagonals; a triangle's when corner 4 = corner 3) and mid_trace = sxx + syy the
  !> mid-surface stress. An output only: the element's forces keep t0 (LS-DYNA's ISTUPD = 0).
  pure subroutine current_thicknesses(n, x0, x, thickness, young, poisson, mid_trace, current)
    integer, intent(in) :: n
    real(wp), intent(in) :: x0(n, 3, 4), x(n, 3, 4), thickness, young, poisson, mid_trace(n)
    real(wp), intent(out) :: current(n)
    real(wp) :: compliance, a0, a
    integer :: i
    compliance = 0.0_wp
    if (young > 0.0_wp) compliance = (1.0_wp - 2.0_wp * poisson) / young
    do i = 1, n
      a0 = norm2(cross(x0(i, :, 3) - x0(i, :, 1), x0(i, :, 4) - x0(i, :, 2)))
      a = norm2(cross(x(i, :, 3) - x(i, :, 1), x(i, :, 4) - x(i, :, 2)))
      current(i) = thickness * exp(compliance * mid_trace(i) - log(a / a0))
    end do
  end subroutine current_thicknesses

  !> Initial volume of each element: the area of its initial quadrilateral (half the cross product
  !> of the diagonals; a triangle's area when corner 4 = corner 3) times the thickness.
  pure subroutine initial_volumes(n, x0, thickness, volume)
    integer, intent(in) :: n
    real(wp), intent(in) :: x0(n, 3, 4), thickness
    real(wp), intent(out) :: volume(n)
    integer :: i
    do i = 1, n
      volume(i) = 0.5_wp * norm2(cross(x0(i, :, 3) - x0(i, :, 1), x0(i, :, 4) - x0(i, :, 2))) * thickness
    end do
  end subroutine initial_volumes

end module shell_field_measures
