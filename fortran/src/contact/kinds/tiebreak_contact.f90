!> Tiebreak contact (schema name "tiebreak"; LS-DYNA's *CONTACT_TIEBREAK_NODES_TO_SURFACE): tied
!> contact (tied_contact: the same ties, the same spring) whose ties fail by stress. A tie's stress
!> is its spring force over its slave node's tributary area at the start (a quarter of each of the
!> node's quadrilaterals in the slave part, a third of each triangle), split into the tension
!> sigma_n (the part of the force along the segment's normal that holds the slave on its side,
!> >= 0) and the shear sigma_s (the rest); the tie fails when
!>   (sigma_n / NFLS)^2 + (sigma_s / SFLS)^2 >= 1
!> (a strength of 0: no failure in that mode). A failed tie is penalty contact of its slave
!> against the segment it was tied to (contact_stages), as LS-DYNA's tiebreak becomes
!> nodes-to-surface contact after failure. The failed ties are kept by the contact (contact_t,
!> failed_ties: the same on every rank, in checkpoints; tie_failures gathers each step's).
!>
!> The law's data of a slave (bound_data): the tie's five numbers (tied_contact), then its area and
!> the definition's NFLS and SFLS.
module tiebreak_contact
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t
  use vector_algebra, only: cross
  use integer_sort, only: sorted_position
  use contact_pass, only: contact_pass_t
  use contact_surfaces, only: part_nodes
  use tied_contact, only: tied_t, tied_force, segment_frame
  implicit none
  private
  public :: tiebreak_t, tiebreak_width, tie_areas, tiebreak_data, tiebreak_force

  integer, parameter :: tiebreak_width = 8   !< the tie (5), the area, NFLS, SFLS

  type, extends(tied_t) :: tiebreak_t
  contains
    procedure :: make_passes => tiebreak_passes
  end type tiebreak_t

contains

  !> The tied pass, each slave with its area and the definition's failure stresses.
  subroutine tiebreak_passes(self, deck, definition, contact_id, n_contact, passes)
    class(tiebreak_t), intent(in) :: self
    type(deck_t), intent(in) :: deck
    integer, intent(in) :: definition, contact_id(:), n_contact
    type(contact_pass_t), intent(inout) :: passes(:)
    integer, allocatable :: slave_nodes(:), slave_elements(:)
    call self%tied_t%make_passes(deck, definition, contact_id, n_contact, passes)
    call part_nodes(deck, passes(1)%slave_part, slave_nodes, slave_elements)
    call tiebreak_data(passes(1), tie_areas(deck%coordinates, slave_nodes, deck%connectivity(:, slave_elements)))
  end subroutine tiebreak_passes

  !> The tributary area of each node x(:, slaves(s)) (slaves ascending) in the elements (4, n:
  !> columns of x, in ascending id order, so that the sum's order is the same on any layout): a
  !> quarter of each quadrilateral that holds it, a third of each triangle (node 3 repeated).
  pure function tie_areas(x, slaves, elements) result(area)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: slaves(:), elements(:, :)
    real(wp) :: area(size(slaves)), whole, share
    integer :: e, m, s, corners
    area = 0.0_wp
    if (size(slaves) == 0) return
    do e = 1, size(elements, 2)
      associate (n => elements(:, e))
      whole = 0.5_wp * norm2(cross(x(:, n(3)) - x(:, n(1)), x(:, n(4)) - x(:, n(2))))
      corners = merge(3, 4, n(4) == n(3))
      share = whole / real(corners, wp)
      do m = 1, corners
        s = sorted_position(slaves, n(m))
        if (s < 1 .or. s > size(slaves)) cycle
        if (slaves(s) == n(m)) area(s) = area(s) + share
      end do
      end associate
    end do
  end function tie_areas

  !> The pass's law data widened to tiebreak_width: each slave's area, and the failure stresses
  !> (NFLS, SFLS) of the definition (pass%strength).
  subroutine tiebreak_data(pass, area)
    type(contact_pass_t), intent(inout) :: pass
    real(wp), intent(in) :: area(:)
    real(wp), allocatable :: data(:, :)
    integer :: s
    allocate (data(tiebreak_width, size(pass%bound_element)), source=0.0_wp)
    data(1:5, :) = pass%bound_data(1:5, :)
    do s = 1, size(data, 2)
      data(6, s) = area(s)
      data(7:8, s) = pass%strength
    end do
    call move_alloc(data, pass%bound_data)
  end subroutine tiebreak_data

  !> The tie's spring (tied_force) and its failure value (sigma_n / NFLS)^2 + (sigma_s / SFLS)^2:
  !> the tie fails where it is >= 1. sigma_n is the tension: the force's part along the segment's
  !> normal that pulls the slave back towards the segment (both ways for a slave on the segment).
  pure subroutine tiebreak_force(p, xseg, data, k, f_slave, f_master, failure)
    real(wp), intent(in) :: p(3), xseg(3, 4), data(:), k
    real(wp), intent(out) :: f_slave(3), f_master(3, 4), failure
    real(wp) :: frame(3, 3), fn, tension, shear
    call tied_force(p, xseg, data(1:5), k, f_slave, f_master)
    frame = segment_frame(xseg, data(1), data(2))
    fn = dot_product(f_slave, frame(:, 3))
    if (data(5) /= 0.0_wp) then
      tension = max(-sign(1.0_wp, data(5)) * fn, 0.0_wp)
    else
      tension = abs(fn)
    end if
    shear = norm2(f_slave - fn * frame(:, 3))
    failure = 0.0_wp
    if (data(6) <= 0.0_wp) return
    if (data(7) > 0.0_wp) failure = failure + (tension / (data(6) * data(7)))**2
    if (data(8) > 0.0_wp) failure = failure + (shear / (data(6) * data(8)))**2
  end subroutine tiebreak_force

end module tiebreak_contact
