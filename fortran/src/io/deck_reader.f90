!> Reads a deck (docs/formats.md, version 1) from HDF5 and checks it as strictly as the frontend:
!> a loop over the schema's datasets (presence, type class, shape, then the value rules of
!> deck_rules) and /control attributes, then the relations (deck_checks). Collective over the
!> ranks (issue 19, item 5): the file is opened with parallel HDF5, every rank reads the tables
!> sized by the definitions whole and, with collective hyperslab reads, only its block of the
!> mesh's rows: elements block_owner(e, n_elements, n_ranks) and nodes block_owner(n, n_nodes,
!> n_ranks) (deck_directory). The value rules run on those blocks and are agreed over the ranks
!> (the first offending row, as one rank reading everything would name it); deck_checks then
!> gives each rank the rows model_deck's layout holds. A rank never holds a mesh dataset whole.
module deck_reader
  use hdf5
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Comm_size
  use paradyn_kinds, only: wp, i8
  use parallel_hdf5, only: phdf5_open, phdf5_close, read_rows, row_runs
  use deck_directory, only: block_range
  use deck_checks, only: agree_on_first, chain_fingerprint, distribute_and_check
  use deck_fingerprint, only: fingerprint_start, fingerprint_add, group_of
  use paradyn_schema, only: deck_version, deck_version_attribute, deck_datasets, control_attributes, &
                            deck_conditions, deck_enums, n_deck_datasets, n_control_attributes, n_sizes, &
                            size_entity, size_symbol, size_min_rows, class_int, class_float, class_string, &
                            condition_none, enum_code, control_restart_may_change, &
                            status_ok, status_bad_input, size_n_nodes, size_n_elements
  use deck_rules, only: check_field_values, check_attribute_value, selected_rows, condition_rows, integer_text
  use model_deck, only: deck_t, store_dataset, store_control
  use hdf5_attributes, only: read_string_attribute, read_real_attribute, read_int_attribute, link_exists
  implicit none
  private
  public :: read_deck

  !> One dataset as the file holds it: (max(columns, 1), rows), indices 0-based.
  type :: field_t
    real(wp), allocatable :: values(:, :)
  end type field_t

  !> A deck being read: the open file, the datasets read so far, the row counts known so far (-1
  !> until the first dataset of a row symbol is read), and the first problem found ('' while none).
  !> The mesh's datasets (rows of nodes or elements) hold this rank's block of rows only: rows
  !> first(symbol) + 1 .. first(symbol) + held(symbol) of the file's.
  type :: deck_file_t
    integer(hid_t) :: file = -1, transfer = -1
    type(MPI_Comm) :: comm
    integer :: rank = 0, n_ranks = 1
    type(field_t) :: fields(n_deck_datasets)
    integer :: sizes(n_sizes) = -1
    integer :: first(n_sizes) = 0, held(n_sizes) = -1
    real(wp) :: control(n_control_attributes) = 0.0_wp   !< the /control values as read, or their defaults
    character(len=1024) :: message = ''
  end type deck_file_t

contains

  !> status_ok on success, status_bad_input with a message for a bad deck, the same on every rank
  !> of comm. Collective.
  subroutine read_deck(path, comm, d, status, message)
    character(len=*), intent(in) :: path
    type(MPI_Comm), intent(in) :: comm
    type(deck_t), intent(out) :: d
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    type(deck_file_t) :: r
    integer :: err, version, id, bad_row
    logical :: exists

    status = status_bad_input
    message = ''
    inquire (file=path, exist=exists)
    if (.not. exists) then
      message = 'no such file; give the path of a deck written by paradyn-run or h5py'
      return
    end if
    r%comm = comm
    call MPI_Comm_rank(comm, r%rank)
    call MPI_Comm_size(comm, r%n_ranks)
    call phdf5_open(path, comm, 'read', r%file, r%transfer, err)
    if (err /= 0) then
      call h5pclose_f(r%transfer, err)
      message = 'not an HDF5 file (or a damaged one); give the deck.h5 that paradyn-run or paradyn.deck.write_deck wrote'
      return
    end if
    call read_int_attribute(r%file, '/', deck_version_attribute, version, -1, .true., r%message)
    if (status_ok_so_far(r) .and. version /= deck_version) then
      r%message = 'root attribute '//deck_version_attribute//' = '//integer_text(version)// &
                  ' is not supported; this engine reads version '//integer_text(deck_version)
    end if
    do id = 1, n_deck_datasets
      if (.not. status_ok_so_far(r)) exit
      call read_field(r, id)
    end do
    if (status_ok_so_far(r)) call read_control(r, d)
    call phdf5_close(r%file, r%transfer)
    message = r%message
    if (.not. status_ok_so_far(r)) return

    ! every field has its class and shape: now its values (the first bad row over all ranks),
    ! then the relations between fields
    do id = 1, n_deck_datasets
      call check_field_values(id, r%fields(id)%values, r%sizes, rows_to_check(r, id), message, &
                              r%first(deck_datasets(id)%row_symbol), bad_row)
      if (sliced(id)) call agree_on_first(comm, bad_row, message)
      if (len_trim(message) > 0) return
      call store_dataset(d, id, r%fields(id)%values)
    end do
    call fingerprint_deck(r, d)
    d%n_nodes = r%sizes(size_n_nodes)
    d%n_elements = r%sizes(size_n_elements)
    d%node_ids = [(id, id = r%first(size_n_nodes) + 1, r%first(size_n_nodes) + r%held(size_n_nodes))]
    d%element_ids = [(id, id = r%first(size_n_elements) + 1, r%first(size_n_elements) + r%held(size_n_elements))]
    d%rows_read = [r%held(size_n_elements), r%held(size_n_nodes)]
    do id = 1, n_deck_datasets   ! the blocks as read: deck_t holds them now
      deallocate (r%fields(id)%values)
    end do
    call distribute_and_check(d, comm, status, message)
  end subroutine read_deck

  !> Whether dataset id is one of the mesh's (a row per node or element): read in blocks.
  pure logical function sliced(id)
    integer, intent(in) :: id
    sliced = deck_datasets(id)%row_symbol == size_n_nodes .or. deck_datasets(id)%row_symbol == size_n_elements
  end function sliced

  !> The rows of dataset `id` its rules apply to (those of the J2 materials for the J2 data).
  function rows_to_check(r, id) result(selected)
    type(deck_file_t), intent(in) :: r
    integer, intent(in) :: id
    logical, allocatable :: selected(:)
    integer :: condition_dataset
    condition_dataset = id   ! no condition: selected_rows selects every row and ignores the values
    if (deck_datasets(id)%checked_when /= condition_none) &
      condition_dataset = deck_conditions(deck_datasets(id)%checked_when)%dataset
    selected = selected_rows(id, size(r%fields(id)%values, 2), r%fields(condition_dataset)%values)
  end function rows_to_check

  logical function status_ok_so_far(r)
    type(deck_file_t), intent(in) :: r
    status_ok_so_far = len_trim(r%message) == 0
  end function status_ok_so_far

  !> Whether condition `condition` holds for the datasets read so far.
  logical function condition_holds(r, condition)
    type(deck_file_t), intent(in) :: r
    integer, intent(in) :: condition
    condition_holds = .false.
    if (condition == condition_none) return
    associate (c => deck_conditions(condition))
      if (c%dataset == 0) then
        condition_holds = link_exists(r%file, trim(c%group))
      else
        condition_holds = any(condition_rows(condition, r%fields(c%dataset)%values(1, :)))
      end if
    end associate
  end function condition_holds

  !> Why an absent dataset is required, for the message.
  function required_because(r, condition) result(words)
    type(deck_file_t), intent(in) :: r
    integer, intent(in) :: condition
    character(len=:), allocatable :: words
    integer :: row
    words = ''
    if (condition == condition_none) return
    associate (c => deck_conditions(condition))
      if (c%dataset == 0) then
        words = ' (required since the group '//trim(c%group)//' exists)'
      else
        row = findloc(condition_rows(condition, r%fields(c%dataset)%values(1, :)), .true., dim=1)
        words = ' (required since '//trim(deck_datasets(c%dataset)%path)//'['//integer_text(row - 1)//'] = '// &
                integer_text(nint(r%fields(c%dataset)%values(1, row)))//')'
      end if
    end associate
  end function required_because

  !> Reads dataset `id` after checking presence, class and shape; an absent optional one gets its default.
  subroutine read_field(r, id)
    type(deck_file_t), intent(inout) :: r
    integer, intent(in) :: id
    integer(hid_t) :: dset
    integer(hsize_t) :: dims(2)
    logical :: found
    integer :: columns, err, k
    associate (spec => deck_datasets(id), rows => r%sizes(deck_datasets(id)%row_symbol))
      columns = max(spec%columns, 1)
      call open_checked(r, id, dset, dims, found)
      if (.not. status_ok_so_far(r)) return
      if (.not. found) then
        if (spec%required .or. condition_holds(r, spec%required_when)) then
          r%message = 'dataset '//trim(spec%path)//' is missing'//required_because(r, spec%required_when)// &
                    '; see docs/formats.md for what it holds'
          return
        end if
        rows = max(rows, 0)
        call set_block(r, id)
        allocate (r%fields(id)%values(columns, r%held(spec%row_symbol)), source=spec%default)
        return
      end if
      if (spec%defines_rows) then
        rows = int(dims(1))
        if (rows < size_min_rows(spec%row_symbol)) then
          r%message = 'dataset '//trim(spec%path)//' has no rows; a deck needs at least one '// &
                    trim(size_entity(spec%row_symbol))
          call h5dclose_f(dset, err)
          return
        end if
      end if
      call set_block(r, id)
      if (sliced(id)) then   ! collective: this rank's block of rows
        call h5dclose_f(dset, err)
        allocate (r%fields(id)%values(columns, r%held(spec%row_symbol)))
        if (spec%columns > 0) then
          call read_rows(r%file, r%transfer, trim(spec%path), [int(columns, hsize_t), dims(1)], &
                         row_runs([(k, k = r%first(spec%row_symbol) + 1, r%first(spec%row_symbol) + &
                                    r%held(spec%row_symbol))]), r%fields(id)%values, err)
        else
          call read_rows(r%file, r%transfer, trim(spec%path), [dims(1)], &
                         row_runs([(k, k = r%first(spec%row_symbol) + 1, r%first(spec%row_symbol) + &
                                    r%held(spec%row_symbol))]), r%fields(id)%values, err)
        end if
        return
      end if
      allocate (r%fields(id)%values(columns, dims(1)))
      call h5dread_f(dset, H5T_NATIVE_DOUBLE, r%fields(id)%values, [int(columns, hsize_t), dims(1)], err)
      call h5dclose_f(dset, err)
    end associate
  end subroutine read_field

  !> This rank's block of the rows of dataset id's symbol, once its row count is known: the
  !> whole table for the tables sized by the definitions.
  subroutine set_block(r, id)
    type(deck_file_t), intent(inout) :: r
    integer, intent(in) :: id
    integer :: symbol
    symbol = deck_datasets(id)%row_symbol
    if (r%held(symbol) >= 0) return
    if (sliced(id)) then
      call block_range(r%sizes(symbol), r%rank, r%n_ranks, r%first(symbol), r%held(symbol))
      r%first(symbol) = r%first(symbol) - 1
    else
      r%first(symbol) = 0
      r%held(symbol) = r%sizes(symbol)
    end if
  end subroutine set_block

  !> The dataset that sets the row count of dataset id's row symbol (the first with that symbol).
  pure integer function row_setter(id) result(setter)
    integer, intent(in) :: id
    do setter = 1, id
      if (deck_datasets(setter)%row_symbol == deck_datasets(id)%row_symbol .and. &
          deck_datasets(setter)%defines_rows) return
    end do
    setter = id
  end function row_setter

  !> Opens dataset `id` after checking that it has the spec's class and shape. dims(1): rows.
  subroutine open_checked(r, id, dset, dims, found)
    type(deck_file_t), intent(inout) :: r
    integer, intent(in) :: id
    integer(hid_t), intent(out) :: dset
    integer(hsize_t), intent(out) :: dims(2)
    logical, intent(out) :: found
    integer(hid_t) :: space, dtype
    integer(hsize_t) :: maxdims(2)
    integer :: ndims, cls, want_rank, rows, err
    character(len=:), allocatable :: name
    name = trim(deck_datasets(id)%path)
    rows = r%sizes(deck_datasets(id)%row_symbol)
    dims = 0
    found = link_exists(r%file, name)
    if (.not. found) return
    call h5dopen_f(r%file, name, dset, err)
    call h5dget_type_f(dset, dtype, err)
    call h5tget_class_f(dtype, cls, err)
    call h5tclose_f(dtype, err)
    if (deck_datasets(id)%class == class_float .and. cls /= H5T_FLOAT_F) then
      r%message = 'dataset '//name//' must hold floating-point numbers; write it as float64'
    else if (deck_datasets(id)%class == class_int .and. cls /= H5T_INTEGER_F) then
      r%message = 'dataset '//name//' must hold integers; write it with an integer dtype such as int32'
    end if
    call h5dget_space_f(dset, space, err)
    call h5sget_simple_extent_ndims_f(space, ndims, err)
    want_rank = merge(2, 1, deck_datasets(id)%columns > 0)
    if (status_ok_so_far(r) .and. ndims /= want_rank) then
      r%message = 'dataset '//name//' has '//integer_text(ndims)//' dimensions; expected '//shape_words(id)
    else if (status_ok_so_far(r)) then
      call h5sget_simple_extent_dims_f(space, dims(1:ndims), maxdims(1:ndims), err)
      ! the Fortran API reports dimensions fastest first: put rows (h5py's first axis) first
      if (ndims == 2) dims = [dims(2), dims(1)]
      if (deck_datasets(id)%columns > 0 .and. dims(min(2, ndims)) /= deck_datasets(id)%columns) then
        r%message = 'dataset '//name//' has shape ('//integer_text(int(dims(1)))//', '// &
                  integer_text(int(dims(2)))//'); expected '//shape_words(id)
      else if (rows >= 0 .and. dims(1) /= rows) then
        r%message = 'dataset '//name//' has '//integer_text(int(dims(1)))//' rows but '// &
                  trim(deck_datasets(row_setter(id))%path)//', which sets the number of '// &
                  trim(size_entity(deck_datasets(id)%row_symbol))//'s, has '//integer_text(rows)// &
                  '; give both one row per '//trim(size_entity(deck_datasets(id)%row_symbol))// &
                  ' (expected '//shape_words(id)//')'
      end if
    end if
    call h5sclose_f(space, err)
    if (.not. status_ok_so_far(r)) call h5dclose_f(dset, err)
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

  !> One fingerprint per group of the deck, in the order the schema first names the group, and one
  !> of the /control attributes a restart may not change (deck_fingerprint).
  subroutine fingerprint_deck(r, d)
    type(deck_file_t), intent(in) :: r
    type(deck_t), intent(inout) :: d
    character(len=16) :: groups(n_deck_datasets + 1)
    real(wp) :: rows(1)
    integer(i8) :: hashes(n_deck_datasets + 1)
    integer :: id, j, k, n
    n = 0
    do id = 1, n_deck_datasets
      k = 0
      do j = 1, n   ! (gfortran's findloc on strings of two lengths does not find them)
        if (groups(j) == group_of(trim(deck_datasets(id)%path))) k = j
      end do
      if (k == 0) then
        n = n + 1
        k = n
        groups(k) = group_of(trim(deck_datasets(id)%path))
        hashes(k) = fingerprint_start()
      end if
      rows = real(size(r%fields(id)%values, 2), wp)
      if (sliced(id)) rows = real(r%sizes(deck_datasets(id)%row_symbol), wp)   ! the file's, not the block's
      call fingerprint_add(hashes(k), rows)
      if (sliced(id)) then   ! the blocks in rank order: the hash of the whole dataset
        call chain_fingerprint(r%comm, hashes(k), reshape(r%fields(id)%values, [size(r%fields(id)%values)]))
      else
        call fingerprint_add(hashes(k), reshape(r%fields(id)%values, [size(r%fields(id)%values)]))
      end if
    end do
    n = n + 1
    groups(n) = 'control'
    hashes(n) = fingerprint_start()
    call fingerprint_add(hashes(n), pack(r%control, .not. control_restart_may_change))
    d%fingerprint_groups = groups(1:n)
    d%fingerprints = real(hashes(1:n), wp)
  end subroutine fingerprint_deck

  !> Every /control attribute: presence, class, then its rules; absent ones get their defaults.
  subroutine read_control(r, d)
    type(deck_file_t), intent(inout) :: r
    type(deck_t), intent(inout) :: d
    real(wp) :: values(n_control_attributes)
    character(len=:), allocatable :: name
    logical :: have
    integer :: id
    if (.not. link_exists(r%file, '/control')) then
      r%message = 'group /control is missing; it carries the attributes end_time and output_interval'
      return
    end if
    do id = 1, n_control_attributes
      associate (spec => control_attributes(id))
        values(id) = spec%default
        if (spec%default_from > 0) values(id) = values(spec%default_from) / spec%default_divisor
        if (spec%class == class_string) then
          call read_string_attribute(r%file, '/control', trim(spec%name), name, have, r%message)
          if (status_ok_so_far(r) .and. have) then
            values(id) = real(enum_code(spec%enum, name), wp)
            if (values(id) < 0.0_wp) r%message = '/control attribute '//trim(spec%name)//' = "'//name// &
              '" is unknown: it '//trim(spec%enum_rule)//'; '//trim(spec%fix)
          end if
        else
          call read_real_attribute(r%file, '/control', trim(spec%name), values(id), values(id), spec%required, &
                                   trim(spec%fix), r%message)
          if (status_ok_so_far(r)) call check_attribute_value(id, values(id), r%message)
        end if
        if (.not. status_ok_so_far(r)) return
        call store_control(d, id, values(id))
        r%control(id) = values(id)
      end associate
    end do
  end subroutine read_control

end module deck_reader
