!> The keys of the failed ties of tiebreak contacts (tiebreak_contact): a tie is its definition and
!> its slave's contact-node id (both the same on every rank and in every run of the deck), its key
!> definition * 2^31 + node; a list of keys is kept ascending, so that it is the same on any layout.
module tie_keys
  use paradyn_kinds, only: i8
  implicit none
  private
  public :: tie_key, tie_failed, merge_keys

contains

  !> The key of the tie of definition's slave node (a contact-node id).
  elemental integer(i8) function tie_key(definition, node) result(key)
    integer, intent(in) :: definition, node
    key = int(definition, i8) * 2_i8**31 + int(node, i8)
  end function tie_key

  !> Whether keys (ascending) holds the tie of definition's slave node.
  pure logical function tie_failed(keys, definition, node) result(found)
    integer(i8), intent(in) :: keys(:)
    integer, intent(in) :: definition, node
    integer(i8) :: key
    integer :: lo, hi, mid
    found = .false.
    key = tie_key(definition, node)
    lo = 1
    hi = size(keys)
    do while (lo <= hi)
      mid = (lo + hi) / 2
      if (keys(mid) == key) then
        found = .true.
        return
      else if (keys(mid) < key) then
        lo = mid + 1
      else
        hi = mid - 1
      end if
    end do
  end function tie_failed

  !> The ascending union of keys (ascending, distinct) and more (any order, repeats allowed).
  pure function merge_keys(keys, more) result(merged)
    integer(i8), intent(in) :: keys(:), more(:)
    integer(i8), allocatable :: merged(:)
    integer(i8) :: next
    integer :: i, n
    merged = keys
    do i = 1, size(more)
      if (tie_failed_key(merged, more(i))) cycle
      n = count(merged < more(i))
      next = more(i)
      merged = [merged(1:n), next, merged(n + 1:)]
    end do
  end function merge_keys

  pure logical function tie_failed_key(keys, key) result(found)
    integer(i8), intent(in) :: keys(:), key
    found = any(keys == key)
  end function tie_failed_key

end module tie_keys
