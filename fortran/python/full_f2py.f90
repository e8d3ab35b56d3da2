! f2py wrapper of the fully integrated shell's kernel (element/shell_full), as kernels_f2py.f90's
! blt_forces: properties as scalars, the state at 4 x nip points (in-plane point slowest).

subroutine full_forces(n, nip, x, v, w, thickness, density, young, poisson, yield_stress, tangent, beta, &
                       model, dt, stress, back, eps_p, drilling, force, e_internal, inverted, dt_element, &
                       warping_correction, failure_strain)
  use paradyn_kinds, only: wp
  use shell_section, only: shell_properties_t
  use shell_full, only: full_internal_forces
  use material_factory, only: material_from_deck
  use deck_fields, only: deck_fields_t
  implicit none
  integer, intent(in) :: n, nip, model
  integer, intent(in) :: warping_correction  ! 1 on, 0 off
  !f2py integer optional, intent(in) :: warping_correction = 1
  real(wp), intent(in) :: failure_strain  ! 0: no point fails (element_erosion)
  !f2py double precision optional, intent(in) :: failure_strain = 0.0
  real(wp), intent(in) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
  real(wp), intent(in) :: thickness, density, young, poisson, yield_stress, tangent, beta, dt
  real(wp), intent(inout) :: stress(n, 5, 4 * nip), back(n, 3, 4 * nip), eps_p(n, 4 * nip)
  real(wp), intent(inout) :: drilling(n, 4)   ! the drilling moments (the hourglass array's slots 6:9)
  real(wp), intent(out) :: force(n, 6, 4)
  real(wp), intent(inout) :: e_internal(n)
  integer, intent(out) :: inverted
  real(wp), intent(out) :: dt_element(n)
  type(shell_properties_t) :: props
  type(deck_fields_t) :: material   ! a deck of this one material
  real(wp) :: corner_force(6, 4, n)
  real(wp), allocatable :: state(:, :, :)
  real(wp) :: hourglass(n, 10)
  props = shell_properties_t(thickness=thickness, density=density, young=young, poisson=poisson, &
                             integration_points=nip, warping_correction=warping_correction /= 0, &
                             fully_integrated=.true., failure_strain=failure_strain)
  material = deck_fields_t(material_model=[model], young=[young], poisson=[poisson], yield_stress=[yield_stress], &
                           tangent_modulus=[tangent], hardening_mixing=[beta])
  call material_from_deck(material, 1, props%material)
  inverted = 0
  hourglass = 0.0_wp
  hourglass(:, 6:9) = drilling
  allocate (state(n, props%material%state_width(), 4 * nip), source=0.0_wp)
  call full_internal_forces(n, x, v, w, props, dt, stress, back(:, :, 1:props%material%back_stress_points(4 * nip)), &
                            eps_p, state, hourglass, corner_force, e_internal, inverted, dt_element)
  drilling = hourglass(:, 6:9)
  force = reshape(corner_force, [n, 6, 4], order=[2, 3, 1])   ! (component, corner, element) -> (i, c, k)
end subroutine full_forces
