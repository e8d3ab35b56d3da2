! The material kernels for Python through f2py (module paradyn._kernels, with kernels_f2py.f90):
! thin explicit-shape wrappers, properties as scalars (f2py cannot pass derived types).

subroutine j2_update(stress, back, eps_p, dstrain, young, poisson, yield_stress, tangent, beta)
  use paradyn_kinds, only: wp
  use plane_stress_returns, only: j2_plane_stress_update
  implicit none
  real(wp), intent(inout) :: stress(3), back(3), eps_p
  real(wp), intent(in) :: dstrain(3), young, poisson, yield_stress, tangent, beta
  call j2_plane_stress_update(stress, back, eps_p, dstrain, young, poisson, yield_stress, tangent, beta)
end subroutine j2_update

! The array form used by the element kernel: m points, point index first.
subroutine j2_update_points(m, stress, back, eps_p, dstrain, young, poisson, yield_stress, tangent, beta)
  use paradyn_kinds, only: wp
  use plane_stress_returns, only: j2_plane_stress_update_points
  implicit none
  integer, intent(in) :: m
  real(wp), intent(inout) :: stress(m, 3), back(m, 3), eps_p(m)
  real(wp), intent(in) :: dstrain(m, 3), young, poisson, yield_stress, tangent, beta
  call j2_plane_stress_update_points(m, stress, back, eps_p, dstrain, young, poisson, yield_stress, tangent, beta)
end subroutine j2_update_points

! The radial return without the plane-stress iteration (the j2_radial member), same arrays.
subroutine j2_radial_points(m, stress, back, eps_p, dstrain, young, poisson, yield_stress, tangent, beta)
  use paradyn_kinds, only: wp
  use plane_stress_returns, only: j2_radial_update_points
  implicit none
  integer, intent(in) :: m
  real(wp), intent(inout) :: stress(m, 3), back(m, 3), eps_p(m)
  real(wp), intent(in) :: dstrain(m, 3), young, poisson, yield_stress, tangent, beta
  call j2_radial_update_points(m, stress, back, eps_p, dstrain, young, poisson, yield_stress, tangent, beta)
end subroutine j2_radial_points

! The piecewise-linear member's batch update (material/piecewise_linear_material.f90): m points
! over a step dt, its hardening curve (strain, curve_stress: n points) and rate law (0 none,
! 1 Cowper-Symonds rate_c, rate_p, 2 the rate curve rates, factors: nr points); state: each
! point's segment.
subroutine piecewise_update_points(m, stress, eps_p, state, dstrain, dt, young, poisson, n, strain, curve_stress, &
                                   law, rate_c, rate_p, nr, rates, factors)
  use paradyn_kinds, only: wp
  use piecewise_linear_material, only: piecewise_linear_material_t, piecewise_linear_from_curve
  implicit none
  integer, intent(in) :: m, n, law, nr
  real(wp), intent(inout) :: stress(m, 3), eps_p(m), state(m, 1)
  real(wp), intent(in) :: dstrain(m, 3), dt, young, poisson, strain(n), curve_stress(n), rate_c, rate_p
  real(wp), intent(in) :: rates(nr), factors(nr)
  type(piecewise_linear_material_t) :: material
  real(wp) :: back(m, 3)
  back = 0.0_wp
  material = piecewise_linear_from_curve(young, poisson, strain, curve_stress, law, rate_c, rate_p, rates, factors)
  call material%update_points(m, dt, stress, back, eps_p, state, dstrain)
end subroutine piecewise_update_points

! The piecewise-linear member's dissipated work per unit volume at plastic strains eps_p(m).
subroutine piecewise_dissipated_work(m, eps_p, n, strain, curve_stress, work)
  use paradyn_kinds, only: wp
  use piecewise_linear_material, only: piecewise_linear_material_t, piecewise_linear_from_curve
  implicit none
  integer, intent(in) :: m, n
  real(wp), intent(in) :: eps_p(m), strain(n), curve_stress(n)
  real(wp), intent(out) :: work(m)
  type(piecewise_linear_material_t) :: material
  real(wp) :: w(m, 1)
  material = piecewise_linear_from_curve(1.0_wp, 0.3_wp, strain, curve_stress, 0, 1.0_wp, 1.0_wp, [0.0_wp], [1.0_wp])
  call material%dissipated_work(reshape(eps_p, [m, 1]), w)
  work = w(:, 1)
end subroutine piecewise_dissipated_work
