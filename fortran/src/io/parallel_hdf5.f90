!> Collective parallel HDF5 (MPI-IO) plumbing shared by the results and checkpoint files: every
!> rank reads or writes its own rows of a global dataset, selected as a union of hyperslabs, one
!> per run of consecutive global ids. Rows lie along the last Fortran dimension of a dataset
!> (h5py's first); a growing dataset has one more dimension, the frame. Every call is collective.
module parallel_hdf5
  use, intrinsic :: iso_c_binding, only: c_loc, c_ptr
  use hdf5
  use mpi_f08, only: MPI_Comm, MPI_Comm_size, MPI_Info, MPI_Info_create, MPI_Info_set, MPI_Info_free
  use paradyn_kinds, only: wp, i8
  implicit none
  private
  public :: row_runs_t, row_runs, phdf5_open, phdf5_close
  public :: create_dataset, create_growing, write_rows, read_rows, truncate_growing
  public :: write_long_array_attribute, write_real_array_attribute, read_long_attribute
  public :: write_int_attribute, write_long_attribute, write_real_attribute, read_int_attribute, read_real_attribute
  public :: read_real_array_attribute

  !> The MPI-IO hint cb_buffer_size of every file (bytes, as the hint's text): 4 MiB.
  character(len=*), parameter :: collective_buffer_bytes = '4194304'

  !> The global rows (node or element ids) a rank reads or writes, as runs of consecutive ids.
  type :: row_runs_t
    integer :: n_rows = 0                       !< rows in all runs
    integer, allocatable :: first(:), length(:)
  end type row_runs_t

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

  !> Creates (mode 'create'), or opens for reading ('read') or appending ('append'), a file on
  !> every rank of comm, with a collective transfer list for the row reads and writes.
  subroutine phdf5_open(path, comm, mode, file, transfer, err)
    character(len=*), intent(in) :: path, mode
    type(MPI_Comm), intent(in) :: comm
    integer(hid_t), intent(out) :: file, transfer
    integer, intent(out) :: err
    integer(hid_t) :: access
    integer :: ignored, n_ranks
    type(MPI_Info) :: hints
    call MPI_Comm_size(comm, n_ranks)
    call h5pcreate_f(H5P_FILE_ACCESS_F, access, ignored)
    ! one rank: the POSIX driver; MPI-IO would load its components and make lock and shared files.
    ! Several: MPI-IO, with its collective buffer bounded: an aggregator rank (rank 0 among them)
    ! gathers the ranks' rows of a collective write in cycles of this many bytes, so its memory
    ! stays within it whatever the mesh (the libraries' defaults, 16 or 32 MiB, fill with the
    ! global mesh until reached; docs/performance.md, "Beyond one machine")
    if (n_ranks > 1) then
      call MPI_Info_create(hints)
      call MPI_Info_set(hints, 'cb_buffer_size', collective_buffer_bytes)
      call h5pset_fapl_mpio_f(access, comm%MPI_VAL, hints%MPI_VAL, ignored)   ! HDF5 keeps a copy
      call MPI_Info_free(hints)
    end if
    select case (mode)
    case ('create')
      call h5fcreate_f(path, H5F_ACC_TRUNC_F, file, err, access_prp=access)
    case ('append')
      call h5fopen_f(path, H5F_ACC_RDWR_F, file, err, access_prp=access)
    case default
      call h5fopen_f(path, H5F_ACC_RDONLY_F, file, err, access_prp=access)
    end select
    call h5pclose_f(access, ignored)
    call h5pcreate_f(H5P_DATASET_XFER_F, transfer, ignored)
    if (n_ranks > 1) call h5pset_dxpl_mpio_f(transfer, H5FD_MPIO_COLLECTIVE_F, ignored)
  end subroutine phdf5_open

  subroutine phdf5_close(file, transfer)
    integer(hid_t), intent(inout) :: file, transfer
    integer :: err
    call h5pclose_f(transfer, err)
    call h5fclose_f(file, err)
    file = -1
    transfer = -1
  end subroutine phdf5_close

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

  !> A chunked float64 dataset of Fortran shape [fixed, 0] whose last dimension grows.
  subroutine create_growing(loc, name, fixed)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(hsize_t), intent(in) :: fixed(:)
    integer(hid_t) :: space, plist, dset
    integer(hsize_t) :: dims(size(fixed) + 1), maxdims(size(fixed) + 1), chunk(size(fixed) + 1)
    integer :: err
    dims = [fixed, 0_hsize_t]
    maxdims = [fixed, H5S_UNLIMITED_F]
    ! rows of about 4 KiB per chunk (1 to 64): a history row of a few numbers is not a chunk of its own
    chunk = [max(fixed, 1_hsize_t), max(1_hsize_t, min(64_hsize_t, 512_hsize_t / max(1_hsize_t, product(fixed))))]
    call h5screate_simple_f(size(dims), dims, space, err, maxdims)
    call h5pcreate_f(H5P_DATASET_CREATE_F, plist, err)
    call h5pset_chunk_f(plist, size(chunk), chunk, err)
    ! every entry is written before it is read: no fill values (parallel HDF5 writes them at each extension)
    call h5pset_fill_time_f(plist, H5D_FILL_TIME_NEVER_F, err)
    ! chunks made when the dataset grows, as parallel HDF5 requires: a file one rank wrote
    ! (POSIX driver) continues on several (a restart on another layout)
    call h5pset_alloc_time_f(plist, H5D_ALLOC_TIME_EARLY_F, err)
    call h5dcreate_f(loc, name, H5T_NATIVE_DOUBLE, space, dset, err, plist)
    call h5dclose_f(dset, err)
    call h5pclose_f(plist, err)
    call h5sclose_f(space, err)
  end subroutine create_growing

  !> Cuts a growing dataset back to its first `entries` frames (a restart drops what follows).
  subroutine truncate_growing(file, name, entries)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: name
    integer, intent(in) :: entries
    integer(hid_t) :: dset, space
    integer(hsize_t) :: dims(3), maxdims(3)
    integer :: err, nd
    call h5dopen_f(file, name, dset, err)
    call h5dget_space_f(dset, space, err)
    call h5sget_simple_extent_ndims_f(space, nd, err)
    call h5sget_simple_extent_dims_f(space, dims(1:nd), maxdims(1:nd), err)
    call h5sclose_f(space, err)
    dims(nd) = int(entries, hsize_t)
    call h5dset_extent_f(dset, dims(1:nd), err)
    call h5dclose_f(dset, err)
  end subroutine truncate_growing

  !> Writes this rank's rows (values in run order) into dataset `name` of Fortran shape `fixed`,
  !> or, with frame > 0, into entry `frame` of the growing dataset [fixed, frames], extended
  !> first. frame_is_row: fixed ends with a dummy 1 and the frame itself is the row (scalars).
  !> n_frames: entries frame .. frame + n_frames - 1 at once (values frame after frame).
  subroutine write_rows(file, transfer, name, fixed, runs, frame, real_values, int_values, frame_is_row, n_frames, &
                        failed)
    integer(hid_t), intent(in) :: file, transfer
    character(len=*), intent(in) :: name
    integer(hsize_t), intent(in) :: fixed(:)
    type(row_runs_t), intent(in) :: runs
    integer, intent(in) :: frame
    real(wp), intent(in), optional :: real_values(:)
    integer, intent(in), optional :: int_values(:)
    logical, intent(in), optional :: frame_is_row
    integer, intent(in), optional :: n_frames
    logical, intent(inout), optional :: failed   !< set when HDF5 reports a failed write (a full disk)
    integer(hid_t) :: dset, filespace, memspace
    integer(hsize_t) :: dims(size(fixed) + 1), n_values(1)
    integer :: err, nd, count
    logical :: merged
    merged = .false.
    if (present(frame_is_row)) merged = frame_is_row
    count = 1
    if (present(n_frames)) count = n_frames
    nd = size(fixed) + merge(1, 0, frame > 0 .and. .not. merged)
    dims(1:size(fixed)) = fixed
    if (frame > 0) dims(nd) = int(frame + count - 1, hsize_t)
    call h5dopen_f(file, name, dset, err)
    if (frame > 0) call h5dset_extent_f(dset, dims(1:nd), err)
    if (err /= 0 .and. present(failed)) failed = .true.
    call h5dget_space_f(dset, filespace, err)
    call select_rows(filespace, dims(1:nd), size(fixed), runs, frame, n_values(1), count)
    memspace = memory_space(dims(1:nd), size(fixed), runs, frame, count, n_values(1))
    if (present(real_values)) then
      call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, real_values, n_values, err, memspace, filespace, transfer)
    else
      call h5dwrite_f(dset, H5T_NATIVE_INTEGER, int_values, n_values, err, memspace, filespace, transfer)
    end if
    if (err /= 0 .and. present(failed)) failed = .true.
    call h5sclose_f(memspace, err)
    call h5sclose_f(filespace, err)
    call h5dclose_f(dset, err)
  end subroutine write_rows

  !> Reads this rank's rows of a float64 dataset of Fortran shape `fixed` into values (width,
  !> rows), in run order.
  subroutine read_rows(file, transfer, name, fixed, runs, values, err)
    integer(hid_t), intent(in) :: file, transfer
    character(len=*), intent(in) :: name
    integer(hsize_t), intent(in) :: fixed(:)
    type(row_runs_t), intent(in) :: runs
    real(wp), intent(out) :: values(:, :)
    integer, intent(out) :: err
    integer(hid_t) :: dset, filespace, memspace
    integer(hsize_t) :: n_values(1)
    integer :: ignored
    real(wp), allocatable :: buffer(:)   ! not on the stack: checkpoints of large meshes
    call h5dopen_f(file, name, dset, err)
    if (err /= 0) return
    allocate (buffer(max(size(values), 1)))
    call h5dget_space_f(dset, filespace, ignored)
    call select_rows(filespace, fixed, size(fixed), runs, 0, n_values(1))
    memspace = memory_space(fixed, size(fixed), runs, 0, 1, n_values(1))
    call h5dread_f(dset, H5T_NATIVE_DOUBLE, buffer, n_values, err, memspace, filespace, transfer)
    values = reshape(buffer(1:size(values)), shape(values))
    call h5sclose_f(memspace, ignored)
    call h5sclose_f(filespace, ignored)
    call h5dclose_f(dset, ignored)
  end subroutine read_rows

  !> The memory space of n_values values for the selection of select_rows. One run: the shape of
  !> the selection, which lets HDF5 map it chunk by chunk (a flat space of another shape makes it
  !> map every value, which cost more than the rest of a frame's write); several runs: flat.
  integer(hid_t) function memory_space(dims, row_dim, runs, frame, n_frames, n_values) result(space)
    integer(hsize_t), intent(in) :: dims(:), n_values
    integer, intent(in) :: row_dim, frame, n_frames
    type(row_runs_t), intent(in) :: runs
    integer(hsize_t) :: selection(size(dims))
    integer :: err
    if (size(runs%first) == 1) then
      selection = dims
      selection(row_dim) = int(runs%length(1), hsize_t)
      if (frame > 0) selection(size(dims)) = int(n_frames, hsize_t)
      call h5screate_simple_f(size(dims), selection, space, err)
    else
      call h5screate_simple_f(1, [max(n_values, 1_hsize_t)], space, err)
      if (n_values == 0) call h5sselect_none_f(space, err)
    end if
  end function memory_space

  !> Selects the runs' rows (along dimension row_dim) of entries frame .. frame + n_frames - 1
  !> (when frame > 0, along the last dimension).
  subroutine select_rows(space, dims, row_dim, runs, frame, n_values, n_frames)
    integer(hid_t), intent(in) :: space
    integer(hsize_t), intent(in) :: dims(:)
    integer, intent(in) :: row_dim, frame
    type(row_runs_t), intent(in) :: runs
    integer(hsize_t), intent(out) :: n_values
    integer, intent(in), optional :: n_frames
    integer(hsize_t) :: offset(size(dims)), count(size(dims))
    integer :: k, err, nd, entries
    nd = size(dims)
    entries = 1
    if (present(n_frames) .and. frame > 0) entries = n_frames
    call h5sselect_none_f(space, err)
    do k = 1, size(runs%first)
      offset = 0
      count = dims
      offset(row_dim) = int(runs%first(k) - 1, hsize_t)
      count(row_dim) = int(runs%length(k), hsize_t)
      if (frame > 0) then
        offset(nd) = int(frame - 1, hsize_t)
        count(nd) = int(entries, hsize_t)
      end if
      ! the first as a set: a single run stays a regular hyperslab
      call h5sselect_hyperslab_f(space, merge(H5S_SELECT_SET_F, H5S_SELECT_OR_F, k == 1), offset, count, err)
    end do
    n_values = product(dims(1:row_dim - 1)) * int(runs%n_rows, hsize_t) * int(entries, hsize_t)
  end subroutine select_rows

  !> Writes (or overwrites) an integer attribute; every rank passes the same value.
  subroutine write_int_attribute(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(in) :: value
    integer(hid_t) :: attr
    integer :: err
    attr = scalar_attribute(loc, name, H5T_STD_I32LE)
    call h5awrite_f(attr, H5T_NATIVE_INTEGER, value, [1_hsize_t], err)
    call h5aclose_f(attr, err)
  end subroutine write_int_attribute

  subroutine write_long_attribute(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(i8), intent(in), target :: value
    integer(hid_t) :: attr
    integer :: err
    attr = scalar_attribute(loc, name, H5T_STD_I64LE)
    call h5awrite_f(attr, h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(value), err)
    call h5aclose_f(attr, err)
  end subroutine write_long_attribute

  !> A one-dimensional int64 attribute (h5py reads a numpy array).
  subroutine write_long_array_attribute(loc, name, values)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(i8), intent(in), target :: values(:)
    integer(hid_t) :: attr, space
    integer :: err
    call h5screate_simple_f(1, [int(size(values), hsize_t)], space, err)
    call h5acreate_f(loc, name, H5T_STD_I64LE, space, attr, err)
    if (size(values) > 0) call h5awrite_f(attr, h5kind_to_type(i8, H5_INTEGER_KIND), c_loc(values), err)
    call h5aclose_f(attr, err)
    call h5sclose_f(space, err)
  end subroutine write_long_array_attribute

  !> A one-dimensional float64 attribute (h5py reads a numpy array).
  subroutine write_real_array_attribute(loc, name, values)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: values(:)
    integer(hid_t) :: attr, space
    integer :: err
    call h5screate_simple_f(1, [int(size(values), hsize_t)], space, err)
    call h5acreate_f(loc, name, H5T_NATIVE_DOUBLE, space, attr, err)
    if (size(values) > 0) call h5awrite_f(attr, H5T_NATIVE_DOUBLE, values, [int(size(values), hsize_t)], err)
    call h5aclose_f(attr, err)
    call h5sclose_f(space, err)
  end subroutine write_real_array_attribute

  !> An int64 attribute; err /= 0 where it is missing.
  subroutine read_long_attribute(loc, name, value, err)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer(i8), intent(out), target :: value
    integer, intent(out) :: err
    integer(hid_t) :: attr
    integer :: ignored
    type(c_ptr) :: buffer
    value = 0
    call h5aopen_f(loc, name, attr, err)
    if (err /= 0) return
    buffer = c_loc(value)
    call h5aread_f(attr, h5kind_to_type(i8, H5_INTEGER_KIND), buffer, err)
    call h5aclose_f(attr, ignored)
  end subroutine read_long_attribute

  subroutine write_real_attribute(loc, name, value)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: value
    integer(hid_t) :: attr
    integer :: err
    attr = scalar_attribute(loc, name, H5T_NATIVE_DOUBLE)
    call h5awrite_f(attr, H5T_NATIVE_DOUBLE, value, [1_hsize_t], err)
    call h5aclose_f(attr, err)
  end subroutine write_real_attribute

  !> A scalar attribute opened for writing: the existing one, or a new one of file type type_id.
  function scalar_attribute(loc, name, type_id) result(attr)
    integer(hid_t), intent(in) :: loc, type_id
    character(len=*), intent(in) :: name
    integer(hid_t) :: attr, space
    integer :: err
    logical :: exists
    call h5aexists_f(loc, name, exists, err)
    if (exists) then
      call h5aopen_f(loc, name, attr, err)
    else
      call h5screate_f(H5S_SCALAR_F, space, err)
      call h5acreate_f(loc, name, type_id, space, attr, err)
      call h5sclose_f(space, err)
    end if
  end function scalar_attribute

  subroutine read_int_attribute(loc, name, value, err)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    integer, intent(out) :: value, err
    integer(hid_t) :: attr
    integer :: ignored
    value = 0
    call h5aopen_f(loc, name, attr, err)
    if (err /= 0) return
    call h5aread_f(attr, H5T_NATIVE_INTEGER, value, [1_hsize_t], err)
    call h5aclose_f(attr, ignored)
  end subroutine read_int_attribute

  subroutine read_real_attribute(loc, name, value, err)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(wp), intent(out) :: value
    integer, intent(out) :: err
    integer(hid_t) :: attr
    integer :: ignored
    value = 0
    call h5aopen_f(loc, name, attr, err)
    if (err /= 0) return
    call h5aread_f(attr, H5T_NATIVE_DOUBLE, value, [1_hsize_t], err)
    call h5aclose_f(attr, ignored)
  end subroutine read_real_attribute

  !> A float64 attribute of the size of values (zeros and err /= 0 when it is absent).
  subroutine read_real_array_attribute(loc, name, values, err)
    integer(hid_t), intent(in) :: loc
    character(len=*), intent(in) :: name
    real(wp), intent(out) :: values(:)
    integer, intent(out) :: err
    integer(hid_t) :: attr
    integer :: ignored
    values = 0
    call h5aopen_f(loc, name, attr, err)
    if (err /= 0) return
    if (size(values) > 0) call h5aread_f(attr, H5T_NATIVE_DOUBLE, values, [int(size(values), hsize_t)], err)
    call h5aclose_f(attr, ignored)
  end subroutine read_real_array_attribute

end module parallel_hdf5
