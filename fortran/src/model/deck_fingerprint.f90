!> Fingerprints of a deck, one per HDF5 group (/nodes, /elements, ..., /control), so that a
!> checkpoint knows the deck it belongs to and a restart with another deck is refused naming the
!> group that differs (issue 17). 32-bit FNV-1a over the bytes of the values as read, in schema
!> order; the /control attributes a restart may change (schema [deck] restart_may_change) are
!> left out. No MPI, no I/O.
module deck_fingerprint
  use paradyn_kinds, only: wp, i8
  implicit none
  private
  public :: fingerprint_start, fingerprint_add, group_of

  integer(i8), parameter :: fnv_offset = 2166136261_i8, fnv_prime = 16777619_i8, low32 = 4294967295_i8

contains

  pure integer(i8) function fingerprint_start() result(hash)
    hash = fnv_offset
  end function fingerprint_start

  !> Adds the bytes of values to hash (32 bits kept in 64, so the product never overflows).
  pure subroutine fingerprint_add(hash, values)
    integer(i8), intent(inout) :: hash
    real(wp), intent(in) :: values(:)
    integer(i8) :: word
    integer :: k, b
    do k = 1, size(values)
      word = transfer(values(k), word)
      do b = 0, 7
        hash = iand(ieor(hash, iand(shiftr(word, 8 * b), 255_i8)) * fnv_prime, low32)
      end do
    end do
  end subroutine fingerprint_add

  !> The group of a dataset path: "/nodes/coordinates" -> "nodes".
  pure function group_of(path) result(group)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: group
    integer :: slash
    slash = index(path(2:), '/')
    if (slash == 0) then
      group = trim(path(2:))
    else
      group = path(2:slash)
    end if
  end function group_of

end module deck_fingerprint
