! f2py wrappers of the frame fields' kernels (shell_field_measures), for tests/test_frame_fields.py:
! element index first, as blt_forces in kernels_f2py.f90.

subroutine shell_layer_stresses(n, nip, stress, layers)
  use paradyn_kinds, only: wp, ek
  use shell_field_measures, only: layer_stresses
  implicit none
  integer, intent(in) :: n, nip
  real(wp), intent(in) :: stress(n, 5, nip)
  real(wp), intent(out) :: layers(5, 3, n)
  call layer_stresses(n, nip, real(stress, ek), layers)
end subroutine shell_layer_stresses

subroutine shell_membrane_strain(n, x0, x, strain)
  use paradyn_kinds, only: wp
  use shell_field_measures, only: membrane_green_strain
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x0(n, 3, 4), x(n, 3, 4)
  real(wp), intent(out) :: strain(3, n)
  call membrane_green_strain(n, x0, x, strain)
end subroutine shell_membrane_strain

subroutine shell_initial_volumes(n, x0, thickness, volume)
  use paradyn_kinds, only: wp
  use shell_field_measures, only: initial_volumes
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x0(n, 3, 4), thickness
  real(wp), intent(out) :: volume(n)
  call initial_volumes(n, x0, thickness, volume)
end subroutine shell_initial_volumes

subroutine shell_surface_strains(n, x0, x, q, thickness, membrane, surface)
  use paradyn_kinds, only: wp
  use shell_field_measures, only: surface_strains
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x0(n, 3, 4), x(n, 3, 4), q(n, 4, 4), thickness, membrane(3, n)
  real(wp), intent(out) :: surface(3, 2, n)
  call surface_strains(n, x0, x, q, thickness, membrane, surface)
end subroutine shell_surface_strains

subroutine shell_current_thicknesses(n, x0, x, thickness, young, poisson, mid_trace, current)
  use paradyn_kinds, only: wp
  use shell_field_measures, only: current_thicknesses
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: x0(n, 3, 4), x(n, 3, 4), thickness, young, poisson, mid_trace(n)
  real(wp), intent(out) :: current(n)
  call current_thicknesses(n, x0, x, thickness, young, poisson, mid_trace, current)
end subroutine shell_current_thicknesses

subroutine node_update_orientations(n, dt, w, q)
  use paradyn_kinds, only: wp
  use time_integration, only: update_orientations
  implicit none
  integer, intent(in) :: n
  real(wp), intent(in) :: dt, w(3, n)
  real(wp), intent(inout) :: q(4, n)
  call update_orientations(n, dt, w, q)
end subroutine node_update_orientations
