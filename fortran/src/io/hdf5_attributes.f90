!> Reading single HDF5 attributes and checking links, with messages that name the attribute and
!> the fix (docs/formats.md). A routine sets `message` only when something is wrong.
module hdf5_attributes
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_char, c_null_char, c_loc, c_f_pointer, &
                                          c_associated
  use hdf5
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: read_string_attribute, read_real_attribute, read_int_attribute, attribute_class, link_exists

contains

  !> One string attribute, fixed-length or variable-length (h5py's default for str).
  subroutine read_string_attribute(file, object, name, value, have, message)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: object, name
    character(len=:), allocatable, intent(out) :: value
    logical, intent(out) :: have
    character(len=*), intent(inout) :: message   !< set when the attribute is there but not one string
    integer(hid_t) :: attr, file_type, space
    integer(hsize_t) :: points
    integer(size_t) :: length
    integer :: k, err
    logical :: variable
    type(c_ptr), target :: pointers(1)
    type(c_ptr) :: buffer   ! HDF5's pointer interface takes a variable, not c_loc(...)
    character(kind=c_char), pointer :: text(:)
    character(len=:), allocatable, target :: fixed
    value = ''
    call h5aexists_by_name_f(file, object, name, have, err)
    if (.not. have) return
    call h5aopen_by_name_f(file, object, name, attr, err)
    call h5aget_space_f(attr, space, err)
    call h5sget_simple_extent_npoints_f(space, points, err)
    if (attribute_class(attr) /= H5T_STRING_F .or. points /= 1) then
      message = object//' attribute '//name//' must be one string; write it as a str attribute'
      call h5sclose_f(space, err)
      call h5aclose_f(attr, err)
      return
    end if
    ! read in the file's own string type: HDF5 does not convert between UTF-8 (h5py) and ASCII
    call h5aget_type_f(attr, file_type, err)
    call h5tis_variable_str_f(file_type, variable, err)
    if (variable) then
      pointers(1) = c_null_ptr
      buffer = c_loc(pointers)
      call h5aread_f(attr, file_type, buffer, err)
      if (err == 0 .and. c_associated(pointers(1))) then
        ! a C string of unknown length: find its terminating null within a generous bound
        call c_f_pointer(pointers(1), text, [4096])
        k = 0
        do while (k < size(text))
          if (text(k + 1) == c_null_char) exit
          k = k + 1
        end do
        value = repeat(' ', k)
        do k = 1, len(value)
          value(k:k) = text(k)
        end do
        call h5dvlen_reclaim_f(file_type, space, H5P_DEFAULT_F, buffer, err)
      end if
    else
      call h5tget_size_f(file_type, length, err)
      allocate (character(len=length) :: fixed)
      buffer = c_loc(fixed)
      call h5aread_f(attr, file_type, buffer, err)
      k = index(fixed, c_null_char)
      if (k > 0) fixed = fixed(1:k - 1)
      value = trim(fixed)
    end if
    if (err /= 0) message = 'attribute '//name//' of '//object//' could not be read as a string'
    call h5tclose_f(file_type, err)
    call h5sclose_f(space, err)
    call h5aclose_f(attr, err)
  end subroutine read_string_attribute

  !> One number (integer or floating point), `default` when absent.
  subroutine read_real_attribute(loc, object, name, value, default, required, fix, message)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: object, name, fix
    real(wp), intent(out) :: value
    real(wp), intent(in) :: default
    logical, intent(in) :: required
    character(len=*), intent(inout) :: message   !< set when required and missing, or not a number
    integer(hid_t) :: attr
    logical :: have
    integer :: err
    value = default
    call h5aexists_by_name_f(loc, object, name, have, err)
    if (.not. have) then
      if (required) message = object//' attribute '//name//' is missing; '//fix
      return
    end if
    call h5aopen_by_name_f(loc, object, name, attr, err)
    if (attribute_class(attr) /= H5T_FLOAT_F .and. attribute_class(attr) /= H5T_INTEGER_F) then
      message = object//' attribute '//name//' must be a number; write it as a float64 attribute'
    else
      call h5aread_f(attr, H5T_NATIVE_DOUBLE, value, [1_hsize_t], err)
    end if
    call h5aclose_f(attr, err)
  end subroutine read_real_attribute

  !> One integer of the root, `default` when absent.
  subroutine read_int_attribute(loc, object, name, value, default, required, message)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: object, name
    integer, intent(out) :: value
    integer, intent(in) :: default
    logical, intent(in) :: required
    character(len=*), intent(inout) :: message   !< set when required and missing, or not an integer
    integer(hid_t) :: attr
    logical :: have
    integer :: err
    value = default
    call h5aexists_by_name_f(loc, object, name, have, err)
    if (.not. have) then
      if (required) message = 'root attribute '//name//' is missing; this file is not a ParaDyn deck'
      return
    end if
    call h5aopen_by_name_f(loc, object, name, attr, err)
    if (attribute_class(attr) /= H5T_INTEGER_F) then
      message = 'root attribute '//name//' must be an integer; write it as an int32 attribute'
    else
      call h5aread_f(attr, H5T_NATIVE_INTEGER, value, [1_hsize_t], err)
    end if
    call h5aclose_f(attr, err)
  end subroutine read_int_attribute

  integer function attribute_class(attr) result(cls)
    integer(hid_t), intent(in) :: attr
    integer(hid_t) :: dtype
    integer :: err
    call h5aget_type_f(attr, dtype, err)
    call h5tget_class_f(dtype, cls, err)
    call h5tclose_f(dtype, err)
  end function attribute_class

  !> True if every group along the path and the final link exist.
  logical function link_exists(file, path)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    integer :: i, err
    link_exists = .true.
    do i = 2, len(path)
      if (path(i:i) == '/' .or. i == len(path)) then
        if (path(i:i) == '/') then
          call h5lexists_f(file, path(1:i - 1), link_exists, err)
        else
          call h5lexists_f(file, path, link_exists, err)
        end if
        if (.not. link_exists .or. err /= 0) then
          link_exists = .false.
          return
        end if
      end if
    end do
  end function link_exists

end module hdf5_attributes
