!> Writes results.h5 (docs/formats.md, version 1) from the rank that holds the gathered fields.
!> Datasets grow by one frame or record at a time and the file is flushed after each, so a run
!> that stops early leaves a readable file whose root attribute `complete` stays 0.
module results_writer
  use hdf5
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: results_file_t, results_create, results_write_frame, results_write_history
  public :: results_finish, run_record_t

  type :: results_file_t
    integer(hid_t) :: file = -1
    integer :: n_nodes = 0, n_elements = 0, n_tracked = 0
    integer :: frames = 0, records = 0
  end type results_file_t

  !> What the engine reports about a run (the /run attributes).
  type :: run_record_t
    integer :: cycles = 0, ranks = 1, threads = 1, elements = 0, nodes = 0
    real(wp) :: dt_s = 0, dt_stable_s = 0, wall_s = 0, element_cycles_per_s = 0
    real(wp) :: phase_elements_s = 0, phase_contact_s = 0, phase_communication_s = 0
    real(wp) :: phase_output_s = 0, phase_other_s = 0
    real(wp) :: phase_contact_sort_s = 0, phase_contact_search_s = 0, phase_contact_force_s = 0
  end type run_record_t

  integer, parameter :: history_names_count = 6
  character(len=*), parameter :: history_names(history_names_count) = [character(len=20) :: &
    'kinetic_energy', 'internal_energy', 'hourglass_energy', 'contact_energy', 'external_work', &
    'contact_penetration']

contains

  subroutine results_create(path, coordinates, connectivity, element_part, n_tracked, rf, status, message)
    character(len=*), intent(in) :: path
    real(wp), intent(in) :: coordinates(:, :)
    integer, intent(in) :: connectivity(:, :), element_part(:), n_tracked
    type(results_file_t), intent(out) :: rf
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer :: err, k
    integer(hid_t) :: group
    rf%n_nodes = size(coordinates, 2)
    rf%n_elements = size(connectivity, 2)
    rf%n_tracked = n_tracked
    call h5fcreate_f(path, H5F_ACC_TRUNC_F, rf%file, err)
    if (err /= 0) then
      status = 1
      message = 'cannot create '//trim(path)//'; check that the folder exists and is writable'
      return
    end if
    call write_int_attribute(rf%file, 'paradyn_results_version', 1)
    call write_int_attribute(rf%file, 'complete', 0)
    call h5gcreate_f(rf%file, 'mesh', group, err)
    call write_real_dataset(group, 'coordinates', coordinates)
    call write_int_dataset(group, 'connectivity', connectivity - 1)
    call write_int_dataset(group, 'part', reshape(element_part - 1, [1, size(element_part)]), rank1=.true.)
    call h5gclose_f(group, err)
    call h5gcreate_f(rf%file, 'frames', group, err)
    call create_growing(group, 'time', [integer(hsize_t) ::])
    call create_growing(group, 'displacement', [3_hsize_t, int(rf%n_nodes, hsize_t)])
    call create_growing(group, 'velocity', [3_hsize_t, int(rf%n_nodes, hsize_t)])
    call create_growing(group, 'element_membrane_stress', [3_hsize_t, int(rf%n_elements, hsize_t)])
    call create_growing(group, 'element_von_mises', [int(rf%n_elements, hsize_t)])
    call create_growing(group, 'element_plastic_strain', [int(rf%n_elements, hsize_t)])
    call h5gclose_f(group, err)
    call h5gcreate_f(rf%file, 'history', group, err)
    call create_growing(group, 'time', [integer(hsize_t) ::])
    do k = 1, history_names_count
      call create_growing(group, trim(history_names(k)), [integer(hsize_t) ::])
    end do
    call create_growing(group, 'tracked_displacement', [3_hsize_t, int(max(n_tracked, 0), hsize_t)])
    call create_growing(group, 'tracked_velocity', [3_hsize_t, int(max(n_tracked, 0), hsize_t)])
    call h5gclose_f(group, err)
    call h5fflush_f(rf%file, H5F_SCOPE_GLOBAL_F, err)
    status = 0
    message = ''
  end subroutine results_create

  subroutine results_write_frame(rf, time, displacement, velocity, membrane, von_mises, plastic_strain)
    type(results_file_t), intent(inout) :: rf
    real(wp), intent(in) :: time, displacement(:, :), velocity(:, :), membrane(:, :)
    real(wp), intent(in) :: von_mises(:), plastic_strain(:)
    integer :: err
    rf%frames = rf%frames + 1
    call append(rf%file, '/frames/time', [time], [integer(hsize_t) ::], rf%frames)
    call append(rf%file, '/frames/displacement', reshape(displacement, [size(displacement)]), &
                [3_hsize_t, int(rf%n_nodes, hsize_t)], rf%frames)
    call append(rf%file, '/frames/velocity', reshape(velocity, [size(velocity)]), &
                [3_hsize_t, int(rf%n_nodes, hsize_t)], rf%frames)
    call append(rf%file, '/frames/element_membrane_stress', reshape(membrane, [size(membrane)]), &
                [3_hsize_t, int(rf%n_elements, hsize_t)], rf%frames)
    call append(rf%file, '/frames/element_von_mises', von_mises, [int(rf%n_elements, hsize_t)], rf%frames)
    call append(rf%file, '/frames/element_plastic_strain', plastic_strain, &
                [int(rf%n_elements, hsize_t)], rf%frames)
    call h5fflush_f(rf%file, H5F_SCOPE_GLOBAL_F, err)
  end subroutine results_write_frame

  !> values: kinetic, internal, hourglass and contact energy, external work, deepest contact
  !> penetration.
  subroutine results_write_history(rf, time, energies, tracked_displacement, tracked_velocity)
    type(results_file_t), intent(inout) :: rf
    real(wp), intent(in) :: time, energies(history_names_count)  ! energies and penetration
    real(wp), intent(in) :: tracked_displacement(:, :), tracked_velocity(:, :)
    integer :: k
    rf%records = rf%records + 1
    call append(rf%file, '/history/time', [time], [integer(hsize_t) ::], rf%records)
    do k = 1, history_names_count
      call append(rf%file, '/history/'//trim(history_names(k)), [energies(k)], [integer(hsize_t) ::], rf%records)
    end do
    call append(rf%file, '/history/tracked_displacement', reshape(tracked_displacement, &
                [size(tracked_displacement)]), [3_hsize_t, int(rf%n_tracked, hsize_t)], rf%records)
    call append(rf%file, '/history/tracked_velocity', reshape(tracked_velocity, &
                [size(tracked_velocity)]), [3_hsize_t, int(rf%n_tracked, hsize_t)], rf%records)
  end subroutine results_write_history

  !> Writes the /run attributes, marks the file complete when asked, and closes it.
  subroutine results_finish(rf, run, complete)
    type(results_file_t), intent(inout) :: rf
    type(run_record_t), intent(in) :: run
    logical, intent(in) :: complete
    integer(hid_t) :: group
    integer :: err
    call h5gcreate_f(rf%file, 'run', group, err)
    call write_int_attribute(group, 'cycles', run%cycles)
    call write_int_attribute(group, 'ranks', run%ranks)
    call write_int_attribute(group, 'threads', run%threads)
    call write_int_attribute(group, 'elements', run%elements)
    call write_int_attribute(group, 'nodes', run%nodes)
    call write_real_attribute(group, 'dt_s', run%dt_s)
    call write_real_attribute(group, 'dt_stable_s', run%dt_stable_s)
    call write_real_attribute(group, 'wall_s', run%wall_s)
    call write_real_attribute(group, 'element_cycles_per_s', run%element_cycles_per_s)
    call write_real_attribute(group, 'phase_elements_s', run%phase_elements_s)
    call write_real_attribute(group, 'phase_contact_s', run%phase_contact_s)
    call write_real_attribute(group, 'phase_communication_s', run%phase_communication_s)
    call write_real_attribute(group, 'phase_output_s', run%phase_output_s)
    call write_real_attribute(group, 'phase_other_s', run%phase_other_s)
    call write_real_attribute(group, 'phase_contact_sort_s', run%phase_contact_sort_s)
    call write_real_attribute(group, 'phase_contact_search_s', run%phase_contact_search_s)
    call write_real_attribute(group, 'phase_contact_force_s', run%phase_contact_force_s)
    call h5gclose_f(group, err)
    if (complete) call overwrite_int_attribute(rf%file, 'complete', 1)
    call h5fclose_f(rf%file, err)
    rf%file = -1
  end subroutine results_finish

  ! ---------------------------------------------------------------- HDF5 plumbing

  !> A chunked dataset whose last (slowest, h5py's first) dimension grows: Fortran shape fixed + [0].
  subroutine create_growing(loc, name, fixed)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(hsize_t), intent(in) :: fixed(:)
    integer(hid_t) :: space, plist, dset
    integer(hsize_t) :: dims(size(fixed) + 1), maxdims(size(fixed) + 1), chunk(size(fixed) + 1)
    integer :: err
    dims = [fixed, 0_hsize_t]
    maxdims = [fixed, H5S_UNLIMITED_F]
    chunk = [max(fixed, 1_hsize_t), merge(64_hsize_t, 1_hsize_t, size(fixed) == 0)]
    call h5screate_simple_f(size(dims), dims, space, err, maxdims)
    call h5pcreate_f(H5P_DATASET_CREATE_F, plist, err)
    call h5pset_chunk_f(plist, size(chunk), chunk, err)
    call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, space, dset, err, plist)
    call h5dclose_f(dset, err)
    call h5pclose_f(plist, err)
    call h5sclose_f(space, err)
  end subroutine create_growing

  !> Appends entry number `index` (1-based) to a growing dataset.
  subroutine append(file, name, values, fixed, index)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: values(:)
    integer(hsize_t), intent(in) :: fixed(:)
    integer, intent(in) :: index
    integer(hid_t) :: dset, filespace, memspace
    integer(hsize_t) :: dims(size(fixed) + 1), offset(size(fixed) + 1), count(size(fixed) + 1)
    integer :: err
    dims = [fixed, int(index, hsize_t)]
    offset = 0
    offset(size(offset)) = index - 1
    count = [fixed, 1_hsize_t]
    call h5dopen_f(file, name, dset, err)
    call h5dset_extent_f(dset, dims, err)
    call h5dget_space_f(dset, filespace, err)
    call h5sselect_hyperslab_f(filespace, H5S_SELECT_SET_F, offset, count, err)
    call h5screate_simple_f(size(count), count, memspace, err)
    call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, values, count, err, memspace, filespace)
    call h5sclose_f(memspace, err)
    call h5sclose_f(filespace, err)
    call h5dclose_f(dset, err)
  end subroutine append

  subroutine write_real_dataset(loc, name, a)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: a(:, :)
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(2)
    integer :: err
    dims = shape(a, kind=hsize_t)
    call h5screate_simple_f(2, dims, space, err)
    call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, space, dset, err)
    call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, a, dims, err)
    call h5dclose_f(dset, err)
    call h5sclose_f(space, err)
  end subroutine write_real_dataset

  subroutine write_int_dataset(loc, name, a, rank1)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: a(:, :)
    logical, intent(in), optional :: rank1
    integer(hid_t) :: space, dset
    integer(hsize_t) :: dims(2)
    integer :: err, ndims
    dims = shape(a, kind=hsize_t)
    ndims = 2
    if (present(rank1)) then
      if (rank1) then
        ndims = 1
        dims(1) = dims(2)
      end if
    end if
    call h5screate_simple_f(ndims, dims(1:ndims), space, err)
    call h5dcreate_f(loc, name, H5T_STD_I32LE, space, dset, err)
    call h5dwrite_f(dset, H5T_NATIVE_INTEGER, a, dims(1:ndims), err)
    call h5dclose_f(dset, err)
    call h5sclose_f(space, err)
  end subroutine write_int_dataset

  subroutine write_int_attribute(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: value
    integer(hid_t) :: space, attr
    integer :: err
    call h5screate_f(H5S_SCALAR_F, space, err)
    call h5acreate_f(loc, name, H5T_STD_I32LE, space, attr, err)
    call h5awrite_f(attr, H5T_NATIVE_INTEGER, value, [1_hsize_t], err)
    call h5aclose_f(attr, err)
    call h5sclose_f(space, err)
  end subroutine write_int_attribute

  subroutine overwrite_int_attribute(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: value
    integer(hid_t) :: attr
    integer :: err
    call h5aopen_f(loc, name, attr, err)
    call h5awrite_f(attr, H5T_NATIVE_INTEGER, value, [1_hsize_t], err)
    call h5aclose_f(attr, err)
  end subroutine overwrite_int_attribute

  subroutine write_real_attribute(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: value
    integer(hid_t) :: space, attr
    integer :: err
    call h5screate_f(H5S_SCALAR_F, space, err)
    call h5acreate_f(loc, name, H5T_NATIVE_DOUBLE, space, attr, err)
    call h5awrite_f(attr, H5T_NATIVE_DOUBLE, value, [1_hsize_t], err)
    call h5aclose_f(attr, err)
    call h5sclose_f(space, err)
  end subroutine write_real_attribute

end module results_writer
