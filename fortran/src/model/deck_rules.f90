!> The value rules of the deck schema (paradyn_schema's tables), applied to one dataset or one
!> /control attribute at a time: finiteness, bounds, enum codes and index ranges. The reader
!> calls them with the values as the file holds them (0-based indices), so that the messages name
!> the entries as a user sees them. Pure: no MPI, no HDF5.
module deck_rules
  use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
  use paradyn_kinds, only: wp
  use paradyn_schema, only: deck_datasets, control_attributes, deck_conditions, dataset_spec_t, &
                            attribute_spec_t, class_int, class_float, size_none, size_entity, condition_none
  implicit none
  private
  public :: check_field_values, check_attribute_value, selected_rows, condition_rows, within_bounds, &
            number_text, integer_text, index_list

contains

  !> Rows whose values are checked: all, or those where the spec's checked_when condition holds
  !> (the condition's dataset, given as `condition_values`, holds one of the condition's codes there).
  pure function selected_rows(id, rows, condition_values) result(selected)
    integer, intent(in) :: id, rows
    real(wp), intent(in) :: condition_values(:, :)
    logical :: selected(rows)
    integer :: condition
    condition = deck_datasets(id)%checked_when
    selected = .true.
    if (condition == condition_none) return
    if (deck_conditions(condition)%dataset == 0) return
    selected = condition_rows(condition, condition_values(1, 1:rows))
  end function selected_rows

  !> Where a dataset condition holds: the entries of its dataset (values) equal to one of its codes.
  pure function condition_rows(condition, values) result(holds)
    integer, intent(in) :: condition
    real(wp), intent(in) :: values(:)
    logical :: holds(size(values))
    integer :: k
    holds = .false.
    do k = 1, deck_conditions(condition)%n_codes
      holds = holds .or. values == real(deck_conditions(condition)%codes(k), wp)
    end do
  end function condition_rows

  !> Checks every selected entry of dataset `id` (values: (max(columns, 1), rows), as in the file,
  !> or the rows first_row + 1 .. of it when first_row is given). sizes: the count of each row
  !> symbol, for index references. An empty message means valid; else bad_row is the 1-based row
  !> of the file it names.
  pure subroutine check_field_values(id, values, sizes, selected, message, first_row, bad_row)
    integer, intent(in) :: id
    real(wp), intent(in) :: values(:, :)
    integer, intent(in) :: sizes(:)
    logical, intent(in) :: selected(:)
    character(len=*), intent(out) :: message
    integer, intent(in), optional :: first_row
    integer, intent(out), optional :: bad_row
    type(dataset_spec_t) :: spec
    integer :: row, column, upper, offset, lowest
    message = ''
    offset = 0
    if (present(first_row)) offset = first_row
    if (present(bad_row)) bad_row = huge(1)
    spec = deck_datasets(id)
    do row = 1, size(values, 2)
      if (.not. selected(row)) cycle
      do column = 1, size(values, 1)
        associate (v => values(column, row))
          ! the words are built only for a bad entry: internal writes would cost more than the checks
          if (spec%class == class_float .and. .not. ieee_is_finite(v)) then
            message = entry_text(spec, offset + row, column, v)//' must be finite'//rows_text(spec)//'; '//trim(spec%fix)
          else if (.not. within_bounds(v, spec%has_lower, spec%lower_inclusive, spec%lower, &
                                       spec%has_upper, spec%upper_inclusive, spec%upper)) then
            message = entry_text(spec, offset + row, column, v)//' '//trim(spec%rule)//rows_text(spec)//'; '//trim(spec%fix)
          else if (spec%n_codes > 0) then
            if (.not. any(real(spec%codes(1:spec%n_codes), wp) == v)) &
              message = entry_text(spec, offset + row, column, v)//' '//trim(spec%enum_rule)//'; '//trim(spec%fix)
          else if (spec%reference /= size_none) then
            upper = sizes(spec%reference)
            lowest = 0
            if (spec%has_lower .and. spec%lower == -1.0_wp) lowest = -1   ! -1 names none
            if (v < real(lowest, wp) .or. v >= real(upper, wp)) message = entry_text(spec, offset + row, column, v)// &
              ' is out of range '//integer_text(lowest)//'..'//integer_text(upper - 1)//'; '// &
              trim(size_entity(spec%reference))// &
              ' indices are 0-based and must be below the number of '//trim(size_entity(spec%reference))// &
              's ('//integer_text(upper)//')'
          end if
        end associate
        ! a message starts with its dataset's path; len_trim would scan the whole buffer per entry
        if (message(1:1) /= ' ') then
          if (present(bad_row)) bad_row = offset + row
          return
        end if
      end do
    end do
  end subroutine check_field_values

  !> Checks a numeric /control attribute against its spec; an empty message means valid.
  pure subroutine check_attribute_value(id, value, message)
    integer, intent(in) :: id
    real(wp), intent(in) :: value
    character(len=*), intent(out) :: message
    type(attribute_spec_t) :: spec
    message = ''
    spec = control_attributes(id)
    if (spec%class /= class_float) return
    if (.not. ieee_is_finite(value)) then
      message = '/control attribute '//trim(spec%name)//' = '//number_text(value, class_float)// &
                ' must be finite; '//trim(spec%fix)
    else if (.not. within_bounds(value, spec%has_lower, spec%lower_inclusive, spec%lower, &
                                 spec%has_upper, spec%upper_inclusive, spec%upper)) then
      message = '/control attribute '//trim(spec%name)//' = '//number_text(value, class_float)//' '// &
                trim(spec%rule)//'; '//trim(spec%fix)
    end if
  end subroutine check_attribute_value

  pure logical function within_bounds(v, has_lower, lower_inclusive, lower, has_upper, upper_inclusive, upper)
    real(wp), intent(in) :: v, lower, upper
    logical, intent(in) :: has_lower, lower_inclusive, has_upper, upper_inclusive
    within_bounds = .true.
    if (has_lower) then
      if (lower_inclusive) then
        within_bounds = v >= lower
      else
        within_bounds = v > lower
      end if
    end if
    if (has_upper .and. within_bounds) then
      if (upper_inclusive) then
        within_bounds = v <= upper
      else
        within_bounds = v < upper
      end if
    end if
  end function within_bounds

  !> `/path[row] = value` or `/path[row, column] = value`, 0-based as in the file.
  pure function entry_text(spec, row, column, v) result(words)
    type(dataset_spec_t), intent(in) :: spec
    integer, intent(in) :: row, column
    real(wp), intent(in) :: v
    character(len=:), allocatable :: words
    if (spec%columns > 0) then
      words = trim(spec%path)//'['//integer_text(row - 1)//', '//integer_text(column - 1)//'] = '
    else
      words = trim(spec%path)//'['//integer_text(row - 1)//'] = '
    end if
    words = words//number_text(v, spec%class)
  end function entry_text

  pure function rows_text(spec) result(words)
    type(dataset_spec_t), intent(in) :: spec
    character(len=:), allocatable :: words
    words = ''
    if (spec%checked_when /= condition_none) words = ' '//trim(deck_conditions(spec%checked_when)%rows)
  end function rows_text

  !> A value as the file holds it, as the frontend prints it (Python's %.6g): an integer, or a
  !> real with at most 6 significant digits and no trailing zeros (-1, 0.0015, 2.5E+11).
  pure function number_text(v, class) result(words)
    real(wp), intent(in) :: v
    integer, intent(in) :: class
    character(len=:), allocatable :: words
    character(len=40) :: buffer
    integer :: mark
    if (.not. ieee_is_finite(v)) then   ! first: a comparison with NaN traps in a Debug build
      write (buffer, '(es12.5)') v
      words = trim(adjustl(buffer))
    else if (class == class_int .and. abs(v) < 2.0e9_wp) then
      words = integer_text(nint(v))
    else if (v == 0.0_wp) then
      words = '0'
    else if (abs(v) >= 1.0e-4_wp .and. abs(v) < 1.0e6_wp) then
      ! 6 significant digits: as many decimals as the magnitude leaves
      write (buffer, '(f0.'//integer_text(max(0, 5 - floor(log10(abs(v)))))//')') v
      words = without_trailing_zeros(trim(adjustl(buffer)))
      if (words(1:1) == '.') words = '0'//words
      if (words(1:2) == '-.') words = '-0'//words(2:)
    else
      write (buffer, '(es13.5e3)') v
      buffer = adjustl(buffer)
      mark = index(buffer, 'E')
      words = without_trailing_zeros(buffer(1:mark - 1))//'E'//buffer(mark + 1:mark + 1)// &
              integer_text(abs(exponent_of(buffer(mark + 2:))))
    end if
  end function number_text

  !> `1.500000` -> `1.5`, `2.000` -> `2`; text without a decimal point is left alone.
  pure function without_trailing_zeros(text) result(words)
    character(len=*), intent(in) :: text
    character(len=:), allocatable :: words
    integer :: last
    words = text
    if (index(words, '.') == 0) return
    last = len(words)
    do while (last > 1 .and. words(last:last) == '0')
      last = last - 1
    end do
    if (words(last:last) == '.') last = last - 1
    words = words(1:last)
  end function without_trailing_zeros

  pure integer function exponent_of(digits)
    character(len=*), intent(in) :: digits
    read (digits, *) exponent_of
  end function exponent_of

  pure function integer_text(i) result(words)
    integer, intent(in) :: i
    character(len=:), allocatable :: words
    character(len=16) :: buffer
    write (buffer, '(i0)') i
    words = trim(buffer)
  end function integer_text

  !> `[a, b, ...]` of 1-based indices, shown 0-based as in the file.
  pure function index_list(indices) result(words)
    integer, intent(in) :: indices(:)
    character(len=:), allocatable :: words
    integer :: k
    words = '['
    do k = 1, size(indices)
      if (k > 1) words = words//', '
      words = words//integer_text(indices(k) - 1)
    end do
    words = words//']'
  end function index_list

end module deck_rules
