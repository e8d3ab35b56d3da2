!> Reads a deck (docs/formats.md, version 1) from HDF5 and checks it as strictly as the frontend:
!> a loop over the schema's datasets (presence, type class, shape, then the value rules of
!> deck_rules) and /control attributes, then the relations of model_deck.
module deck_reader
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_char, c_null_char, c_loc, c_f_pointer, &
                                          c_associated
  use hdf5
  use paradyn_kinds, only: wp
  use paradyn_schema, only: deck_version, deck_version_attribute, deck_datasets, control_attributes, &
                            deck_conditions, deck_enums, n_deck_datasets, n_control_attributes, n_sizes, &
                            size_entity, size_symbol, size_min_rows, class_int, class_float, class_string, &
                            condition_none, &
                            status_ok, status_bad_input
  use deck_rules, only: check_field_values, check_attribute_value, selected_rows, integer_text
  use model_deck, only: deck_t, store_deck_field, store_control_value, check_deck_relations
  implicit none
  private
  public :: read_deck

  !> One dataset as the file holds it: (max(columns, 1), rows), indices 0-based.
  type :: field_t
    real(wp), allocatable :: values(:, :)
  end type field_t

contains

  !> status_ok on success, status_bad_input with a message for a bad deck.
  subroutine read_deck(path, d, status, message)
    character(len=*), intent(in) :: path
    type(deck_t), intent(out) :: d
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    type(field_t) :: fields(n_deck_datasets)
    integer :: sizes(n_sizes)
    integer(hid_t) :: file
    integer :: err, version, id
    logical :: exists

    status = status_bad_input
    message = ''
    inquire (file=path, exist=exists)
    if (.not. exists) then
      message = trim(path)//': no such file; give the path of a deck written by paradyn-run or h5py'
      return
    end if
    call h5fopen_f(path, H5F_ACC_RDONLY_F, file, err)
    if (err /= 0) then
      message = trim(path)//': not an HDF5 file'
      return
    end if
    call read_int_attribute(file, '/', deck_version_attribute, version, -1, .true.)
    if (status_ok_so_far() .and. version /= deck_version) then
      message = 'root attribute '//deck_version_attribute//' = '//integer_text(version)// &
                ' is not supported; this engine reads version '//integer_text(deck_version)
    end if
    sizes = -1   ! a row count is known once the first dataset of its symbol is read
    do id = 1, n_deck_datasets
      if (.not. status_ok_so_far()) exit
      call read_field(id)
    end do
    if (status_ok_so_far()) call read_control()
    call h5fclose_f(file, err)
    if (.not. status_ok_so_far()) return

    ! every field has its class and shape: now its values, then the relations between fields
    do id = 1, n_deck_datasets
      call check_field_values(id, fields(id)%values, sizes, rows_to_check(id), message)
      if (.not. status_ok_so_far()) return
      call store_deck_field(d, id, fields(id)%values)
    end do
    call check_deck_relations(d, status, message)

  contains

    !> The rows of dataset `id` its rules apply to (those of the J2 materials for the J2 data).
    function rows_to_check(id) result(selected)
      integer, intent(in) :: id
      logical, allocatable :: selected(:)
      integer :: condition_dataset
      condition_dataset = id   ! no condition: selected_rows selects every row and ignores the values
      if (deck_datasets(id)%checked_when /= condition_none) &
        condition_dataset = deck_conditions(deck_datasets(id)%checked_when)%dataset
      selected = selected_rows(id, size(fields(id)%values, 2), fields(condition_dataset)%values)
    end function rows_to_check

    logical function status_ok_so_far()
      status_ok_so_far = len_trim(message) == 0
    end function status_ok_so_far

    !> Whether condition `condition` holds for the datasets read so far.
    logical function condition_holds(condition)
      integer, intent(in) :: condition
      condition_holds = .false.
      if (condition == condition_none) return
      associate (c => deck_conditions(condition))
        if (c%dataset == 0) then
          condition_holds = link_exists(file, trim(c%group))
        else
          condition_holds = any(fields(c%dataset)%values(1, :) == real(c%code, wp))
        end if
      end associate
    end function condition_holds

    !> Why an absent dataset is required, for the message.
    function required_because(condition) result(words)
      integer, intent(in) :: condition
      character(len=:), allocatable :: words
      words = ''
      if (condition == condition_none) return
      associate (c => deck_conditions(condition))
        if (c%dataset == 0) then
          words = ' (required since the group '//trim(c%group)//' exists)'
        else
          words = ' (required since '//trim(deck_datasets(c%dataset)%path)//'['// &
                  integer_text(findloc(fields(c%dataset)%values(1, :), real(c%code, wp), dim=1) - 1)//'] = '// &
                  integer_text(c%code)//')'
        end if
      end associate
    end function required_because

    !> Reads dataset `id` after checking presence, class and shape; an absent optional one gets its default.
    subroutine read_field(id)
      integer, intent(in) :: id
      integer(hid_t) :: dset
      integer(hsize_t) :: dims(2)
      logical :: found
      integer :: columns
      associate (spec => deck_datasets(id), rows => sizes(deck_datasets(id)%row_symbol))
        columns = max(spec%columns, 1)
        call open_checked(id, dset, dims, found)
        if (.not. status_ok_so_far()) return
        if (.not. found) then
          if (spec%required .or. condition_holds(spec%required_when)) then
            message = 'dataset '//trim(spec%path)//' is missing'//required_because(spec%required_when)// &
                      '; see docs/formats.md for what it holds'
            return
          end if
          rows = max(rows, 0)
          allocate (fields(id)%values(columns, rows), source=spec%default)
          return
        end if
        if (spec%defines_rows) then
          rows = int(dims(1))
          if (rows < size_min_rows(spec%row_symbol)) then
            message = 'dataset '//trim(spec%path)//' has no rows; a deck needs at least one '// &
                      trim(size_entity(spec%row_symbol))
            call h5dclose_f(dset, err)
            return
          end if
        end if
        allocate (fields(id)%values(columns, dims(1)))
        call h5dread_f(dset, H5T_NATIVE_DOUBLE, fields(id)%values, [int(columns, hsize_t), dims(1)], err)
        call h5dclose_f(dset, err)
      end associate
    end subroutine read_field

    !> Opens dataset `id` after checking that it has the spec's class and shape. dims(1): rows.
    subroutine open_checked(id, dset, dims, found)
      integer, intent(in) :: id
      integer(hid_t), intent(out) :: dset
      integer(hsize_t), intent(out) :: dims(2)
      logical, intent(out) :: found
      integer(hid_t) :: space, dtype
      integer(hsize_t) :: maxdims(2)
      integer :: ndims, cls, want_rank, rows
      character(len=:), allocatable :: name
      name = trim(deck_datasets(id)%path)
      rows = sizes(deck_datasets(id)%row_symbol)
      dims = 0
      found = link_exists(file, name)
      if (.not. found) return
      call h5dopen_f(file, name, dset, err)
      call h5dget_type_f(dset, dtype, err)
      call h5tget_class_f(dtype, cls, err)
      call h5tclose_f(dtype, err)
      if (deck_datasets(id)%class == class_float .and. cls /= H5T_FLOAT_F) then
        message = 'dataset '//name//' must hold floating-point numbers; write it as float64'
      else if (deck_datasets(id)%class == class_int .and. cls /= H5T_INTEGER_F) then
        message = 'dataset '//name//' must hold integers; write it with an integer dtype such as int32'
      end if
      call h5dget_space_f(dset, space, err)
      call h5sget_simple_extent_ndims_f(space, ndims, err)
      want_rank = merge(2, 1, deck_datasets(id)%columns > 0)
      if (status_ok_so_far() .and. ndims /= want_rank) then
        message = 'dataset '//name//' has '//integer_text(ndims)//' dimensions; expected '//shape_words(id)
      else if (status_ok_so_far()) then
        call h5sget_simple_extent_dims_f(space, dims(1:ndims), maxdims(1:ndims), err)
        ! the Fortran API reports dimensions fastest first: put rows (h5py's first axis) first
        if (ndims == 2) dims = [dims(2), dims(1)]
        if (deck_datasets(id)%columns > 0 .and. dims(min(2, ndims)) /= deck_datasets(id)%columns) then
          message = 'dataset '//name//' has shape ('//integer_text(int(dims(1)))//', '// &
                    integer_text(int(dims(2)))//'); expected '//shape_words(id)
        else if (rows >= 0 .and. dims(1) /= rows) then
          message = 'dataset '//name//' has '//integer_text(int(dims(1)))//' rows; expected '// &
                    integer_text(rows)//': '//shape_words(id)
        end if
      end if
      call h5sclose_f(space, err)
      if (.not. status_ok_so_far()) call h5dclose_f(dset, err)
    end subroutine open_checked

    !> `shape (n_nodes, 3), one row per node`
    function shape_words(id) result(words)
      integer, intent(in) :: id
      character(len=:), allocatable :: words
      associate (spec => deck_datasets(id))
        if (spec%columns > 0) then
          words = 'shape ('//trim(size_symbol(spec%row_symbol))//', '//integer_text(spec%columns)//')'
        else
          words = 'shape ('//trim(size_symbol(spec%row_symbol))//',)'
        end if
        words = words//', one row per '//trim(size_entity(spec%row_symbol))
      end associate
    end function shape_words

    !> Every /control attribute: presence, class, then its rules; absent ones get their defaults.
    subroutine read_control()
      real(wp) :: values(n_control_attributes)
      character(len=:), allocatable :: name
      logical :: have
      integer :: id
      if (.not. link_exists(file, '/control')) then
        message = 'group /control is missing; it carries the attributes end_time and output_interval'
        return
      end if
      do id = 1, n_control_attributes
        associate (spec => control_attributes(id))
          values(id) = spec%default
          if (spec%default_from > 0) values(id) = values(spec%default_from) / spec%default_divisor
          if (spec%class == class_string) then
            call read_string_attribute('/control', trim(spec%name), name, have)
            if (status_ok_so_far() .and. have) then
              values(id) = real(enum_code(spec%enum, name), wp)
              if (values(id) < 0.0_wp) message = '/control attribute '//trim(spec%name)//' = "'//name// &
                '" is unknown: it '//trim(spec%enum_rule)//'; '//trim(spec%fix)
            end if
          else
            call read_real_attribute(file, '/control', trim(spec%name), values(id), values(id), spec%required, &
                                     trim(spec%fix))
            if (status_ok_so_far()) call check_attribute_value(id, values(id), message)
          end if
          if (.not. status_ok_so_far()) return
          call store_control_value(d, id, values(id))
        end associate
      end do
    end subroutine read_control

    !> Code of an enum member's name, -1 if none has it.
    integer function enum_code(enum, name) result(code)
      integer, intent(in) :: enum
      character(len=*), intent(in) :: name
      integer :: k
      code = -1
      do k = 1, deck_enums(enum)%n_members
        if (name == trim(deck_enums(enum)%names(k))) code = deck_enums(enum)%codes(k)
      end do
    end function enum_code

    !> One string attribute, fixed-length or variable-length (h5py's default for str).
    subroutine read_string_attribute(object, name, value, have)
      character(len=*), intent(in) :: object, name
      character(len=:), allocatable, intent(out) :: value
      logical, intent(out) :: have
      integer(hid_t) :: attr, file_type, space
      integer(hsize_t) :: points
      integer(size_t) :: length
      integer :: k
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

    subroutine read_real_attribute(loc, object, name, value, default, required, fix)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: object, name, fix
      real(wp), intent(out) :: value
      real(wp), intent(in) :: default
      logical, intent(in) :: required
      integer(hid_t) :: attr
      logical :: have
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

    subroutine read_int_attribute(loc, object, name, value, default, required)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: object, name
      integer, intent(out) :: value
      integer, intent(in) :: default
      logical, intent(in) :: required
      integer(hid_t) :: attr
      logical :: have
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

  end subroutine read_deck

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

end module deck_reader
