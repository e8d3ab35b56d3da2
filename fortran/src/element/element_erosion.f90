!> Element erosion (docs/theory.md, "Element erosion"): a shell of a part whose material has a
!> failure strain is eroded once the effective plastic strain at one of its through-thickness
!> points reaches it (LS-DYNA's rule for shells with NUMFIP = 1, its default). From then on it
!> gives no forces and no time step; its mass stays on its nodes and its internal energy stays
!> what it was. The plastic strain never decreases and an eroded element's stays frozen, so the
!> plastic strains are the whole erosion state: a checkpoint restores it with them.
!>
!> The kernels run before and after the element kernel on a group of a part with a failure
!> strain; other parts call nothing. Before, an eroded element gets a unit square (or triangle)
!> at rest as its positions and velocities, so the kernel meets no inside-out element and adds no
!> increment to its zero stress and energy; after, every eroded element, the newly failed
!> included, has its corner forces, stresses, back stresses and hourglass resultants zeroed, its
!> step made huge and its energies put back where they were before the kernel: an element that
!> fails in a step keeps the energies of the step's start, whose forces were the last it gave
!> (so the energy balance goes on as before the erosion). Pure, no module state.
module element_erosion
  use paradyn_kinds, only: wp, ek
  implicit none
  private
  public :: element_eroded, erosion_before, erosion_after, eroded_count

contains

  !> Whether an element with the plastic strains eps_p at its points has failed (failure_strain
  !> > 0; 0: the material never fails).
  pure logical function element_eroded(eps_p, failure_strain) result(eroded)
    real(ek), intent(in) :: eps_p(:)
    real(wp), intent(in) :: failure_strain
    eroded = failure_strain > 0.0_wp .and. any(real(eps_p, wp) >= failure_strain)
  end function element_eroded

  !> Before the kernel: each eroded element of the group (n elements, eps_p(n, points)) gets a
  !> unit square at rest (a triangle: its third corner twice) in x, v, w; the group's energies
  !> are kept in e_kept (internal, hourglass) for erosion_after.
  pure subroutine erosion_before(n, eps_p, failure_strain, triangle, x, v, w, e_internal, e_hourglass, e_kept)
    integer, intent(in) :: n
    real(ek), intent(in) :: eps_p(:, :)
    real(wp), intent(in) :: failure_strain
    logical, intent(in) :: triangle
    real(wp), intent(inout) :: x(n, 3, 4), v(n, 3, 4), w(n, 3, 4)
    real(wp), intent(in) :: e_internal(n), e_hourglass(n)
    real(wp), intent(out) :: e_kept(2, n)
    real(wp), parameter :: square(3, 4) = reshape([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0], [3, 4])
    real(wp), parameter :: corner3(3, 4) = reshape([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0], [3, 4])
    integer :: i
    e_kept(1, :) = e_internal
    e_kept(2, :) = e_hourglass
    do i = 1, n
      if (.not. element_eroded(eps_p(i, :), failure_strain)) cycle
      if (triangle) then
        x(i, :, :) = corner3
      else
        x(i, :, :) = square
      end if
      v(i, :, :) = 0.0_wp
      w(i, :, :) = 0.0_wp
    end do
  end subroutine erosion_before

  !> After the kernel: each eroded element of the group, the newly failed included, gives no force
  !> and no step and keeps no stress, back stress or hourglass resultant, and its energies are
  !> those before the kernel (e_kept).
  pure subroutine erosion_after(n, eps_p, failure_strain, e_kept, stress, back, hourglass, force, &
                                e_internal, e_hourglass, dt_element)
    integer, intent(in) :: n
    real(ek), intent(in) :: eps_p(:, :)
    real(wp), intent(in) :: failure_strain, e_kept(2, n)
    real(ek), intent(inout) :: stress(:, :, :), back(:, :, :), hourglass(:, :)
    real(wp), intent(inout) :: force(6, 4, n), e_internal(n), e_hourglass(n), dt_element(n)
    integer :: i
    do i = 1, n
      if (.not. element_eroded(eps_p(i, :), failure_strain)) cycle
      e_internal(i) = e_kept(1, i)
      e_hourglass(i) = e_kept(2, i)
      stress(i, :, :) = 0.0_ek
      if (size(back, 3) > 0) back(i, :, :) = 0.0_ek
      hourglass(i, :) = 0.0_ek
      force(:, :, i) = 0.0_wp
      dt_element(i) = huge(1.0_wp)
    end do
  end subroutine erosion_after

  !> How many of the n elements with plastic strains eps_p(n, points) are eroded.
  pure integer function eroded_count(n, eps_p, failure_strain) result(count)
    integer, intent(in) :: n
    real(ek), intent(in) :: eps_p(:, :)
    real(wp), intent(in) :: failure_strain
    integer :: i
    count = 0
    if (failure_strain <= 0.0_wp) return
    do i = 1, n
      if (element_eroded(eps_p(i, :), failure_strain)) count = count + 1
    end do
  end function eroded_count

end module element_erosion
