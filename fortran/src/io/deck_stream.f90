!> The deck as the frontend sends it on standard input (docs/formats.md, "Deck stream"), written
!> into the deck file that the engine then reads as any other. The frontend then needs no HDF5
!> library before the engine runs (docs/performance.md, "Fixed costs").
!> The stream names each dataset and attribute of the deck with its type and shape, then its bytes.
!> This module knows nothing of the schema: it writes what it is sent, as h5py would have:
!> - little-endian int32 and float64;
!> - C-order shapes;
!> - variable-length UTF-8 strings;
!> - groups made as paths need them.
!> The file is written under a temporary name and renamed when whole.
module deck_stream
  use, intrinsic :: iso_c_binding, only: c_int, c_int8_t, c_char, c_null_char, c_loc, c_ptr, c_size_t, c_long
  use hdf5
  implicit none
  private
  public :: stream_reader_t, write_streamed_deck, bad_stream

  integer, parameter :: buffer_bytes = 65536
  integer, parameter :: bad_stream = 1, unwritable = 2   !< write_streamed_deck's failures

  !> Standard input read as bytes: the first line, then the stream, without a Fortran unit's buffer
  !> taking bytes that belong to the stream.
  type :: stream_reader_t
    integer(c_int8_t) :: buffer(buffer_bytes)
    integer :: next = 1, fill = 0
    logical :: ended = .false.
  contains
    procedure :: line => read_line
    procedure :: bytes => read_bytes
  end type stream_reader_t

  interface
    function c_read(fd, buffer, count) bind(C, name='read') result(got)
      import :: c_int, c_ptr, c_size_t, c_long
      integer(c_int), value :: fd
      type(c_ptr), value :: buffer
      integer(c_size_t), value :: count
      integer(c_long) :: got
    end function c_read
    function c_rename(from, to) bind(C, name='rename') result(status)
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: from(*), to(*)
      integer(c_int) :: status
    end function c_rename
    function c_getpid() bind(C, name='getpid') result(pid)
      import :: c_int
      integer(c_int) :: pid
    end function c_getpid
  end interface

contains

  !> Reads the stream that follows the line `deck` and writes it to `path` (status 0), or says
  !> in `message` what was wrong (bad_stream or unwritable) and leaves no file.
  subroutine write_streamed_deck(input, path, status, message)
    class(stream_reader_t), intent(inout) :: input
    character(len=*), intent(in) :: path
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    character(len=:), allocatable :: temporary, header
    integer(hid_t) :: file
    integer :: err
    logical :: done
    temporary = hidden_beside(path)
    message = ''
    status = unwritable
    call h5fcreate_f(temporary, H5F_ACC_TRUNC_F, file, err)
    if (err /= 0) then
      message = 'cannot create '//temporary//'; check that the folder is writable and has space'
      return
    end if
    status = 0
    call input%line(header)
    if (header /= 'paradyn-deck-stream 1') call note_failure(status, message, bad_stream, 'it does not start with '// &
                                                               '"paradyn-deck-stream 1" but "'//header//'"')
    done = .false.
    do while (status == 0 .and. .not. done)
      call input%line(header)
      if (header == 'end') then
        done = .true.
      else if (input%ended) then
        call note_failure(status, message, bad_stream, 'it ended before its line "end" (the frontend stopped while sending it)')
      else if (index(header, 'dataset ') == 1) then
        call write_dataset(input, file, header(9:), status, message)
      else if (index(header, 'attribute ') == 1) then
        call write_attribute(input, file, header(11:), status, message)
      else
        call note_failure(status, message, bad_stream, 'unexpected line "'//header//'"')
      end if
    end do
    call h5fclose_f(file, err)
    if (status == 0 .and. err /= 0) then
      status = unwritable
      message = 'cannot write '//path//' (the disk is full or the file system failed); free space and rerun'
    end if
    if (status == 0) then
      if (c_rename(temporary//c_null_char, path//c_null_char) /= 0) then
        status = unwritable
        message = 'cannot rename '//temporary//' to '//path//'; check the folder''s permissions'
      end if
    end if
    if (status /= 0) call remove_file(temporary)
  end subroutine write_streamed_deck

  !> `dataset PATH TYPE NDIM D1 .. Dn`, then the values' bytes.
  subroutine write_dataset(input, file, fields, status, message)
    class(stream_reader_t), intent(inout) :: input
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: fields
    integer, intent(inout) :: status
    character(len=*), intent(inout) :: message
    character(len=256) :: words(11)
    integer :: n_words, rank, err, k
    integer(hsize_t) :: dims(8), values
    integer(hid_t) :: file_type, space, dataset, links
    integer(c_int8_t), allocatable, target :: bytes(:)
    type(c_ptr) :: address   ! HDF5's pointer interface takes a variable, not c_loc(...)
    call split_words(fields, words, n_words)
    err = 1
    rank = 0
    if (n_words >= 3) read (words(3), *, iostat=err) rank
    if (err == 0 .and. (rank < 1 .or. rank > size(dims) .or. n_words /= 3 + rank)) err = 1
    do k = 1, rank   ! the stream's C order, reversed into HDF5's Fortran order
      if (err == 0) read (words(3 + k), *, iostat=err) dims(rank + 1 - k)
    end do
    file_type = numeric_type(words(2))
    if (err /= 0 .or. file_type < 0 .or. any(dims(:max(rank, 1)) < 0)) then
      call note_failure(status, message, bad_stream, 'bad dataset line "dataset '//trim(fields)//'"')
      return
    end if
    values = product(dims(:rank))
    allocate (bytes(values * type_bytes(words(2))))
    call input%bytes(bytes)
    if (input%ended) then
      call note_failure(status, message, bad_stream, 'it ended inside dataset '//trim(words(1)))
      return
    end if
    call h5pcreate_f(H5P_LINK_CREATE_F, links, err)
    call h5pset_create_inter_group_f(links, 1, err)
    call h5screate_simple_f(rank, dims(:rank), space, err)
    call h5dcreate_f(file, trim(words(1)), file_type, space, dataset, k, lcpl_id=links)
    address = c_loc(bytes)
    if (k == 0 .and. values > 0) call h5dwrite_f(dataset, file_type, address, k)
    if (k /= 0) call note_failure(status, message, unwritable, 'dataset '//trim(words(1)))
    call h5dclose_f(dataset, err)
    call h5sclose_f(space, err)
    call h5pclose_f(links, err)
  end subroutine write_dataset

  !> `attribute OBJECT NAME TYPE COUNT` (0: one value, not an array), then the values: numbers as
  !> bytes, strings each as a line with its length in bytes, then its bytes.
  subroutine write_attribute(input, file, fields, status, message)
    class(stream_reader_t), intent(inout) :: input
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: fields
    integer, intent(inout) :: status
    character(len=*), intent(inout) :: message
    character(len=256) :: words(4), object, name, kind
    integer :: n_words, count, err, k
    logical :: ok
    integer(hid_t) :: file_type, space, location, attribute
    integer(c_int8_t), allocatable, target :: bytes(:)
    character(kind=c_char), allocatable, target :: text(:)
    type(c_ptr), allocatable, target :: starts(:)
    type(c_ptr) :: address   ! HDF5's pointer interface takes a variable, not c_loc(...)
    call split_words(fields, words, n_words)
    object = words(1)
    name = words(2)
    kind = words(3)
    err = 1
    if (n_words == 4) read (words(4), *, iostat=err) count
    if (err /= 0 .or. count < 0 .or. (kind /= 'string' .and. numeric_type(kind) < 0)) then
      call note_failure(status, message, bad_stream, 'bad attribute line "attribute '//trim(fields)//'"')
      return
    end if
    if (kind == 'string') then
      call read_strings(input, max(count, 1), text, starts, ok)
      if (.not. ok) then
        call note_failure(status, message, bad_stream, 'a bad string length in attribute '//trim(name)//' of '// &
                          trim(object))
        return
      end if
      call h5tcopy_f(H5T_STRING, file_type, err)   ! the Fortran API's variable-length C string
      call h5tset_cset_f(file_type, H5T_CSET_UTF8_F, err)
    else
      allocate (bytes(max(count, 1) * type_bytes(kind)))
      call input%bytes(bytes)
      call h5tcopy_f(numeric_type(kind), file_type, err)
    end if
    if (input%ended) then
      call note_failure(status, message, bad_stream, 'it ended inside attribute '//trim(name)//' of '//trim(object))
      call h5tclose_f(file_type, err)
      return
    end if
    if (count == 0) then
      call h5screate_f(H5S_SCALAR_F, space, err)
    else
      call h5screate_simple_f(1, [int(count, hsize_t)], space, err)
    end if
    call open_group(file, trim(object), location, k)
    if (k == 0) call h5acreate_f(location, trim(name), file_type, space, attribute, k)
    if (k == 0) then
      if (kind == 'string') then
        address = c_loc(starts)
      else
        address = c_loc(bytes)
      end if
      call h5awrite_f(attribute, file_type, address, k)
      call h5aclose_f(attribute, err)
    end if
    if (k /= 0) call note_failure(status, message, unwritable, 'attribute '//trim(name)//' of '//trim(object))
    if (location /= file) call h5gclose_f(location, err)
    call h5sclose_f(space, err)
    call h5tclose_f(file_type, err)
  end subroutine write_attribute

  !> `count` strings, each a line with its length in bytes and then its bytes, as C strings and
  !> the pointers HDF5 writes variable-length strings from; ok is false for a length that is not
  !> a count of bytes.
  subroutine read_strings(input, count, text, starts, ok)
    class(stream_reader_t), intent(inout) :: input
    integer, intent(in) :: count
    character(kind=c_char), allocatable, target, intent(out) :: text(:)
    type(c_ptr), allocatable, intent(out) :: starts(:)
    logical, intent(out) :: ok
    integer :: lengths(count), first(count), k, err, total
    integer(c_int8_t), allocatable :: bytes(:)
    character(len=:), allocatable :: header
    allocate (bytes(0))
    total = 0
    ok = .true.
    do k = 1, count
      call input%line(header)
      read (header, *, iostat=err) lengths(k)
      if (err /= 0 .or. lengths(k) < 0) ok = input%ended   ! the end of input is reported by the caller
      if (err /= 0 .or. lengths(k) < 0 .or. input%ended) lengths(k) = 0
      first(k) = total + 1
      bytes = [bytes, read_exactly(input, lengths(k)), 0_c_int8_t]
      total = total + lengths(k) + 1
    end do
    text = transfer(bytes, [c_null_char], size(bytes))
    allocate (starts(count))
    do k = 1, count
      starts(k) = c_loc(text(first(k)))
    end do
  end subroutine read_strings

  function read_exactly(input, n) result(bytes)
    class(stream_reader_t), intent(inout) :: input
    integer, intent(in) :: n
    integer(c_int8_t) :: bytes(max(n, 0))
    call input%bytes(bytes)
  end function read_exactly

  !> The group at `path` (made with its parents where missing); the file itself for `/`.
  subroutine open_group(file, path, group, err)
    integer(hid_t), intent(in) :: file
    character(len=*), intent(in) :: path
    integer(hid_t), intent(out) :: group
    integer, intent(out) :: err
    integer(hid_t) :: links
    logical :: exists
    group = file
    err = 0
    if (path == '/') return
    call h5lexists_f(file, path, exists, err)
    if (exists) then
      call h5gopen_f(file, path, group, err)
    else
      call h5pcreate_f(H5P_LINK_CREATE_F, links, err)
      call h5pset_create_inter_group_f(links, 1, err)
      call h5gcreate_f(file, path, group, err, lcpl_id=links)
      call h5pclose_f(links, err)
    end if
  end subroutine open_group

  !> One line without its newline; `ended` is set at the end of input (the line then holds what
  !> came before it).
  subroutine read_line(input, line)
    class(stream_reader_t), intent(inout) :: input
    character(len=:), allocatable, intent(out) :: line
    integer :: k
    line = ''
    do
      if (input%next > input%fill) call refill(input)
      if (input%ended) return
      do k = input%next, input%fill
        if (input%buffer(k) == 10_c_int8_t) exit
      end do
      line = line//transfer(input%buffer(input%next:k - 1), repeat(' ', k - input%next))
      input%next = k + 1
      if (k <= input%fill) return
    end do
  end subroutine read_line

  !> Fills `bytes` from the stream; `ended` is set if the input ends first.
  subroutine read_bytes(input, bytes)
    class(stream_reader_t), intent(inout) :: input
    integer(c_int8_t), intent(out) :: bytes(:)
    integer :: done, take
    done = 0
    do while (done < size(bytes))
      if (input%next > input%fill) call refill(input)
      if (input%ended) return
      take = min(size(bytes) - done, input%fill - input%next + 1)
      bytes(done + 1:done + take) = input%buffer(input%next:input%next + take - 1)
      input%next = input%next + take
      done = done + take
    end do
  end subroutine read_bytes

  subroutine refill(input)
    class(stream_reader_t), intent(inout), target :: input
    integer(c_long) :: got
    do
      got = c_read(0_c_int, c_loc(input%buffer), int(buffer_bytes, c_size_t))
      if (got >= 0) exit   ! -1 is an interrupted read (a signal): read again
    end do
    input%next = 1
    input%fill = int(got)
    input%ended = got == 0
  end subroutine refill

  !> The blank-separated words of `text` (list-directed input would stop at the slashes of paths).
  subroutine split_words(text, words, n)
    character(len=*), intent(in) :: text
    character(len=*), intent(out) :: words(:)
    integer, intent(out) :: n
    integer :: first, last
    n = 0
    words = ''
    last = 0
    do
      first = verify(text(last + 1:), ' ')
      if (first == 0) return
      first = last + first
      last = index(text(first:)//' ', ' ') + first - 2
      if (n == size(words)) then
        n = n + 1   ! too many: the caller's count check refuses the line
        return
      end if
      n = n + 1
      words(n) = text(first:last)
    end do
  end subroutine split_words

  integer(hid_t) function numeric_type(kind) result(file_type)
    character(len=*), intent(in) :: kind
    select case (kind)
    case ('int32')
      file_type = H5T_STD_I32LE
    case ('float64')
      file_type = H5T_IEEE_F64LE
    case default
      file_type = -1
    end select
  end function numeric_type

  integer function type_bytes(kind) result(size)
    character(len=*), intent(in) :: kind
    size = merge(4, 8, kind == 'int32')
  end function type_bytes

  !> Keeps the first failure: `what` is wrong with the stream (1) or cannot be written (2).
  subroutine note_failure(status, message, code, what)
    integer, intent(inout) :: status
    character(len=*), intent(inout) :: message
    integer, intent(in) :: code
    character(len=*), intent(in) :: what
    if (status /= 0) return
    status = code
    if (code == bad_stream) then
      message = 'the deck stream on standard input is not one the engine reads: '//what// &
                ' (docs/formats.md, "Deck stream"); use the paradyn frontend of this engine'
    else
      message = 'cannot write '//what//' of the deck (the disk is full or the file system failed); free space and rerun'
    end if
  end subroutine note_failure

  !> `.NAME.PID.tmp` in the folder of `path`.
  function hidden_beside(path) result(temporary)
    character(len=*), intent(in) :: path
    character(len=:), allocatable :: temporary
    character(len=16) :: pid
    integer :: slash
    write (pid, '(i0)') c_getpid()
    slash = index(path, '/', back=.true.)
    temporary = path(:slash)//'.'//path(slash + 1:)//'.'//trim(pid)//'.tmp'
  end function hidden_beside

  subroutine remove_file(path)
    character(len=*), intent(in) :: path
    integer :: unit, err
    open (newunit=unit, file=path, status='old', iostat=err)
    if (err == 0) close (unit, status='delete')
  end subroutine remove_file

end module deck_stream
