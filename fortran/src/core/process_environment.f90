!> The process environment: a default for a variable the user did not set, before the library
!> that reads it starts (C's setenv without overwrite; a setting of the user's own wins).
module process_environment
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
  implicit none
  private
  public :: default_environment

  interface
    function c_setenv(name, value, overwrite) bind(C, name='setenv') result(status)
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: name(*), value(*)
      integer(c_int), value :: overwrite
      integer(c_int) :: status
    end function c_setenv
  end interface

contains

  !> name=value unless name is already set.
  subroutine default_environment(name, value)
    character(len=*), intent(in) :: name, value
    integer(c_int) :: status
    status = c_setenv(name//c_null_char, value//c_null_char, 0_c_int)
  end subroutine default_environment

end module process_environment
