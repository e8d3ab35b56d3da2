!> Checkpoints: the whole state of the time loop at the top of a step, written collectively
!> (parallel HDF5) by global node and element id, so a run restarts from it on any number of
!> ranks and threads and continues to the answer of the uninterrupted run (bitwise on the same
!> number of ranks; docs/formats.md, "Checkpoint"). The file is written beside its final name and
!> renamed once complete, so a stop during the write never leaves a half-written checkpoint.
module solver_checkpoint
  use hdf5
  use mpi_f08
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: status_ok, status_failure, status_bad_input, n_control_attributes, control_attributes, &
                            control_restart_may_change
  use solver_state, only: solver_t
  use run_control, only: run_control_t
  use nodal_effect, only: stage_corners
  use element_state, only: element_row_width, element_rows_pack, element_rows_unpack
  use contact_births, only: contact_births_restored
  use contact_checkpoint, only: contact_checkpoint_rows, contact_checkpoint_restore, contact_checkpoint_width, &
                                contact_checkpoint_sums
  use parallel_hdf5, only: row_runs, phdf5_open, phdf5_close, create_dataset, write_rows, &
                           read_rows, write_int_attribute, write_real_attribute, read_int_attribute, &
                           read_real_attribute, write_long_attribute, read_long_attribute, &
                           write_real_array_attribute, read_real_array_attribute
  implicit none
  private
  public :: checkpoint_write, checkpoint_read, checkpoint_path

  integer, parameter :: checkpoint_version = 2   !< 2: the varying step (dt_previous, ...) and 64-bit cycles
  integer, parameter :: node_width = 25   !< x, v, w (3 each), internal and external force (6 each), orientation (4)

  interface
    integer(c_int) function c_rename(old, new) bind(C, name='rename')
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old(*), new(*)
    end function c_rename
  end interface

contains

  !> results.h5 -> results.checkpoint.h5 (the checkpoint of a run lives beside its results).
  function checkpoint_path(results_path) result(path)
    character(len=*), intent(in) :: results_path
    character(len=:), allocatable :: path
    integer :: n
    n = len_trim(results_path)
    if (n > 3) then
      if (results_path(n - 2:n) == '.h5') then
        path = results_path(1:n - 3)//'.checkpoint.h5'
        return
      end if
    end if
    path = trim(results_path)//'.checkpoint.h5'
  end function checkpoint_path

  subroutine checkpoint_write(s, path, frames, records, status, message)
    type(solver_t), intent(in) :: s
    character(len=*), intent(in) :: path
    integer, intent(in) :: frames, records    !< results written so far
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer(hid_t) :: file, transfer
    integer(hsize_t) :: nn, ne, nc, nr, width
    real(wp), allocatable :: nodes(:, :), elements(:, :), contact(:, :)
    real(wp) :: contact_sums(2 + 3 * s%n_contacts)
    integer :: err, k, j
    integer, allocatable :: contact_nodes(:)
    nn = int(s%control%n_nodes, hsize_t)
    ne = int(s%control%n_elements, hsize_t)
    nr = int(s%n_ranks, hsize_t)
    width = int(element_row_width(s%control%max_points, s%elements%max_state, s%elements%thickness_words), hsize_t)
    call phdf5_open(path//'.partial', s%halo%comm, 'create', file, transfer, err)
    if (err /= 0) then
      status = status_failure
      message = 'cannot create the checkpoint '//path//'.partial; check that the folder is writable'
      return
    end if
    call write_int_attribute(file, 'paradyn_checkpoint_version', checkpoint_version)
    do j = 1, size(s%control%fingerprints)   ! the deck it belongs to, group by group
      call write_real_attribute(file, 'fingerprint_'//trim(s%control%fingerprint_groups(j)), s%control%fingerprints(j))
    end do
    call write_real_attribute(file, 'time', s%clock%time)
    ! the clock: the next step, the one before it (the velocity update takes their mean), the first
    ! (the floor's base), the fixed-step flag, the controlling element and the steps' range
    call write_real_attribute(file, 'dt', s%clock%dt)
    call write_real_attribute(file, 'dt_previous', s%clock%dt_previous)
    call write_real_attribute(file, 'dt_stable', s%clock%dt_stable)
    call write_real_attribute(file, 'dt_first', s%clock%dt_first)
    call write_real_attribute(file, 'dt_min', s%dt_min)
    call write_real_attribute(file, 'dt_max', s%dt_max)
    if (s%has_contact) call write_real_attribute(file, 'contact_soft_step', s%contact%c%soft_step)
    call write_int_attribute(file, 'fixed_step', merge(1, 0, s%clock%fixed))
    call write_long_attribute(file, 'dt_element', s%clock%controlling)
    call write_long_attribute(file, 'steps_left', s%clock%steps_left)
    call write_long_attribute(file, 'cycles', s%clock%cycles)
    call write_int_attribute(file, 'nodes', s%control%n_nodes)
    call write_int_attribute(file, 'elements', s%control%n_elements)
    call write_int_attribute(file, 'element_width', int(width))
    call write_int_attribute(file, 'ranks', s%n_ranks)
    call write_int_attribute(file, 'frames', frames)
    call write_int_attribute(file, 'records', records)
    call write_long_attribute(file, 'frame_index', s%clock%frame_index)
    call write_long_attribute(file, 'record_index', s%clock%record_index)
    call write_long_attribute(file, 'contact_last_sort', s%contact%c%last_sort)
    contact_sums = 0.0_wp
    if (s%has_contact) call contact_checkpoint_sums(s%contact, contact_sums)
    call write_real_attribute(file, 'contact_energy', contact_sums(1))
    call write_real_attribute(file, 'contact_max_penetration', contact_sums(2))
    if (s%has_contact) call write_real_array_attribute(file, 'contact_definition_force', contact_sums(3:))
    if (s%has_contact) then   ! the failed ties of tiebreak contacts (keys below 2^53: exact as float64)
      call write_real_attribute(file, 'contact_failed_tie_count', real(size(s%contact%c%failed_ties), wp))
      if (size(s%contact%c%failed_ties) > 0) &
        call write_real_array_attribute(file, 'contact_failed_ties', real(s%contact%c%failed_ties, wp))
    end if
    call write_effect_states(s, file)

    allocate (nodes(node_width, size(s%halo%owned_local)))
    do k = 1, size(s%halo%owned_local)
      j = s%halo%owned_local(k)
      nodes(:, k) = [s%nodes%x(:, j), s%nodes%v(:, j), s%nodes%w(:, j), s%nodes%f_int(:, j), s%nodes%f_ext(:, j), &
                     s%nodes%q(:, j)]
    end do
    call create_dataset(file, 'nodes', H5T_NATIVE_DOUBLE, [int(node_width, hsize_t), nn])
    call write_rows(file, transfer, 'nodes', [int(node_width, hsize_t), nn], &
                    row_runs(s%dom%nodes(s%halo%owned_local)), 0, real_values=reshape(nodes, [size(nodes)]))
    allocate (elements(width, s%dom%n_elements))
    call element_rows_pack(s%elements, s%dom, elements)
    call create_dataset(file, 'elements', H5T_NATIVE_DOUBLE, [width, ne])
    call write_rows(file, transfer, 'elements', [width, ne], row_runs(s%dom%elements), 0, &
                    real_values=reshape(elements, [size(elements)]))
    ! per-rank sums of the external and damping work (restored as they are on the same layout)
    call create_dataset(file, 'work', H5T_NATIVE_DOUBLE, [2_hsize_t, nr])
    call write_rows(file, transfer, 'work', [2_hsize_t, nr], row_runs([s%rank + 1]), 0, &
                    real_values=[s%external_work, s%damping_work])
    if (s%has_contact) then
      ! the contact state (force, position at the last sort and whether it carried a force, per
      ! contact node): each rank writes the rows of the contact nodes it owns
      nc = int(s%contact%c%n_nodes, hsize_t)
      call contact_checkpoint_rows(s%contact, contact, contact_nodes)
      call create_dataset(file, 'contact', H5T_NATIVE_DOUBLE, [int(contact_checkpoint_width, hsize_t), nc])
      call write_rows(file, transfer, 'contact', [int(contact_checkpoint_width, hsize_t), nc], &
                      row_runs(contact_nodes), 0, real_values=reshape(contact, [size(contact)]))
    end if
    call phdf5_close(file, transfer)
    call MPI_Barrier(s%halo%comm)
    status = status_ok
    message = ''
    if (s%rank == 0) then
      if (c_rename(path//'.partial'//c_null_char, path//c_null_char) /= 0) then
        status = status_failure
        message = 'cannot rename '//path//'.partial to '//path
      end if
    end if
    call MPI_Bcast(status, 1, MPI_INTEGER, 0, s%halo%comm)
  end subroutine checkpoint_write

  !> '' when the checkpoint's deck fingerprints equal this deck's, else a message naming the
  !> first group that differs (a checkpoint without them was written by an older engine).
  subroutine check_fingerprints(file, control, path, message)
    integer(hid_t), intent(in) :: file
    type(run_control_t), intent(in) :: control
    character(len=*), intent(in) :: path
    character(len=*), intent(out) :: message
    real(wp) :: stored
    integer :: k, err
    message = ''
    do k = 1, size(control%fingerprints)
      call read_real_attribute(file, 'fingerprint_'//trim(control%fingerprint_groups(k)), stored, err)
      if (err /= 0) then
        message = 'the checkpoint '//path//' does not say which deck it belongs to (an older engine wrote it); '// &
                  'rerun from the start'
      else if (stored /= control%fingerprints(k)) then
        message = 'the checkpoint '//path//' was written for another deck: its /'// &
                  trim(control%fingerprint_groups(k))//' differs from this deck''s; restart with the deck of '// &
                  'the interrupted run (a restart may change only the /control attributes '//may_change()//')'
      end if
      if (message /= '') return
    end do
  end subroutine check_fingerprints

  !> The /control attributes a restart may change (schema [deck] restart_may_change), as words.
  function may_change() result(words)
    character(len=:), allocatable :: words
    integer :: id
    words = ''
    do id = 1, n_control_attributes
      if (.not. control_restart_may_change(id)) cycle
      if (len(words) > 0) words = words//', '
      words = words//trim(control_attributes(id)%name)
    end do
  end function may_change

  !> Restores a set-up solver (solver_setup done, same deck) to the state of a checkpoint; returns
  !> the number of frames and records the results held at that point. status 2: not a checkpoint
  !> of this deck.
  subroutine checkpoint_read(s, path, frames, records, status, message)
    type(solver_t), intent(inout) :: s
    character(len=*), intent(in) :: path
    integer, intent(out) :: frames, records, status
    character(len=*), intent(out) :: message
    integer(hid_t) :: file, transfer
    integer(hsize_t) :: nn, ne, nr, width
    real(wp), allocatable :: nodes(:, :), elements(:, :), work(:, :)
    real(wp) :: dt, energy, penetration
    integer :: err, bad, version, n_nodes, n_elements, n_width, ranks, j, fixed
    integer(i8) :: last_sort
    logical :: exists
    status = status_bad_input
    inquire (file=path, exist=exists)
    if (.not. exists) then
      message = 'the checkpoint '//path//' does not exist; a run writes one when /control '// &
                'checkpoint_interval > 0 or when it is stopped by SIGTERM, SIGINT or SIGUSR1'
      return
    end if
    call phdf5_open(path, s%halo%comm, 'read', file, transfer, err)
    if (err /= 0) then
      message = 'cannot open the checkpoint '//path//' as HDF5; give the .checkpoint.h5 file of the run'
      return
    end if
    bad = 0
    call read_int_attribute(file, 'paradyn_checkpoint_version', version, err)
    bad = bad + abs(err)

    call read_int_attribute(file, 'nodes', n_nodes, err)
    bad = bad + abs(err)
    call read_int_attribute(file, 'elements', n_elements, err)
    bad = bad + abs(err)
    call read_int_attribute(file, 'element_width', n_width, err)
    bad = bad + abs(err)
    call read_real_attribute(file, 'dt', dt, err)
    bad = bad + abs(err)
    if (bad /= 0 .or. version /= checkpoint_version) then
      call phdf5_close(file, transfer)
      write (message, '(a,i0,a)') path//' is not a ParaDyn checkpoint of version ', checkpoint_version, &
        '; give the .checkpoint.h5 file written by this engine'
      return
    end if
    call check_fingerprints(file, s%control, path, message)
    if (message /= '') then
      call phdf5_close(file, transfer)
      return
    end if
    if (n_nodes /= s%control%n_nodes .or. n_elements /= s%control%n_elements .or. &
        n_width /= element_row_width(s%control%max_points, s%elements%max_state, s%elements%thickness_words)) then
      call phdf5_close(file, transfer)
      write (message, '(a,i0,a,i0,a)') 'the checkpoint '//path//' was written for another deck (', &
        n_nodes, ' nodes, ', n_elements, ' elements); restart with the deck of the interrupted run'
      return
    end if
    call read_real_attribute(file, 'time', s%clock%time, err)
    call contact_births_restored(s)
    s%clock%dt = dt
    call read_real_attribute(file, 'dt_previous', s%clock%dt_previous, err)
    call read_real_attribute(file, 'dt_stable', s%clock%dt_stable, err)
    call read_real_attribute(file, 'dt_first', s%clock%dt_first, err)
    call read_real_attribute(file, 'dt_min', s%dt_min, err)
    call read_real_attribute(file, 'dt_max', s%dt_max, err)
    call read_int_attribute(file, 'fixed_step', fixed, err)
    s%clock%fixed = fixed == 1
    call read_long_attribute(file, 'dt_element', s%clock%controlling, err)
    call read_long_attribute(file, 'steps_left', s%clock%steps_left, err)
    call read_long_attribute(file, 'cycles', s%clock%cycles, err)
    call read_int_attribute(file, 'ranks', ranks, err)
    call read_int_attribute(file, 'frames', frames, err)
    call read_int_attribute(file, 'records', records, err)
    call read_long_attribute(file, 'frame_index', s%clock%frame_index, err)
    call read_long_attribute(file, 'record_index', s%clock%record_index, err)
    call read_long_attribute(file, 'contact_last_sort', last_sort, err)
    call read_real_attribute(file, 'contact_energy', energy, err)
    call read_real_attribute(file, 'contact_max_penetration', penetration, err)

    nn = int(s%control%n_nodes, hsize_t)
    ne = int(s%control%n_elements, hsize_t)
    width = int(n_width, hsize_t)
    ! every rank reads all the nodes it holds, owned or not
    allocate (nodes(node_width, s%dom%n_nodes))
    call read_rows(file, transfer, 'nodes', [int(node_width, hsize_t), nn], row_runs(s%dom%nodes), nodes, err)
    s%nodes%x = nodes(1:3, :)
    s%nodes%v = nodes(4:6, :)
    s%nodes%w = nodes(7:9, :)
    s%nodes%f_int = nodes(10:15, :)
    s%nodes%f_ext = nodes(16:21, :)
    s%nodes%q = nodes(22:25, :)
    s%external_forces_zero = all(s%nodes%f_ext == 0.0_wp)   ! the loads stage skips only when they are
    do j = 1, size(s%nodal_effects)   ! corner members rebuild what they keep from the last positions
      associate (e => s%nodal_effects(j)%effect)
        if (.not. e%acts_at(stage_corners)) cycle
        call e%add_corner_forces(s%dom%connectivity, s%nodes%x, s%clock%time, s%corner)
        e%work = 0.0_wp
      end associate
    end do
    allocate (elements(width, s%dom%n_elements))
    call read_rows(file, transfer, 'elements', [width, ne], row_runs(s%dom%elements), elements, err)
    call element_rows_unpack(s%elements, s%dom, elements)
    nr = int(ranks, hsize_t)
    allocate (work(2, ranks))
    call read_rows(file, transfer, 'work', [2_hsize_t, nr], row_runs([(j, j = 1, ranks)]), work, err)
    if (ranks == s%n_ranks) then
      s%external_work = work(1, s%rank + 1)
      s%damping_work = work(2, s%rank + 1)
    else   ! another layout: rank 0 carries the whole sum
      s%external_work = merge(sum(work(1, :)), 0.0_wp, s%rank == 0)
      s%damping_work = merge(sum(work(2, :)), 0.0_wp, s%rank == 0)
    end if
    if (s%has_contact) then
      call read_contact_state(s, file, transfer, last_sort, energy, penetration)
    end if
    call read_effect_states(s, file)
    call phdf5_close(file, transfer)
    status = status_ok
    message = ''
  end subroutine checkpoint_read

  !> The states of the nodal effects that keep one (the same on every rank): effect_<id>_state.
  subroutine write_effect_states(s, file)
    type(solver_t), intent(in) :: s
    integer(hid_t), intent(in) :: file
    real(wp), allocatable :: words(:)
    integer :: k
    do k = 1, size(s%nodal_effects)
      words = s%nodal_effects(k)%effect%state_words()
      if (size(words) > 0) call write_real_array_attribute(file, effect_state_name(s%nodal_effects(k)%effect%id), words)
    end do
  end subroutine write_effect_states

  subroutine read_effect_states(s, file)
    type(solver_t), intent(inout) :: s
    integer(hid_t), intent(in) :: file
    real(wp), allocatable :: words(:)
    integer :: k, err
    do k = 1, size(s%nodal_effects)
      associate (e => s%nodal_effects(k)%effect)
        words = e%state_words()
        if (size(words) == 0) cycle
        call read_real_array_attribute(file, effect_state_name(e%id), words, err)
        call e%restore_state(words)
      end associate
    end do
  end subroutine read_effect_states

  function effect_state_name(id) result(name)
    integer, intent(in) :: id
    character(len=:), allocatable :: name
    character(len=12) :: text
    write (text, '(i0)') id
    name = 'effect_'//trim(text)//'_state'
  end function effect_state_name

  !> The contact's rows and its last step's force per definition.
  subroutine read_contact_state(s, file, transfer, last_sort, energy, penetration)
    type(solver_t), intent(inout) :: s
    integer(hid_t), intent(in) :: file, transfer
    integer(i8), intent(in) :: last_sort
    real(wp), intent(in) :: energy, penetration
    real(wp), allocatable :: contact(:, :), force(:)
    integer(hsize_t) :: nc
    real(wp), allocatable :: tie_keys(:)
    real(wp) :: tie_count
    integer :: err
    s%contact%c%time_step = s%clock%dt   ! the penalty's cap follows the step (time_step_control)
    call read_real_attribute(file, 'contact_soft_step', s%contact%c%soft_step, err)
    nc = int(s%contact%c%n_nodes, hsize_t)
    ! the rows of the contact nodes this rank holds (contact-node ids, ascending)
    allocate (contact(contact_checkpoint_width, size(s%contact%c%held_node)), force(3 * s%n_contacts))
    call read_rows(file, transfer, 'contact', [int(contact_checkpoint_width, hsize_t), nc], &
                   row_runs(s%contact%c%held_node), contact, err)
    call contact_checkpoint_restore(s%contact, contact, last_sort, energy, penetration)
    call read_real_array_attribute(file, 'contact_definition_force', force, err)
    s%contact%c%definition_force = reshape(force, [3, s%n_contacts])
    call read_real_attribute(file, 'contact_failed_tie_count', tie_count, err)   ! the failed ties (tiebreak)
    if (err /= 0) tie_count = 0.0_wp
    allocate (tie_keys(nint(tie_count)))
    if (size(tie_keys) > 0) call read_real_array_attribute(file, 'contact_failed_ties', tie_keys, err)
    s%contact%c%failed_ties = int(tie_keys, i8)
  end subroutine read_contact_state

end module solver_checkpoint
