!> Reads a deck (docs/formats.md, version 1) from HDF5 and checks it as strictly as the frontend:
!> presence, type class and shape of every dataset here, values in model_deck.
module deck_reader
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_char, c_null_char, c_loc, c_f_pointer, &
                                          c_associated
  use hdf5
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t, check_deck_values, partition_code
  implicit none
  private
  public :: read_deck

  integer, parameter :: supported_version = 1

contains

  !> status 0 on success, 2 with a message for a bad deck.
  subroutine read_deck(path, d, status, message)
    character(len=*), intent(in) :: path
    type(deck_t), intent(out) :: d
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer(hid_t) :: file
    integer :: err, version
    logical :: exists, plastic

    status = 2
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
    call read_int_attribute(file, '/', 'paradyn_deck_version', version, -1, .true.)
    if (status_ok() .and. version /= supported_version) then
      write (message, '(a,i0,a,i0)') 'root attribute paradyn_deck_version = ', version, &
        ' is not supported; this engine reads version ', supported_version
    end if
    if (status_ok()) call read_real2('/nodes/coordinates', 3, -1, d%coordinates, .true.)
    if (status_ok()) d%n_nodes = size(d%coordinates, 2)
    if (status_ok()) call read_int2('/elements/connectivity', 4, -1, d%connectivity, .true.)
    if (status_ok()) d%n_elements = size(d%connectivity, 2)
    if (status_ok()) call read_int1('/elements/part', d%n_elements, d%element_part, .true., 0)
    if (status_ok()) call read_real1('/parts/thickness', -1, d%thickness, .true., 0.0_wp)
    if (status_ok()) d%n_parts = size(d%thickness)
    if (status_ok()) call read_int1('/parts/material', d%n_parts, d%part_material, .true., 0)
    if (status_ok()) call read_int1('/parts/integration_points', d%n_parts, d%integration_points, .false., 5)
    if (status_ok()) call read_int1('/parts/hourglass_form', d%n_parts, d%hourglass_form, .false., 2)
    if (status_ok()) call read_real1('/parts/hourglass_coefficient', d%n_parts, d%hourglass_coefficient, &
                                     .false., 0.1_wp)
    if (status_ok()) call read_int1('/materials/model', -1, d%material_model, .true., 0)
    if (status_ok()) d%n_materials = size(d%material_model)
    if (status_ok()) call read_real1('/materials/density', d%n_materials, d%density, .true., 0.0_wp)
    if (status_ok()) call read_real1('/materials/youngs_modulus', d%n_materials, d%young, .true., 0.0_wp)
    if (status_ok()) call read_real1('/materials/poisson_ratio', d%n_materials, d%poisson, .true., 0.0_wp)
    plastic = .false.
    if (status_ok()) plastic = any(d%material_model == 2)
    if (status_ok()) call read_real1('/materials/yield_stress', d%n_materials, d%yield_stress, plastic, 0.0_wp)
    if (status_ok()) call read_real1('/materials/tangent_modulus', d%n_materials, d%tangent_modulus, &
                                     plastic, 0.0_wp)
    if (status_ok()) call read_real1('/materials/hardening_mixing', d%n_materials, d%hardening_mixing, &
                                     plastic, 1.0_wp)
    if (status_ok()) call read_real2('/nodes/initial_velocity', 3, d%n_nodes, d%velocity, .false.)
    if (status_ok()) call read_real2('/nodes/initial_angular_velocity', 3, d%n_nodes, d%angular_velocity, .false.)
    if (status_ok()) call read_int2('/nodes/fixed_dofs', 6, d%n_nodes, d%fixed, .false.)
    if (status_ok()) call read_loads()
    if (status_ok()) call read_contacts()
    if (status_ok()) call read_int1('/output/tracked_nodes', -1, d%tracked_nodes, .false., 0)
    if (status_ok()) d%n_tracked = size(d%tracked_nodes)
    if (status_ok()) call read_control()
    call h5fclose_f(file, err)
    if (.not. status_ok()) return

    ! the file holds 0-based indices; the engine counts from 1
    d%connectivity = d%connectivity + 1
    d%element_part = d%element_part + 1
    d%part_material = d%part_material + 1
    d%load_node = d%load_node + 1
    d%tracked_nodes = d%tracked_nodes + 1
    d%contact_pairs = d%contact_pairs + 1
    call check_deck_values(d, status, message)

  contains

    logical function status_ok()
      status_ok = len_trim(message) == 0
    end function status_ok

    subroutine read_loads()
      logical :: have
      have = link_exists(file, '/loads')
      call read_int1('/loads/node', -1, d%load_node, have, 0)
      if (status_ok()) d%n_loads = size(d%load_node)
      if (status_ok()) call read_int1('/loads/dof', d%n_loads, d%load_dof, have, 1)
      if (status_ok()) call read_real1('/loads/value', d%n_loads, d%load_value, have, 0.0_wp)
      if (status_ok()) call read_real1('/loads/ramp_time', d%n_loads, d%load_ramp_time, have, 0.0_wp)
    end subroutine read_loads

    subroutine read_contacts()
      logical :: have
      have = link_exists(file, '/contact')
      call read_int2('/contact/pairs', 2, -1, d%contact_pairs, have)
      if (status_ok()) d%n_contacts = size(d%contact_pairs, 2)
      if (status_ok()) call read_real1('/contact/penalty_scale', d%n_contacts, d%contact_penalty_scale, &
                                       .false., 0.1_wp)
      if (status_ok()) call read_real1('/contact/static_friction', d%n_contacts, d%contact_static_friction, &
                                       .false., 0.0_wp)
      if (status_ok()) call read_real1('/contact/dynamic_friction', d%n_contacts, &
                                       d%contact_dynamic_friction, .false., 0.0_wp)
      if (status_ok()) call read_real1('/contact/friction_decay', d%n_contacts, d%contact_friction_decay, &
                                       .false., 0.0_wp)
      if (status_ok()) call read_int1('/contact/passes', d%n_contacts, d%contact_passes, .false., 2)
    end subroutine read_contacts

    subroutine read_control()
      real(wp) :: interval
      character(len=:), allocatable :: name
      logical :: have
      if (.not. link_exists(file, '/control')) then
        message = 'group /control is missing; it carries the attributes end_time and output_interval'
        return
      end if
      call read_real_attribute(file, '/control', 'end_time', d%end_time, 0.0_wp, .true.)
      if (status_ok()) call read_real_attribute(file, '/control', 'output_interval', d%output_interval, &
                                                0.0_wp, .true.)
      if (status_ok()) call read_real_attribute(file, '/control', 'history_interval', d%history_interval, &
                                                d%output_interval / 10.0_wp, .false.)
      if (status_ok()) call read_real_attribute(file, '/control', 'time_step', d%time_step, 0.0_wp, .false.)
      if (status_ok()) call read_real_attribute(file, '/control', 'time_step_safety', d%time_step_safety, &
                                                0.9_wp, .false.)
      if (status_ok()) call read_real_attribute(file, '/control', 'mass_damping', d%mass_damping, 0.0_wp, .false.)
      if (status_ok()) call read_real_attribute(file, '/control', 'progress_interval', d%progress_interval, &
                                                0.5_wp, .false.)
      if (status_ok()) call read_real_attribute(file, '/control', 'contact_sort_interval', interval, &
                                                0.0_wp, .false.)
      if (status_ok()) d%contact_sort_interval = nint(interval)
      if (status_ok()) call read_real_attribute(file, '/control', 'checkpoint_interval', d%checkpoint_interval, &
                                                0.0_wp, .false.)
      if (status_ok()) call read_string_attribute('/control', 'partition', name, have)
      if (status_ok() .and. have) then
        d%partition_name = name
        d%partition = partition_code(name)
      end if
    end subroutine read_control

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
        message = 'attribute '//name//' of '//object//' must be one string'
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

    !> Opens a dataset after checking that it exists and has the expected class and shape.
    !> ncomp > 0: h5py shape (nrows, ncomp); ncomp = 0: shape (nrows,). nrows < 0: any length.
    subroutine open_checked(name, want_class, ncomp, nrows, dset, dims, found, required)
      character(len=*), intent(in) :: name
      integer, intent(in) :: want_class, ncomp, nrows
      integer(hid_t), intent(out) :: dset
      integer(hsize_t), intent(out) :: dims(2)
      logical, intent(out) :: found
      logical, intent(in) :: required
      integer(hid_t) :: space, dtype
      integer(hsize_t) :: maxdims(2)
      integer :: ndims, cls, want_rank
      found = link_exists(file, name)
      if (.not. found) then
        if (required) message = 'dataset '//name//' is missing; see docs/formats.md for what it holds'
        return
      end if
      call h5dopen_f(file, name, dset, err)
      call h5dget_type_f(dset, dtype, err)
      call h5tget_class_f(dtype, cls, err)
      call h5tclose_f(dtype, err)
      if (cls /= want_class) then
        if (want_class == H5T_FLOAT_F) then
          message = 'dataset '//name//' must hold floating-point numbers'
        else
          message = 'dataset '//name//' must hold integers'
        end if
      end if
      call h5dget_space_f(dset, space, err)
      call h5sget_simple_extent_ndims_f(space, ndims, err)
      want_rank = merge(2, 1, ncomp > 0)
      dims = 0
      if (status_ok() .and. ndims /= want_rank) then
        write (message, '(a,i0,a)') 'dataset '//name//' must have ', want_rank, ' dimensions'
      else if (status_ok()) then
        call h5sget_simple_extent_dims_f(space, dims(1:ndims), maxdims(1:ndims), err)
        ! the Fortran API reports dimensions fastest first: put rows (h5py's first axis) first
        if (ndims == 2) dims = [dims(2), dims(1)]
        if (ncomp > 0 .and. dims(min(2, ndims)) /= ncomp) then
          write (message, '(a,i0,a,i0,a)') 'dataset '//name//' has shape (', dims(1), ', ', dims(2), &
            '); expected (n, '//trim(itoa(ncomp))//')'
        else if (nrows >= 0 .and. dims(1) /= nrows) then
          write (message, '(a,i0,a,i0,a)') 'dataset '//name//' has ', dims(1), ' rows; expected ', nrows, &
            ' (one per entity)'
        end if
      end if
      call h5sclose_f(space, err)
      if (.not. status_ok()) call h5dclose_f(dset, err)
    end subroutine open_checked

    !> Reads a checked dataset into a real buffer (max(ncomp, 1), rows); HDF5 converts integer
    !> files exactly (|i| < 2**53). A missing optional dataset gives `default` everywhere.
    subroutine read_array(name, want_class, ncomp, nrows, buffer, required, default)
      character(len=*), intent(in) :: name
      integer, intent(in) :: want_class, ncomp, nrows
      real(wp), allocatable, intent(out) :: buffer(:, :)
      logical, intent(in) :: required
      real(wp), intent(in) :: default
      integer(hid_t) :: dset
      integer(hsize_t) :: dims(2)
      logical :: found
      call open_checked(name, want_class, ncomp, nrows, dset, dims, found, required)
      if (.not. status_ok()) return
      if (.not. found) then
        allocate (buffer(max(ncomp, 1), max(nrows, 0)), source=default)
        return
      end if
      allocate (buffer(max(ncomp, 1), dims(1)))
      call h5dread_f(dset, H5T_NATIVE_DOUBLE, buffer, [int(max(ncomp, 1), hsize_t), dims(1)], err)
      call h5dclose_f(dset, err)
    end subroutine read_array

    subroutine read_real2(name, ncomp, nrows, a, required)
      character(len=*), intent(in) :: name
      integer, intent(in) :: ncomp, nrows
      real(wp), allocatable, intent(out) :: a(:, :)
      logical, intent(in) :: required
      call read_array(name, H5T_FLOAT_F, ncomp, nrows, a, required, 0.0_wp)
    end subroutine read_real2

    subroutine read_int2(name, ncomp, nrows, a, required)
      character(len=*), intent(in) :: name
      integer, intent(in) :: ncomp, nrows
      integer, allocatable, intent(out) :: a(:, :)
      logical, intent(in) :: required
      real(wp), allocatable :: buffer(:, :)
      call read_array(name, H5T_INTEGER_F, ncomp, nrows, buffer, required, 0.0_wp)
      if (allocated(buffer)) a = nint(buffer)
    end subroutine read_int2

    subroutine read_real1(name, nrows, a, required, default)
      character(len=*), intent(in) :: name
      integer, intent(in) :: nrows
      real(wp), allocatable, intent(out) :: a(:)
      logical, intent(in) :: required
      real(wp), intent(in) :: default
      real(wp), allocatable :: buffer(:, :)
      call read_array(name, H5T_FLOAT_F, 0, nrows, buffer, required, default)
      if (allocated(buffer)) a = buffer(1, :)
    end subroutine read_real1

    subroutine read_int1(name, nrows, a, required, default)
      character(len=*), intent(in) :: name
      integer, intent(in) :: nrows
      integer, allocatable, intent(out) :: a(:)
      logical, intent(in) :: required
      integer, intent(in) :: default
      real(wp), allocatable :: buffer(:, :)
      call read_array(name, H5T_INTEGER_F, 0, nrows, buffer, required, real(default, wp))
      if (allocated(buffer)) a = nint(buffer(1, :))
    end subroutine read_int1

    subroutine read_real_attribute(loc, object, name, value, default, required)
      integer(hid_t), intent(in) :: loc
      character(len=*), intent(in) :: object, name
      real(wp), intent(out) :: value
      real(wp), intent(in) :: default
      logical, intent(in) :: required
      integer(hid_t) :: attr
      logical :: have
      value = default
      call h5aexists_by_name_f(loc, object, name, have, err)
      if (.not. have) then
        if (required) message = 'attribute '//name//' of '//object//' is missing; see docs/formats.md'
        return
      end if
      call h5aopen_by_name_f(loc, object, name, attr, err)
      if (attribute_class(attr) /= H5T_FLOAT_F .and. attribute_class(attr) /= H5T_INTEGER_F) then
        message = 'attribute '//name//' of '//object//' must be a number'
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
        message = 'attribute '//name//' of '//object//' must be an integer'
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

  pure function itoa(i) result(s)
    integer, intent(in) :: i
    character(len=12) :: s
    write (s, '(i0)') i
  end function itoa

end module deck_reader
