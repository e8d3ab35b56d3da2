! f2py wrappers of element_erosion's counting rules (failed points and NUMFIP), for
! tests/test_numfip.py.

subroutine erosion_layers_needed(numfip, layers, needed)
  ! element_erosion.failed_layers_needed: the failed layers that erode an element (LS-DYNA NUMFIP)
  use paradyn_kinds, only: wp
  use element_erosion, only: failed_layers_needed
  implicit none
  real(wp), intent(in) :: numfip
  integer, intent(in) :: layers
  integer, intent(out) :: needed
  needed = failed_layers_needed(numfip, layers)
end subroutine erosion_layers_needed

subroutine erosion_element_eroded(points, eps_p, failure_strain, layers, needed, eroded)
  ! element_erosion.element_eroded of one element's plastic strains (points in-plane point slowest)
  use paradyn_kinds, only: wp, ek
  use element_erosion, only: element_eroded
  implicit none
  integer, intent(in) :: points, layers, needed
  real(wp), intent(in) :: eps_p(points), failure_strain
  integer, intent(out) :: eroded
  eroded = merge(1, 0, element_eroded(real(eps_p, ek), failure_strain, layers, needed))
end subroutine erosion_element_eroded
