!> Element erosion (docs/theory.md, "Element erosion"): a point of a part whose material has a
!> failure strain fails when its effective plastic strain reaches it, and carries no stress from
!> then on (zero_failed_points, called by every element kernel between the material update and
!> the resultants). A layer (one through-thickness point; for the fully integrated element the
!> layer's 4 in-plane points) fails with its first failed point, and the element is eroded once
!> failed_layers_needed of its layers have failed (LS-DYNA's NUMFIP for shells: a number, or a
!> percentage of the layers; 1 by default). From then on it gives no forces and no time step;
!> its mass stays on its nodes and its internal energy stays what it was. The plastic strain
!> never decreases and an eroded element's stays frozen, so the plastic strains are the whole
!> failure and erosion state: a checkpoint restores it with them.
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
  public :: point_failed, zero_failed_points, failed_layers_needed

contains

  !> Whether a point with the plastic strain eps_p has failed (failure_strain > 0; 0: the
  !> material never fails).
  elemental logical function point_failed(eps_p, failure_strain) result(failed)
    real(ek), intent(in) :: eps_p
    real(wp), intent(in) :: failure_strain
    failed = failure_strain > 0.0_wp .and. real(eps_p, wp) >= failure_strain
  end function point_failed

  !> After the material update of one layer of m elements: the stresses sp(1:m, :) of the points
  !> whose plastic strain eps_p(1:m) reached failure_strain are zero (a failed point carries no
  !> stress, and so adds no increment either). Elements with no failed point are untouched.
  pure subroutine zero_failed_points(m, failure_strain, eps_p, sp)
    integer, intent(in) :: m
    real(wp), intent(in) :: failure_strain
    real(ek), intent(in) :: eps_p(:)
    real(ek), intent(inout) :: sp(:, :)
    integer :: i, c
    do c = 1, size(sp, 2)
      do i = 1, m
        sp(i, c) = merge(0.0_ek, sp(i, c), point_failed(eps_p(i), failure_strain))
      end do
    end do
  end subroutine zero_failed_points

  !> The number of failed layers that erodes an element of `layers` through-thickness points from
  !> LS-DYNA's NUMFIP (numfip): > 0 that many, -100 <= numfip < 0 that percentage of the layers
  !> (rounded up), < -100 |numfip| - 100 of them; 0 reads as the default 1. Never more than the
  !> layers (an element whose every layer failed is eroded), never less than 1.
  pure integer function failed_layers_needed(numfip, layers) result(needed)
    real(wp), intent(in) :: numfip
    integer, intent(in) :: layers
    real(wp), parameter :: slack = 1.0e-9_wp   ! 60 % of 5 layers is 3, not 3 + rounding
    if (numfip < -100.0_wp) then
      needed = ceiling(-numfip - 100.0_wp - slack)
    else if (numfip < 0.0_wp) then
      needed = ceiling(-numfip * layers / 100.0_wp - slack)
    else
      needed = ceiling(numfip - slack)
    end if
    needed = max(1, min(needed, layers))
  end function failed_layers_needed

  !> Whether an element with the plastic strains eps_p at its points has been eroded: at least
  !> `needed` of its `layers` layers have a failed point (the points in-plane point slowest, as
  !> the element state stores them: point p is in layer mod(p - 1, layers) + 1).
  pure logical function element_eroded(eps_p, failure_strain, layers, needed) result(eroded)
    real(ek), intent(in) :: eps_p(:)
    real(wp), intent(in) :: failure_strain
    integer, intent(in) :: layers, needed
    integer :: k, failed
    eroded = .false.
    if (.not. (failure_strain > 0.0_wp)) return
    if (needed <= 1) then   ! any failed point (NUMFIP 1)
      eroded = any(point_failed(eps_p, failure_strain))
      return
    end if
    failed = 0
    do k = 1, layers
      if (any(point_failed(eps_p(k::layers), failure_strain))) failed = failed + 1
    end do
    eroded = failed >= needed
  end function element_eroded

  !> Before the kernel: each eroded element of the group (n elements, eps_p(n, points); layers and
  !> needed as element_eroded's) gets a
  !> unit square at rest (a triangle: its third corner twice) in x, v, w; the group's energies
  !> are kept in e_kept (internal, hourglass) for erosion_after.
  pure subroutine erosion_before(n, eps_p, failure_strain, layers, needed, triangle, x, v, w, e_internal, &
                                 e_hourglass, e_kept)
    integer, intent(in) :: n, layers, needed
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
      if (.not. element_eroded(eps_p(i, :), failure_strain, layers, needed)) cycle
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
  pure subroutine erosion_after(n, eps_p, failure_strain, layers, needed, e_kept, stress, back, hourglass, force, &
                                e_internal, e_hourglass, dt_element)
    integer, intent(in) :: n, layers, needed
    real(ek), intent(in) :: eps_p(:, :)
    real(wp), intent(in) :: failure_strain, e_kept(2, n)
    real(ek), intent(inout) :: stress(:, :, :), back(:, :, :), hourglass(:, :)
    real(wp), intent(inout) :: force(6, 4, n), e_internal(n), e_hourglass(n), dt_element(n)
    integer :: i
    do i = 1, n
      if (.not. element_eroded(eps_p(i, :), failure_strain, layers, needed)) cycle
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
  pure integer function eroded_count(n, eps_p, failure_strain, layers, needed) result(count)
    integer, intent(in) :: n, layers, needed
    real(ek), intent(in) :: eps_p(:, :)
    real(wp), intent(in) :: failure_strain
    integer :: i
    count = 0
    if (failure_strain <= 0.0_wp) return
    do i = 1, n
      if (element_eroded(eps_p(i, :), failure_strain, layers, needed)) count = count + 1
    end do
  end function eroded_count

end module element_erosion
