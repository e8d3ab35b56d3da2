!> The "gap" rule of a contact born later (docs/theory.md, "Birth and death"): at the start a
!> gap definition takes each slave's overlap as its gap (contact_pass); one born later takes them
!> at its birth, from the positions of the first step at or after it, by the same kernel
!> (initial_penetration) over the slaves and segments the pass holds (every one, or under local
!> contact a rank's own slaves and the segments near them, which are all that can reach them, in
!> the same ascending order, so the same overlaps on any layout). No MPI.
module contact_birth_gaps
  use paradyn_kinds, only: wp
  use initial_penetration, only: slave_penetrations
  use contact_interface, only: contact_t
  implicit none
  private
  public :: contact_birth_overlaps

contains

  !> Each pass that takes its gaps at a birth reached by c%time: its slaves' overlaps at the
  !> contact's current positions (c%x, gathered for the step).
  subroutine contact_birth_overlaps(c)
    type(contact_t), intent(inout) :: c
    real(wp), allocatable :: push(:, :)
    integer :: p
    do p = 1, size(c%passes)
      associate (pass => c%passes(p))
      if (.not. pass%gap_at_birth .or. c%time < pass%birth) cycle
      pass%gap_at_birth = .false.
      allocate (push(3, size(pass%slaves)))
      call slave_penetrations(c%x, pass%slave_at, pass%segment_at, pass%t_slave, pass%t_master, pass%overlap, push)
      deallocate (push)
      end associate
    end do
  end subroutine contact_birth_overlaps

end module contact_birth_gaps
