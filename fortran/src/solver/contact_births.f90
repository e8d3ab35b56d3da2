!> A contact born later is checked at its birth, not at the start (docs/theory.md, "Birth and
!> death"), as LS-DYNA checks a contact with BT > 0 when it starts to act: the start checks skip
!> it, and before the forces of the first step at or after its birth time the same two checks run
!> on the positions then, with the same rules: parts whose mid-surfaces cross are refused (the run
!> stops with the check's message), slave nodes inside the contact thickness are reported (rank 0,
!> the start's warning naming the birth) and moved onto the surface where the definition says
!> "move" (a "gap" definition takes its overlaps at the birth in the contact itself:
!> contact_pass_birth). The checks read this rank's rows of the deck, kept for it from the set-up
!> (only while a definition is still to be born), with the coordinates of the birth. Collective.
module contact_births
  use iso_fortran_env, only: error_unit
  use paradyn_kinds, only: wp
  use paradyn_schema, only: status_ok, contact_kind_is_tied
  use model_deck, only: deck_t, node_row
  use contact_checks, only: check_contact_overlap, resolve_initial_penetrations
  use solver_state, only: solver_t
  implicit none
  private
  public :: contact_births_setup, contact_births_check, contact_births_restored

contains

  !> The definitions born after the start (tied ones excepted: they start within reach on purpose)
  !> and, if any, a copy of this rank's rows of the deck for their checks.
  subroutine contact_births_setup(s, deck)
    type(solver_t), intent(inout) :: s
    type(deck_t), intent(in) :: deck
    integer :: k
    s%birth_time = deck%contact_birth_time
    allocate (s%birth_pending(deck%n_contacts))
    do k = 1, deck%n_contacts
      s%birth_pending(k) = deck%contact_birth_time(k) > 0.0_wp .and. .not. contact_kind_is_tied(deck%contact_kind(k))
    end do
    if (any(s%birth_pending)) s%birth_deck = deck
  end subroutine contact_births_setup

  !> After a restore at the checkpoint's time: a definition born by then was checked before it.
  subroutine contact_births_restored(s)
    type(solver_t), intent(inout) :: s
    if (.not. allocated(s%birth_pending)) return
    s%birth_pending = s%birth_pending .and. s%birth_time > s%clock%time
    if (.not. any(s%birth_pending)) s%birth_deck = deck_t()
  end subroutine contact_births_restored

  !> Before the forces at s%clock%time: the checks of every definition born by now and not yet
  !> checked, at the current positions (moves added to them). status: left as it is, or the
  !> crossing's refusal (status_bad_input) with its message. Collective.
  subroutine contact_births_check(s, status, message)
    type(solver_t), intent(inout) :: s
    integer, intent(inout) :: status
    character(len=*), intent(inout) :: message
    real(wp), allocatable :: moves(:, :)
    integer :: k, j
    integer, allocatable :: rows(:)
    if (.not. allocated(s%birth_pending)) return
    if (.not. any(s%birth_pending .and. s%birth_time <= s%clock%time)) return
    rows = [(node_row(s%birth_deck, s%dom%nodes(j)), j = 1, s%dom%n_nodes)]
    do k = 1, size(s%birth_pending)
      if (.not. s%birth_pending(k) .or. s%birth_time(k) > s%clock%time) cycle
      s%birth_pending(k) = .false.
      s%birth_deck%coordinates(:, rows) = s%nodes%x
      call check_contact_overlap(s%birth_deck, s%halo%comm, status, message, only=k, born=s%clock%time)
      if (status /= status_ok) return
      call resolve_initial_penetrations(s%birth_deck, s%halo%comm, s%rank == 0, error_unit, moves, only=k, &
                                        born=s%clock%time)
      s%nodes%x = s%nodes%x + moves(:, rows)
    end do
    if (.not. any(s%birth_pending)) s%birth_deck = deck_t()
  end subroutine contact_births_check

end module contact_births
