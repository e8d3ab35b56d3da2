!> The section of a part (a Belytschko-Lin-Tsay shell's, or a truss's: element/truss_element) and the
!> geometry every shell routine shares:
!> the part's properties with its material, the state widths, the through-thickness rule and the
!> co-rotational frame of one quadrilateral. Pure, no module state.
module shell_section
  use paradyn_kinds, only: wp
  use vector_algebra, only: cross
  use material_model, only: material_t
  use paradyn_schema, only: hourglass_physical, rotary_inertia_scaled
  use gauss_legendre, only: gauss_zeta, gauss_weight
  implicit none
  private
  public :: shell_properties_t, stress_components, hourglass_components, shear_correction
  public :: back_stress_points, thickness_rule, local_frame, in_plane_points

  integer, parameter :: stress_components = 5     !< sxx, syy, sxy, sxz, syz (local frame)
  !> membrane x, y; rotation x, y; transverse w; the drilling moments of the 4 nodes; then the
  !> second transverse shear resultant of the physical form (its first is the transverse w slot)
  integer, parameter :: hourglass_components = 10
  real(wp), parameter :: shear_correction = 5.0_wp / 6.0_wp

  !> Section and material of one element group (one part). density, young and poisson are the
  !> material's elastic constants, which the element needs whatever the law (mass, wave speed,
  !> transverse shear, hourglass and drilling stiffness); the law itself updates the stresses.
  type :: shell_properties_t
    real(wp) :: thickness = 0.0_wp
    real(wp) :: density = 0.0_wp
    real(wp) :: young = 0.0_wp
    real(wp) :: poisson = 0.0_wp
    real(wp) :: hourglass_coefficient = 0.1_wp
    integer :: integration_points = 5
    integer :: hourglass_form = hourglass_physical
    !> the yield stress that caps the physical form's resultants (huge for an elastic material)
    real(wp) :: hourglass_yield = huge(1.0_wp)
    logical :: warping_correction = .true.   !< shell_warping (docs/theory.md)
    !> the rule for the nodal rotary inertia of the part's shells (rotary_inertia_*: scaled or
    !> radioss; shell_measures.shell_rotary_inertia)
    integer :: rotary_inertia = rotary_inertia_scaled
    !> the fully integrated element (shell_full: 2 x 2 in-plane points, MITC4 shear) for the
    !> part's quadrilaterals, in place of the one-point Belytschko-Lin-Tsay element
    logical :: fully_integrated = .false.
    !> the element's forces use its current thickness, a state updated each step (LS-DYNA ISTUPD = 1;
    !> shell_blt.thickness_strain_step); the one-point quadrilateral only (deck_relations)
    logical :: thickness_update = .false.
    logical :: rigid = .false.          !< a rigid part: no element forces, no step of its own
    logical :: surface_only = .false.   !< the faces of a rigid solid: no mass of their own
    !> the material's failure strain (element_erosion): a point that reaches it fails; 0: never
    real(wp) :: failure_strain = 0.0_wp
    !> the failed layers that erode an element (element_erosion.failed_layers_needed of NUMFIP)
    integer :: failure_layers = 1
    !> a truss part (element/truss_element): 2-node bars of cross-section `area`, one stress point
    logical :: truss = .false.
    real(wp) :: area = 0.0_wp
    class(material_t), allocatable :: material   !< the stress update at the points (material family)
  end type shell_properties_t

contains

  !> Through-thickness points that store a back stress: as many as the part's material asks for.
  pure integer function back_stress_points(props) result(points)
    type(shell_properties_t), intent(in) :: props
    points = props%material%back_stress_points(props%integration_points)
  end function back_stress_points

  !> In-plane points whose stresses an element of the part stores: 4 for the quadrilaterals of a
  !> fully integrated part (shell_full), else 1; a triangle keeps 1 in any part. The element
  !> state holds integration_points x this many points per element, in-plane point slowest.
  pure integer function in_plane_points(props, triangle) result(points)
    type(shell_properties_t), intent(in) :: props
    logical, intent(in) :: triangle
    points = merge(4, 1, props%fully_integrated .and. .not. triangle .and. .not. props%truss)
  end function in_plane_points

  !> Gauss-Legendre points (in [-1, 1]) and weights (summing to 2) for n = 1..9 points.
  pure subroutine thickness_rule(n, zeta, weight)
    integer, intent(in) :: n
    real(wp), intent(out) :: zeta(n), weight(n)
    zeta = gauss_zeta(1:n, n)
    weight = gauss_weight(1:n, n)
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

end module shell_section
