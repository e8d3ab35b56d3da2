!> The effect table of a run (issue 13; docs/formats.md, effects): for each effect of
!> schema/effects.toml whether the deck declares it and whether it runs (declared and not
!> switched off by the scene), and for the running ones the cycles they were active, the cycles
!> they were skipped (idle: nothing to do) and their wall seconds. Effects the deck does not
!> declare have no row: they are not allocated, not called and not timed.
module effect_table
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: n_effects, effect_names, effect_timed_with
  implicit none
  private
  public :: effect_table_t, effect_count, effect_time, effect_list

  type :: effect_table_t
    logical :: declared(n_effects) = .false.   !< the deck declares it
    logical :: running(n_effects) = .false.    !< declared, and the scene did not switch it off
    integer(i8) :: active(n_effects) = 0       !< cycles it did its work
    integer(i8) :: skipped(n_effects) = 0      !< cycles it had none and was not called
    real(wp) :: seconds(n_effects) = 0.0_wp    !< wall seconds (0 where timed with another effect)
  end type effect_table_t

contains

  !> One cycle of a running effect: active, or skipped.
  pure subroutine effect_count(t, id, active)
    type(effect_table_t), intent(inout) :: t
    integer, intent(in) :: id
    logical, intent(in) :: active
    if (active) then
      t%active(id) = t%active(id) + 1
    else
      t%skipped(id) = t%skipped(id) + 1
    end if
  end subroutine effect_count

  !> Wall seconds spent on an effect (an effect timed with another adds to that one).
  pure subroutine effect_time(t, id, seconds)
    type(effect_table_t), intent(inout) :: t
    integer, intent(in) :: id
    real(wp), intent(in) :: seconds
    integer :: owner
    owner = id
    if (effect_timed_with(id) > 0) owner = effect_timed_with(id)
    t%seconds(owner) = t%seconds(owner) + seconds
  end subroutine effect_time

  !> The names of the running effects (off = .false.) or of the declared ones the scene switched
  !> off (off = .true.), comma separated, in the order of the step.
  pure function effect_list(t, off) result(list)
    type(effect_table_t), intent(in) :: t
    logical, intent(in) :: off
    character(len=:), allocatable :: list
    integer :: k
    list = ''
    do k = 1, n_effects
      if (.not. t%declared(k) .or. (t%running(k) .eqv. off)) cycle
      if (len(list) > 0) list = list//','
      list = list//trim(effect_names(k))
    end do
  end function effect_list

end module effect_table
