!> Writes results.h5 (docs/formats.md, version 1) collectively with parallel HDF5 (MPI-IO): every
!> rank writes the rows it owns (its owned nodes, its elements) straight into the global datasets,
!> so no field is funnelled through one rank. Datasets grow by one frame or record at a time and
!> the file is flushed after each, so a run that stops early leaves a readable file whose root
!> attribute `complete` stays 0. Every call here is collective over the communicator.
module results_writer
  use hdf5
  use mpi_f08, only: MPI_Comm, MPI_INFO_NULL, MPI_Comm_rank
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: results_file_t, results_create, results_write_frame, results_write_history
  public :: results_finish, run_record_t, row_runs_t, row_runs

  !> The global rows (node or element ids) a rank writes, as runs of consecutive ids.
  type :: row_runs_t
    integer :: n_rows = 0                       !< rows in all runs
    integer, allocatable :: first(:), length(:)
  end type row_runs_t

  type :: results_file_t
    integer(hid_t) :: file = -1, transfer = -1
    integer :: n_nodes = 0, n_elements = 0, n_tracked = 0
    integer :: frames = 0, records = 0
    logical :: root = .false.                   !< this rank writes the history
    type(row_runs_t) :: nodes, elements, tracked
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

  !> The runs of consecutive ids in an ascending id list.
  pure function row_runs(ids) result(runs)
    integer, intent(in) :: ids(:)
    type(row_runs_t) :: runs
    logical :: starts(size(ids))
    integer :: k, r
    starts = .true.
    if (size(ids) > 1) starts(2:) = ids(2:) /= ids(:size(ids) - 1) + 1
    allocate (runs%first(count(starts)), runs%length(count(starts)))
    r = 0
    do k = 1, size(ids)
      if (starts(k)) then
        r = r + 1
        runs%first(r) = ids(k)
        runs%length(r) = 0
      end if
      runs%length(r) = runs%length(r) + 1
    end do
    runs%n_rows = size(ids)
  end function row_runs

  !> Creates the file on every rank of comm. node_ids: the global nodes this rank writes
  !> (each node written by exactly one rank), ascending; element_ids: this rank's elements,
  !> ascending. coordinates, connectivity (global 1-based ids) and element_part are those rows.
  subroutine results_create(path, comm, n_nodes, n_elements, node_ids, element_ids, coordinates, &
                            connectivity, element_part, n_tracked, rf, status, message)
    character(len=*), intent(in) :: path
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_nodes, n_elements, node_ids(:), element_ids(:)
    real(wp), intent(in) :: coordinates(:, :)
    integer, intent(in) :: connectivity(:, :), element_part(:), n_tracked
    type(results_file_t), intent(out) :: rf
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer :: err, k, rank
    integer(hid_t) :: group, access
    integer(hsize_t) :: nn, ne
    call MPI_Comm_rank(comm, rank)
    rf%root = rank == 0
    rf%n_nodes = n_nodes
    rf%n_elements = n_elements
    rf%n_tracked = n_tracked
    rf%nodes = row_runs(node_ids)
    rf%elements = row_runs(element_ids)
    if (rf%root) then
      rf%tracked = row_runs([(k, k = 1, n_tracked)])
    else
      rf%tracked = row_runs([integer ::])
    end if
    nn = int(n_nodes, hsize_t)
    ne = int(n_elements, hsize_t)
    call h5pcreate_f(H5P_FILE_ACCESS_F, access, err)
    call h5pset_fapl_mpio_f(access, comm%MPI_VAL, MPI_INFO_NULL%MPI_VAL, err)
    call h5fcreate_f(path, H5F_ACC_TRUNC_F, rf%file, err, access_prp=access)
    call h5pclose_f(access, err)
    if (err /= 0) then
      status = 1
      message = 'cannot create '//trim(path)//'; check that the folder exists and is writable'
      return
    end if
    call h5pcreate_f(H5P_DATASET_XFER_F, rf%transfer, err)
    call h5pset_dxpl_mpio_f(rf%transfer, H5FD_MPIO_COLLECTIVE_F, err)
    call write_int_attribute(rf%file, 'paradyn_results_version', 1)
    call write_int_attribute(rf%file, 'complete', 0)
    call h5gcreate_f(rf%file, 'mesh', group, err)
    call create_dataset(group, 'coordinates', H5T_NATIVE_DOUBLE, [3_hsize_t, nn])
    call create_dataset(group, 'connectivity', H5T_STD_I32LE, [4_hsize_t, ne])
    call create_dataset(group, 'part', H5T_STD_I32LE, [ne])
    call h5gclose_f(group, err)
    call write_rows(rf, '/mesh/coordinates', real_values=reshape(coordinates, [size(coordinates)]), &
                    fixed=[3_hsize_t, nn], runs=rf%nodes, frame=0)
    call write_rows(rf, '/mesh/connectivity', int_values=reshape(connectivity - 1, [size(connectivity)]), &
                    fixed=[4_hsize_t, ne], runs=rf%elements, frame=0)
    call write_rows(rf, '/mesh/part', int_values=element_part - 1, fixed=[ne], runs=rf%elements, frame=0)
    call h5gcreate_f(rf%file, 'frames', group, err)
    call create_growing(group, 'time', [integer(hsize_t) ::])
    call create_growing(group, 'displacement', [3_hsize_t, nn])
    call create_growing(group, 'velocity', [3_hsize_t, nn])
    call create_growing(group, 'element_membrane_stress', [3_hsize_t, ne])
    call create_growing(group, 'element_von_mises', [ne])
    call create_growing(group, 'element_plastic_strain', [ne])
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

  !> One frame: this rank's owned nodes (3, n) and elements (membrane (3, n), von Mises, plastic
  !> strain), in the order of the ids given to results_create.
  subroutine results_write_frame(rf, time, displacement, velocity, membrane, von_mises, plastic_strain)
    type(results_file_t), intent(inout) :: rf
    real(wp), intent(in) :: time, displacement(:, :), velocity(:, :), membrane(:, :)
    real(wp), intent(in) :: von_mises(:), plastic_strain(:)
    integer :: err
    integer(hsize_t) :: nn, ne
    nn = int(rf%n_nodes, hsize_t)
    ne = int(rf%n_elements, hsize_t)
    rf%frames = rf%frames + 1
    call append_root(rf, '/frames/time', [time], [integer(hsize_t) ::], rf%frames)
    call write_rows(rf, '/frames/displacement', reshape(displacement, [size(displacement)]), &
                    fixed=[3_hsize_t, nn], runs=rf%nodes, frame=rf%frames)
    call write_rows(rf, '/frames/velocity', reshape(velocity, [size(velocity)]), &
                    fixed=[3_hsize_t, nn], runs=rf%nodes, frame=rf%frames)
    call write_rows(rf, '/frames/element_membrane_stress', reshape(membrane, [size(membrane)]), &
                    fixed=[3_hsize_t, ne], runs=rf%elements, frame=rf%frames)
    call write_rows(rf, '/frames/element_von_mises', von_mises, fixed=[ne], runs=rf%elements, frame=rf%frames)
    call write_rows(rf, '/frames/element_plastic_strain', plastic_strain, fixed=[ne], runs=rf%elements, &
                    frame=rf%frames)
    call h5fflush_f(rf%file, H5F_SCOPE_GLOBAL_F, err)
  end subroutine results_write_frame

  !> values: kinetic, internal, hourglass and contact energy, external work, deepest contact
  !> penetration. Collective; the values of rank 0 are written.
  subroutine results_write_history(rf, time, values, tracked_displacement, tracked_velocity)
    type(results_file_t), intent(inout) :: rf
    real(wp), intent(in) :: time, values(history_names_count)
    real(wp), intent(in) :: tracked_displacement(:, :), tracked_velocity(:, :)
    integer :: k
    integer(hsize_t) :: nt
    nt = int(rf%n_tracked, hsize_t)
    rf%records = rf%records + 1
    call append_root(rf, '/history/time', [time], [integer(hsize_t) ::], rf%records)
    do k = 1, history_names_count
      call append_root(rf, '/history/'//trim(history_names(k)), [values(k)], [integer(hsize_t) ::], rf%records)
    end do
    call write_rows(rf, '/history/tracked_displacement', reshape(tracked_displacement, &
                    [size(tracked_displacement)]), fixed=[3_hsize_t, nt], runs=rf%tracked, frame=rf%records)
    call write_rows(rf, '/history/tracked_velocity', reshape(tracked_velocity, &
                    [size(tracked_velocity)]), fixed=[3_hsize_t, nt], runs=rf%tracked, frame=rf%records)
  end subroutine results_write_history

  !> Writes the /run attributes (the same record on every rank), marks the file complete when
  !> asked, and closes it.
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
    call h5pclose_f(rf%transfer, err)
    call h5fclose_f(rf%file, err)
    rf%file = -1
  end subroutine results_finish

  ! ---------------------------------------------------------------- HDF5 plumbing

  subroutine create_dataset(loc, name, type_id, dims)
    integer(hid_t), intent(in) :: loc, type_id
    character(len=*), intent(in) :: name
    integer(hsize_t), intent(in) :: dims(:)
    integer(hid_t) :: space, dset
    integer :: err
    call h5screate_simple_f(size(dims), dims, space, err)
    call h5dcreate_f(loc, name, type_id, space, dset, err)
    call h5dclose_f(dset, err)
    call h5sclose_f(space, err)
  end subroutine create_dataset

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

  !> Appends entry `index` of a growing dataset whose whole entry rank 0 writes.
  subroutine append_root(rf, name, values, fixed, index)
    type(results_file_t), intent(in) :: rf
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: values(:)
    integer(hsize_t), intent(in) :: fixed(:)
    integer, intent(in) :: index
    type(row_runs_t) :: whole
    ! the entry is one row of a dataset of shape [fixed, 1]
    whole = row_runs(pack([1], rf%root))
    call write_rows(rf, name, values, [fixed, 1_hsize_t], whole, index, frame_is_row=.true.)
  end subroutine append_root

  !> Collective write of this rank's rows into dataset `name` of Fortran shape `fixed` (rows along
  !> its last dimension), or, with frame > 0, into entry `frame` of the growing dataset of shape
  !> [fixed, frames], which is extended first. Values: the rows, in run order.
  !> frame_is_row: the last dimension of fixed is a dummy 1 standing for the frame itself.
  subroutine write_rows(rf, name, real_values, fixed, runs, frame, int_values, frame_is_row)
    type(results_file_t), intent(in) :: rf
    character(len=*), intent(in) :: name
    real(wp), intent(in), optional :: real_values(:)
    integer(hsize_t), intent(in) :: fixed(:)
    type(row_runs_t), intent(in) :: runs
    integer, intent(in) :: frame
    integer, intent(in), optional :: int_values(:)
    logical, intent(in), optional :: frame_is_row
    integer(hid_t) :: dset, filespace, memspace
    integer(hsize_t) :: dims(size(fixed) + 1), offset(size(fixed) + 1), count(size(fixed) + 1)
    integer(hsize_t) :: n_values(1)
    integer :: err, k, nd, row_dim
    logical :: merged
    merged = .false.
    if (present(frame_is_row)) merged = frame_is_row
    row_dim = size(fixed)
    nd = size(fixed) + merge(1, 0, frame > 0 .and. .not. merged)
    dims(1:size(fixed)) = fixed
    if (frame > 0) dims(nd) = int(frame, hsize_t)
    call h5dopen_f(rf%file, name, dset, err)
    if (frame > 0) call h5dset_extent_f(dset, dims(1:nd), err)
    call h5dget_space_f(dset, filespace, err)
    call h5sselect_none_f(filespace, err)
    do k = 1, size(runs%first)
      offset(1:nd) = 0
      count(1:nd) = dims(1:nd)
      offset(row_dim) = int(runs%first(k) - 1, hsize_t)
      count(row_dim) = int(runs%length(k), hsize_t)
      if (frame > 0) then
        offset(nd) = int(frame - 1, hsize_t)
        count(nd) = 1
      end if
      call h5sselect_hyperslab_f(filespace, H5S_SELECT_OR_F, offset(1:nd), count(1:nd), err)
    end do
    n_values = product(fixed(1:row_dim - 1)) * int(runs%n_rows, hsize_t)
    call h5screate_simple_f(1, max(n_values, 1_hsize_t), memspace, err)
    if (n_values(1) == 0) call h5sselect_none_f(memspace, err)
    if (present(real_values)) then
      call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, real_values, n_values, err, memspace, filespace, rf%transfer)
    else
      call h5dwrite_f(dset, H5T_NATIVE_INTEGER, int_values, n_values, err, memspace, filespace, rf%transfer)
    end if
    call h5sclose_f(memspace, err)
    call h5sclose_f(filespace, err)
    call h5dclose_f(dset, err)
  end subroutine write_rows

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
