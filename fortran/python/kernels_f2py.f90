! Thin explicit-shape wrappers that expose the engine's pure kernels to Python through f2py
! (module paradyn._kernels). f2py cannot pass derived types, so properties come as scalars.

subroutine j2_update(stress, back, eps_p, dstrain, young, poisson, yield_stress, tangent, beta)
  use paradyn_kinds, only: wp
  use material_j2, only: j2_plane_stress_update
  implicit none
  real(wp), intent(inout) :: stress(3), back(3), eps_p
  real(wp), intent(in) :: dstrain(3), young, poisson, yield_stress, tangent, beta
  call j2_plane_stress_update(stress, back, eps_p, dstrain, young, poisson, yield_stress, tangent, beta)
end subroutine j2_update

subroutine thickness_points(n, zeta, weight)
  use paradyn_kinds, only: wp
  use shell_blt, only: thickness_rule
  implicit none
  integer, intent(in) :: n
  real(wp), intent(out) :: zeta(n), weight(n)
  call thickness_rule(n, zeta, weight)
end subroutine thickness_points

subroutine blt_forces(n, nip, x, v, w, thickness, density, young, poisson, yield_stress, tangent, &
                      beta, hourglass_coefficient, model, dt, stress, back, eps_p, hourglass, force, &
                      e_internal, e_hourglass, inverted, hourglass_form)
  use paradyn_kinds, only: wp
  use shell_blt, only: shell_properties_t, blt_internal_forces
  implicit none
  integer, intent(in) :: n, nip, model
  integer, intent(in) :: hourglass_form  ! 1 viscous, 2 stiffness
  !f2py integer optional, intent(in) :: hourglass_form = 2
  real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
  real(wp), intent(in) :: thickness, density, young, poisson, yield_stress, tangent, beta
  real(wp), intent(in) :: hourglass_coefficient, dt
  real(wp), intent(inout) :: stress(n, 5, nip), back(n, 3, nip), eps_p(n, nip), hourglass(n, 9)
  real(wp), intent(out) :: force(n, 6, 4)
  real(wp), intent(inout) :: e_internal(n), e_hourglass(n)
  integer, intent(out) :: inverted
  type(shell_properties_t) :: props
  props = shell_properties_t(thickness, density, young, poisson, yield_stress, tangent, beta, &
                             hourglass_coefficient, model, nip, hourglass_form)
  inverted = 0
  call blt_internal_forces(n, x, v, w, props, dt, stress, back, eps_p, hourglass, force, &
                           e_internal, e_hourglass, inverted)
end subroutine blt_forces

subroutine blt_mass(n, x, thickness, density, node_mass, node_inertia)
  use paradyn_kinds, only: wp
  use shell_blt, only: blt_lumped_mass
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x(n, 3, 4), thickness, density
  real(wp), intent(out) :: node_mass(n), node_inertia(n)
  call blt_lumped_mass(n, x, thickness, density, node_mass, node_inertia)
end subroutine blt_mass

subroutine blt_time_step(n, x, thickness, density, young, poisson, dt_element)
  use paradyn_kinds, only: wp
  use shell_blt, only: shell_properties_t, blt_stable_time_step
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x(n, 3, 4), thickness, density, young, poisson
  real(wp), intent(out) :: dt_element(n)
  type(shell_properties_t) :: props
  props%thickness = thickness
  props%density = density
  props%young = young
  props%poisson = poisson
  call blt_stable_time_step(n, x, props, dt_element)
end subroutine blt_time_step

subroutine block_partition(n_elements, n_ranks, owner)
  use domain_decomposition, only: block_owner
  implicit none
  integer, intent(in) :: n_elements, n_ranks
  integer, intent(out) :: owner(n_elements)
  integer :: e
  do e = 1, n_elements
    owner(e) = block_owner(e, n_elements, n_ranks)
  end do
end subroutine block_partition
