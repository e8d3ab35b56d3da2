! f2py wrappers of the C0 triangle's kernels (shell_c0_triangle, shell_measures), for
! tests/test_kernels_triangle.py: the layout of blt_forces in kernels_f2py.f90 (element index
! first; a triangle is a quad whose fourth corner repeats its third).

subroutine triangle_forces(n, nip, x, v, w, thickness, density, young, poisson, yield_stress, tangent, &
                           beta, model, dt, stress, back, eps_p, hourglass, force, e_internal, e_hourglass, &
                           inverted, dt_element, failure_strain)
  use paradyn_kinds, only: wp
  use shell_section, only: shell_properties_t
  use shell_c0_triangle, only: c0_triangle_internal_forces
  use material_factory, only: material_from_deck
  use deck_fields, only: deck_fields_t
  implicit none
  integer, intent(in) :: n, nip, model
  real(wp), intent(in) :: failure_strain  ! 0: no point fails (element_erosion)
  !f2py double precision optional, intent(in) :: failure_strain = 0.0
  real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
  real(wp), intent(in) :: thickness, density, young, poisson, yield_stress, tangent, beta, dt
  real(wp), intent(inout) :: stress(n, 5, nip), back(n, 3, nip), eps_p(n, nip), hourglass(n, 10)
  real(wp), intent(out) :: force(n, 6, 4), dt_element(n)
  real(wp), intent(inout) :: e_internal(n), e_hourglass(n)
  integer, intent(out) :: inverted
  type(shell_properties_t) :: props
  real(wp) :: corner_force(6, 4, n)
  real(wp), allocatable :: state(:, :, :)
  props = shell_properties_t(thickness=thickness, density=density, young=young, poisson=poisson, integration_points=nip, &
                             failure_strain=failure_strain)
  call material_from_deck(deck_fields_t(material_model=[model], young=[young], poisson=[poisson], &
                                        yield_stress=[yield_stress], tangent_modulus=[tangent], &
                                        hardening_mixing=[beta]), 1, props%material)
  inverted = 0
  allocate (state(n, props%material%state_width(), nip), source=0.0_wp)
  call c0_triangle_internal_forces(n, x, v, w, props, dt, stress, back, eps_p, state, hourglass, corner_force, &
                                   e_internal, e_hourglass, inverted, dt_element)
  force = reshape(corner_force, [n, 6, 4], order=[2, 3, 1])
end subroutine triangle_forces

subroutine triangle_mass(n, x, thickness, density, node_mass, node_inertia)
  use paradyn_kinds, only: wp
  use shell_measures, only: triangle_lumped_mass
  use paradyn_schema, only: rotary_inertia_scaled
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x(n, 3, 4), thickness, density
  real(wp), intent(out) :: node_mass(n), node_inertia(n)
  call triangle_lumped_mass(n, x, thickness, density, rotary_inertia_scaled, node_mass, node_inertia)
end subroutine triangle_mass

subroutine triangle_time_step(n, x, thickness, density, young, poisson, dt_element)
  use paradyn_kinds, only: wp
  use shell_section, only: shell_properties_t
  use shell_measures, only: triangle_stable_time_step
  use material_factory, only: material_from_deck
  use deck_fields, only: deck_fields_t
  use paradyn_schema, only: material_elastic
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x(n, 3, 4), thickness, density, young, poisson
  real(wp), intent(out) :: dt_element(n)
  type(shell_properties_t) :: props
  props = shell_properties_t(thickness=thickness, density=density, young=young, poisson=poisson)
  call material_from_deck(deck_fields_t(material_model=[material_elastic], young=[young], poisson=[poisson]), 1, &
                          props%material)
  call triangle_stable_time_step(n, x, props, dt_element)
end subroutine triangle_time_step
