!> The names of a run in its results file, so post-processing needs results.h5 alone: the deck's
!> title (root attribute `title`), part names (`/parts` attribute `names`, copied as `/mesh`
!> attribute `part_names`) and tracked node names (`/output` attribute `tracked_names`, copied to
!> `/history`), copied as they are (h5py writes variable-length UTF-8 strings), and the effects the
!> run switched on (`/run` attribute `effects`, one string). Every rank passes the same
!> values, as attribute writes to a parallel HDF5 file are collective.
module run_names
  use, intrinsic :: iso_c_binding, only: c_int8_t, c_char, c_null_char, c_loc, c_ptr
  use hdf5
  implicit none
  private
  public :: copy_run_names, write_string_attribute

contains

  !> Copies the title, part names and tracked names of the deck at deck_path into the open results
  !> file.
  !> A deck without them (they are optional) gives a results file without them.
  subroutine copy_run_names(deck_path, results_file)
    character(len=*), intent(in) :: deck_path
    integer(hid_t), intent(in) :: results_file
    integer(hid_t) :: deck, group
    integer :: err
    call h5fopen_f(deck_path, H5F_ACC_RDONLY_F, deck, err)
    if (err /= 0) return
    call copy_attribute(deck, '/', 'title', results_file, '/', 'title')
    call h5gopen_f(results_file, 'mesh', group, err)
    if (err == 0) then
      call copy_attribute(deck, '/parts', 'names', group, '.', 'part_names')
      call h5gclose_f(group, err)
    end if
    call h5gopen_f(results_file, 'history', group, err)
    if (err == 0) then
      call copy_attribute(deck, '/output', 'tracked_names', group, '.', 'tracked_names')
      call h5gclose_f(group, err)
    end if
    call h5fclose_f(deck, err)
  end subroutine copy_run_names

  !> One attribute, in its own type and shape, byte for byte (variable-length strings through
  !> their pointers, which HDF5 then reclaims).
  subroutine copy_attribute(from, from_object, name, to, to_object, new_name)
    integer(hid_t), intent(in) :: from, to
    character(len=*), intent(in) :: from_object, name, to_object, new_name
    integer(hid_t) :: source, target, file_type, space
    integer(hsize_t) :: points
    integer(size_t) :: size
    integer(c_int8_t), allocatable, target :: buffer(:)
    type(c_ptr) :: address   ! HDF5's pointer interface takes a variable, not c_loc(...)
    logical :: exists, variable
    integer :: err, class
    exists = .true.
    if (from_object /= '/') call h5lexists_f(from, from_object, exists, err)   ! the group is optional
    if (.not. exists) return
    call h5aexists_by_name_f(from, from_object, name, exists, err)
    if (err /= 0 .or. .not. exists) return
    call h5aopen_by_name_f(from, from_object, name, source, err)
    call h5aget_type_f(source, file_type, err)
    call h5aget_space_f(source, space, err)
    call h5tget_class_f(file_type, class, err)
    call h5sget_simple_extent_npoints_f(space, points, err)
    call h5tget_size_f(file_type, size, err)
    if (class == H5T_STRING_F) then
      allocate (buffer(max(1_hsize_t, points) * size))
      address = c_loc(buffer)
      call h5aread_f(source, file_type, address, err)
      if (err == 0) then
        call h5acreate_by_name_f(to, to_object, new_name, file_type, space, target, err)
        if (err == 0) then
          call h5awrite_f(target, file_type, address, err)
          call h5aclose_f(target, err)
        end if
        call h5tis_variable_str_f(file_type, variable, err)
        if (variable) call h5dvlen_reclaim_f(file_type, space, H5P_DEFAULT_F, address, err)
      end if
    end if
    call h5sclose_f(space, err)
    call h5tclose_f(file_type, err)
    call h5aclose_f(source, err)
  end subroutine copy_attribute

  !> A scalar string attribute, variable-length UTF-8 as h5py writes a str (h5py reads it back
  !> as a str).
  subroutine write_string_attribute(location, name, value)
    integer(hid_t), intent(in) :: location
    character(len=*), intent(in) :: name, value
    character(len=len(value) + 1, kind=c_char), target :: text
    type(c_ptr), target :: pointers(1)
    integer(hid_t) :: string_type, space, attribute
    type(c_ptr) :: address
    integer :: err
    text = value//c_null_char
    pointers(1) = c_loc(text)
    address = c_loc(pointers)
    call h5tcopy_f(H5T_STRING, string_type, err)   ! the Fortran API's variable-length C string
    call h5tset_cset_f(string_type, H5T_CSET_UTF8_F, err)
    call h5screate_f(H5S_SCALAR_F, space, err)
    call h5acreate_f(location, name, string_type, space, attribute, err)
    call h5awrite_f(attribute, string_type, address, err)
    call h5aclose_f(attribute, err)
    call h5sclose_f(space, err)
    call h5tclose_f(string_type, err)
  end subroutine write_string_attribute

end module run_names
