!> The force laws of the contact kinds that bind each slave to a master segment at the start
!> (schema trait tied), by kind: how far a slave is bound, the binding of a list of slaves, and
!> the force of a bound slave. The penalty law (contact_penalty) is every other kind's, called by
!> the local search itself. A kind with a law of its own puts its kernels in its module, its code
!> here in each select, and the trait tied on its enum member (so the start-up checks skip it).
module contact_laws
  use paradyn_kinds, only: wp
  use paradyn_schema, only: contact_kind_tied, contact_kind_tiebreak
  use contact_pass, only: contact_pass_t
  use tied_contact, only: tie_slaves, tie_reach, tied_force
  use tiebreak_contact, only: tiebreak_data, tiebreak_force
  implicit none
  private
  public :: binding_reach, bind_slaves, bound_force

contains

  !> How far from a master segment a slave of the bound pass is bound.
  real(wp) function binding_reach(pass) result(reach)
    type(contact_pass_t), intent(in) :: pass
    reach = 0.0_wp
    select case (pass%kind)
    case (contact_kind_tied, contact_kind_tiebreak)
      reach = tie_reach(pass)
    end select
  end function binding_reach

  !> The bindings of the slaves at x(:, slaves) to the elements (4, n: columns of x; global ids
  !> ids, ascending) within reach: pass%bound_element and pass%bound_data, one column per slave.
  !> area: each slave's tributary area (tiebreak_contact's tie_areas), for the kinds that fail by stress.
  subroutine bind_slaves(pass, x, slaves, elements, ids, area)
    type(contact_pass_t), intent(inout) :: pass
    real(wp), intent(in) :: x(:, :), area(:)
    integer, intent(in) :: slaves(:), elements(:, :), ids(:)
    select case (pass%kind)
    case (contact_kind_tied)
      call tie_slaves(x, slaves, elements, ids, tie_reach(pass), pass%bound_element, pass%bound_data)
    case (contact_kind_tiebreak)
      call tie_slaves(x, slaves, elements, ids, tie_reach(pass), pass%bound_element, pass%bound_data)
      call tiebreak_data(pass, area)
    end select
  end subroutine bind_slaves

  !> The force of a bound slave at p on its segment xseg (3, 4) with the law's data of it and the
  !> spring stiffness k: f_slave on the slave, f_master(:, i) on the segment's node i; failure: the
  !> binding's failure value (it fails where >= 1; 0 for a kind that does not fail).
  pure subroutine bound_force(kind, p, xseg, data, k, f_slave, f_master, failure)
    integer, intent(in) :: kind
    real(wp), intent(in) :: p(3), xseg(3, 4), data(:), k
    real(wp), intent(out) :: f_slave(3), f_master(3, 4), failure
    f_slave = 0.0_wp
    f_master = 0.0_wp
    failure = 0.0_wp
    select case (kind)
    case (contact_kind_tied)
      call tied_force(p, xseg, data, k, f_slave, f_master)
    case (contact_kind_tiebreak)
      call tiebreak_force(p, xseg, data, k, f_slave, f_master, failure)
    end select
  end subroutine bound_force

end module contact_laws
