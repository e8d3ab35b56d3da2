!> Writes results.h5 (docs/formats.md, version 1) collectively with parallel HDF5 (MPI-IO): every
!> rank writes the rows it owns (its owned nodes, its elements) straight into the global datasets,
!> so no field is funnelled through one rank. Frames are written one at a time, history records
!> in batches (when a batch is full and at every flush). The file is flushed at a frame once a
!> second of wall time has passed since the last flush, and at every checkpoint and the end, so a
!> run that stops early leaves a readable file whose root attribute `complete` stays 0. Every
!> call here is collective over the communicator.
module results_writer
  use hdf5
  use mpi_f08, only: MPI_Comm, MPI_Comm_rank, MPI_Bcast, MPI_Allreduce, MPI_LOGICAL, MPI_LOR, MPI_Wtime
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: status_ok, status_failure, status_bad_input, n_history_scalars, history_scalar_names, &
                            frame_field_names
  use parallel_hdf5, only: row_runs_t, row_runs, phdf5_open, phdf5_close, create_dataset, create_growing, &
                           write_rows, truncate_growing, write_int_attribute, write_real_attribute, &
                           write_long_attribute, write_long_array_attribute, read_int_attribute, &
                           write_real_array_attribute
  use run_names, only: write_string_attribute
  use effect_table, only: effect_table_t, effect_list
  use paradyn_schema, only: n_effects, effect_names, effect_timed_with, effect_also_timed_with, effect_contact
  implicit none
  private
  public :: results_file_t, results_create, results_reopen, results_write_frame, results_write_history
  public :: results_finish, results_flush, run_record_t, results_failed
  public :: node_field_width, element_field_width

  integer, parameter :: node_field_width = 12       !< results_write_frame's values per node
  integer, parameter :: element_field_width = 31    !< and per element

  integer, parameter :: history_batch = 64   !< history records written in one collective write
  !> The histories with a value per part (rank 0 writes them), in the order of the block of values
  !> results_write_history takes; then contact_force, 3 values per contact definition,
  !> rigid_wall_force, 3 values per rigid wall, reaction_force and reaction_moment, 3 values each
  character(len=*), parameter :: part_histories(4) = [character(len=21) :: 'part_kinetic_energy', &
                                                      'part_internal_energy', 'part_hourglass_energy', &
                                                      'part_plastic_work']
  !> Wall seconds between flushes at frames: a flush syncs the file to disk, which cost more than
  !> writing the frame itself when done at every frame
  real(wp), parameter :: flush_interval_s = 1.0_wp

  type :: results_file_t
    integer(hid_t) :: file = -1, transfer = -1
    integer :: n_nodes = 0, n_elements = 0, n_tracked = 0, n_parts = 0, n_contacts = 0, n_walls = 0
    integer :: frames = 0, records = 0   !< written or pending
    ! history records wait here and are written together (many small collective writes cost more
    ! than the run's frames): when the buffer is full and at every flush (checkpoint, finish)
    integer :: pending = 0
    real(wp), allocatable :: pending_values(:, :)      !< (1 + history names, history_batch)
    real(wp), allocatable :: pending_tracked(:, :, :)  !< (6, n_tracked, history_batch)
    real(wp), allocatable :: pending_parts(:, :)       !< (4 n_parts + 3 n_contacts + 3 n_walls + 3, history_batch)
    logical :: root = .false.                   !< this rank writes the history
    type(MPI_Comm) :: comm
    real(wp) :: last_flush = 0                  !< MPI_Wtime of the last flush (rank 0's decides)
    logical :: failed = .false.                 !< a write or flush failed on this rank (a full disk)
    type(row_runs_t) :: nodes, elements, tracked
  end type results_file_t

  !> What the engine reports about a run (the /run attributes).
  type :: run_record_t
    integer(i8) :: cycles = 0
    integer :: ranks = 1, threads = 1, elements = 0, nodes = 0
    real(wp) :: dt_s = 0, dt_stable_s = 0, wall_s = 0, element_cycles_per_s = 0
    real(wp) :: dt_first_s = 0, dt_stable_min_s = 0, dt_stable_max_s = 0   !< the first step; the stable step's range
    real(wp) :: added_mass_kg = 0, model_mass_kg = 0          !< mass scaling: added in all, the model's before
    real(wp), allocatable :: part_added_mass_kg(:)            !< mass scaling: added per part
    real(wp) :: phase_elements_s = 0, phase_contact_s = 0, phase_communication_s = 0
    real(wp) :: phase_output_s = 0, phase_other_s = 0
    real(wp) :: phase_contact_sort_s = 0, phase_contact_search_s = 0, phase_contact_force_s = 0
    real(wp) :: peak_memory_mb = 0   !< the largest peak resident memory of any rank (MiB)
    real(wp) :: load_imbalance = 1   !< busiest rank's element + contact time over the mean
    real(wp) :: setup_s = 0          !< rank 0's wall seconds from MPI start-up to the time loop
    real(wp) :: messages_per_step = 0, bytes_sent_per_step = 0, bytes_received_per_step = 0   !< largest of any rank
    character(len=:), allocatable :: precision   !< the engine's: "double" or "mixed"
    type(effect_table_t) :: effects  !< what ran, with its counters and rank 0's seconds
    ! per contact pair: its two parts (0-based) and the cycles it ran its stages or was idle
    integer(i8), allocatable :: pair_parts(:), pair_active_cycles(:), pair_skipped_cycles(:)
  end type run_record_t

contains

  !> Creates the file on every rank of comm. node_ids: the global nodes this rank writes
  !> (each node written by exactly one rank), ascending; element_ids: this rank's elements,
  !> ascending. coordinates, connectivity (global 1-based ids) and element_part are those rows.
  subroutine results_create(path, comm, n_nodes, n_elements, node_ids, element_ids, coordinates, &
                            connectivity, element_part, element_thickness, n_tracked, n_parts, n_contacts, n_walls, &
                            rf, status, message)
    character(len=*), intent(in) :: path
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_nodes, n_elements, node_ids(:), element_ids(:)
    real(wp), intent(in) :: coordinates(:, :), element_thickness(:)
    integer, intent(in) :: connectivity(:, :), element_part(:), n_tracked, n_parts, n_contacts, n_walls
    type(results_file_t), intent(out) :: rf
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer :: err, k
    integer(hid_t) :: group
    integer(hsize_t) :: nn, ne
    call set_rows(rf, comm, n_nodes, n_elements, node_ids, element_ids, n_tracked, n_parts, n_contacts, n_walls)
    nn = int(n_nodes, hsize_t)
    ne = int(n_elements, hsize_t)
    call phdf5_open(path, comm, 'create', rf%file, rf%transfer, err)
    if (err /= 0) then
      status = status_failure
      message = 'cannot create '//trim(path)//'; check that the folder exists and is writable'
      return
    end if
    call write_int_attribute(rf%file, 'paradyn_results_version', 1)
    call write_int_attribute(rf%file, 'complete', 0)
    call h5gcreate_f(rf%file, 'mesh', group, err)
    call create_dataset(group, 'coordinates', H5T_NATIVE_DOUBLE, [3_hsize_t, nn])
    call create_dataset(group, 'connectivity', H5T_STD_I32LE, [4_hsize_t, ne])
    call create_dataset(group, 'part', H5T_STD_I32LE, [ne])
    call create_dataset(group, 'thickness', H5T_NATIVE_DOUBLE, [ne])
    call h5gclose_f(group, err)
    call write_rows(rf%file, rf%transfer, '/mesh/coordinates', [3_hsize_t, nn], rf%nodes, 0, &
                    real_values=reshape(coordinates, [size(coordinates)]))
    call write_rows(rf%file, rf%transfer, '/mesh/connectivity', [4_hsize_t, ne], rf%elements, 0, &
                    int_values=reshape(connectivity - 1, [size(connectivity)]))
    call write_rows(rf%file, rf%transfer, '/mesh/part', [ne], rf%elements, 0, int_values=element_part - 1)
    call write_rows(rf%file, rf%transfer, '/mesh/thickness', [ne], rf%elements, 0, real_values=element_thickness)
    call h5gcreate_f(rf%file, 'frames', group, err)
    call create_growing(group, 'time', [integer(hsize_t) ::])
    call create_growing(group, 'displacement', [3_hsize_t, nn])
    call create_growing(group, 'velocity', [3_hsize_t, nn])
    call create_growing(group, 'element_membrane_stress', [3_hsize_t, ne])
    call create_growing(group, 'element_von_mises', [ne])
    call create_growing(group, 'element_plastic_strain', [ne])
    call create_growing(group, 'acceleration', [3_hsize_t, nn])
    call create_growing(group, 'nodal_contact_force', [3_hsize_t, nn])
    call create_growing(group, 'element_layer_stress', [5_hsize_t, 3_hsize_t, ne])
    call create_growing(group, 'element_membrane_strain', [3_hsize_t, ne])
    call create_growing(group, 'element_internal_energy_density', [ne])
    call create_growing(group, 'element_surface_strain', [3_hsize_t, 2_hsize_t, ne])
    call create_growing(group, 'element_thickness', [ne])
    call h5gclose_f(group, err)
    call h5gcreate_f(rf%file, 'history', group, err)
    call create_growing(group, 'time', [integer(hsize_t) ::])
    do k = 1, n_history_scalars
      call create_growing(group, trim(history_scalar_names(k)), [integer(hsize_t) ::])
    end do
    call create_growing(group, 'tracked_displacement', [3_hsize_t, int(max(n_tracked, 0), hsize_t)])
    call create_growing(group, 'tracked_velocity', [3_hsize_t, int(max(n_tracked, 0), hsize_t)])
    do k = 1, size(part_histories)
      call create_growing(group, trim(part_histories(k)), [int(n_parts, hsize_t)])
    end do
    ! no contact definition, no contact_force (a growing dataset of no columns would keep no count of records)
    if (n_contacts > 0) call create_growing(group, 'contact_force', [3_hsize_t, int(n_contacts, hsize_t)])
    if (n_walls > 0) call create_growing(group, 'rigid_wall_force', [3_hsize_t, int(n_walls, hsize_t)])
    call create_growing(group, 'reaction_force', [3_hsize_t])
    call create_growing(group, 'reaction_moment', [3_hsize_t])
    call h5gclose_f(group, err)
    call h5fflush_f(rf%file, H5F_SCOPE_GLOBAL_F, err)
    status = status_ok
    message = ''
  end subroutine results_create

  !> Reopens the results of a run for a restart: keeps the first `frames` frames and `records`
  !> history records (those written before the checkpoint), drops the rest and the /run and
  !> /effects groups.
  subroutine results_reopen(path, comm, n_nodes, n_elements, node_ids, element_ids, n_tracked, n_parts, &
                            n_contacts, n_walls, frames, records, rf, status, message)
    character(len=*), intent(in) :: path
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_nodes, n_elements, node_ids(:), element_ids(:), n_tracked, n_parts, n_contacts
    integer, intent(in) :: n_walls
    integer, intent(in) :: frames, records
    type(results_file_t), intent(out) :: rf
    integer, intent(out) :: status
    character(len=*), intent(out) :: message
    integer :: err, k, complete
    logical :: exists
    call set_rows(rf, comm, n_nodes, n_elements, node_ids, element_ids, n_tracked, n_parts, n_contacts, n_walls)
    call phdf5_open(path, comm, 'append', rf%file, rf%transfer, err)
    if (err /= 0) then
      status = status_failure
      message = 'cannot open '//trim(path)//' to continue it; a restart appends to the results of the '// &
                'interrupted run, so give the same results path'
      return
    end if
    call read_int_attribute(rf%file, 'complete', complete, err)
    if (err == 0 .and. complete == 1) then   ! a checkpoint left from before the run finished
      call phdf5_close(rf%file, rf%transfer)
      status = status_bad_input
      message = trim(path)//' holds a finished run (complete = 1); a restart continues an interrupted one: '// &
                'its checkpoint is older than the results. Run anew (paradyn-run without --restart, which '// &
                'replaces the results) to compute it again'
      return
    end if
    call write_int_attribute(rf%file, 'complete', 0)
    call h5lexists_f(rf%file, 'run', exists, err)
    if (exists) call h5ldelete_f(rf%file, 'run', err)
    call h5lexists_f(rf%file, 'effects', exists, err)
    if (exists) call h5ldelete_f(rf%file, 'effects', err)
    do k = 1, size(frame_field_names)
      call truncate_growing(rf%file, '/frames/'//trim(frame_field_names(k)), frames)
    end do
    call truncate_growing(rf%file, '/history/time', records)
    do k = 1, n_history_scalars
      call truncate_growing(rf%file, '/history/'//trim(history_scalar_names(k)), records)
    end do
    call truncate_growing(rf%file, '/history/tracked_displacement', records)
    call truncate_growing(rf%file, '/history/tracked_velocity', records)
    do k = 1, size(part_histories)
      call truncate_growing(rf%file, '/history/'//trim(part_histories(k)), records)
    end do
    if (n_contacts > 0) call truncate_growing(rf%file, '/history/contact_force', records)
    if (n_walls > 0) call truncate_growing(rf%file, '/history/rigid_wall_force', records)
    call truncate_growing(rf%file, '/history/reaction_force', records)
    call truncate_growing(rf%file, '/history/reaction_moment', records)
    rf%frames = frames
    rf%records = records
    status = status_ok
    message = ''
  end subroutine results_reopen

  !> One frame: this rank's owned nodes and elements, in the order of the ids given to
  !> results_create. node_fields (node_field_width, nodes): displacement, velocity, acceleration
  !> and contact force, 3 each; element_fields (element_field_width, elements): membrane stress (3),
  !> von Mises, plastic strain, the layer stresses (5 components x 3 layers), the membrane strain (3),
  !> the internal energy density, the bottom and top surface strains (3 x 2), the current thickness.
  subroutine results_write_frame(rf, time, node_fields, element_fields)
    type(results_file_t), intent(inout) :: rf
    real(wp), intent(in) :: time, node_fields(:, :), element_fields(:, :)
    integer(hsize_t) :: nn, ne
    nn = int(rf%n_nodes, hsize_t)
    ne = int(rf%n_elements, hsize_t)
    rf%frames = rf%frames + 1
    call append_root(rf, '/frames/time', [time], [integer(hsize_t) ::], rf%frames)
    call frame_rows('/frames/displacement', [3_hsize_t, nn], rf%nodes, node_fields(1:3, :))
    call frame_rows('/frames/velocity', [3_hsize_t, nn], rf%nodes, node_fields(4:6, :))
    call frame_rows('/frames/acceleration', [3_hsize_t, nn], rf%nodes, node_fields(7:9, :))
    call frame_rows('/frames/nodal_contact_force', [3_hsize_t, nn], rf%nodes, node_fields(10:12, :))
    call frame_rows('/frames/element_membrane_stress', [3_hsize_t, ne], rf%elements, element_fields(1:3, :))
    call frame_rows('/frames/element_von_mises', [ne], rf%elements, element_fields(4:4, :))
    call frame_rows('/frames/element_plastic_strain', [ne], rf%elements, element_fields(5:5, :))
    call frame_rows('/frames/element_layer_stress', [5_hsize_t, 3_hsize_t, ne], rf%elements, element_fields(6:20, :))
    call frame_rows('/frames/element_membrane_strain', [3_hsize_t, ne], rf%elements, element_fields(21:23, :))
    call frame_rows('/frames/element_internal_energy_density', [ne], rf%elements, element_fields(24:24, :))
    call frame_rows('/frames/element_surface_strain', [3_hsize_t, 2_hsize_t, ne], rf%elements, element_fields(25:30, :))
    call frame_rows('/frames/element_thickness', [ne], rf%elements, element_fields(31:31, :))
    ! the history waits for a full batch or a flush: a write per frame cost more than the frame
    if (flush_due(rf)) call results_flush(rf)
  contains
    subroutine frame_rows(name, fixed, runs, values)
      character(len=*), intent(in) :: name
      integer(hsize_t), intent(in) :: fixed(:)
      type(row_runs_t), intent(in) :: runs
      real(wp), intent(in) :: values(:, :)
      call write_rows(rf%file, rf%transfer, name, fixed, runs, rf%frames, real_values=reshape(values, [size(values)]), &
                      failed=rf%failed)
    end subroutine frame_rows
  end subroutine results_write_frame

  !> values: kinetic, internal, hourglass and contact energy, external work, deepest contact
  !> penetration. Collective; the values of rank 0 are written.
  subroutine results_write_history(rf, time, values, tracked_displacement, tracked_velocity, part_values)
    type(results_file_t), intent(inout) :: rf
    real(wp), intent(in) :: time, values(n_history_scalars)
    real(wp), intent(in) :: tracked_displacement(:, :), tracked_velocity(:, :)
    real(wp), intent(in) :: part_values(:)   !< the part_histories in turn, contact_force, rigid_wall_force, reaction_force, reaction_moment
    if (.not. allocated(rf%pending_values)) then
      allocate (rf%pending_values(1 + n_history_scalars, history_batch))
      allocate (rf%pending_tracked(6, rf%n_tracked, history_batch))
      allocate (rf%pending_parts(size(part_histories) * rf%n_parts + 3 * rf%n_contacts + 3 * rf%n_walls + 6, &
                                 history_batch))
    end if
    rf%records = rf%records + 1
    rf%pending = rf%pending + 1
    rf%pending_values(:, rf%pending) = [time, values]
    rf%pending_tracked(1:3, :, rf%pending) = tracked_displacement
    rf%pending_tracked(4:6, :, rf%pending) = tracked_velocity
    rf%pending_parts(:, rf%pending) = part_values
    if (rf%pending == history_batch) call write_pending(rf)
  end subroutine results_write_history

  !> Writes the pending history records and flushes the file (collective).
  subroutine results_flush(rf)
    type(results_file_t), intent(inout) :: rf
    call write_pending(rf)
    call flush_file(rf)
  end subroutine results_flush

  subroutine flush_file(rf)
    type(results_file_t), intent(inout) :: rf
    integer :: err
    call h5fflush_f(rf%file, H5F_SCOPE_GLOBAL_F, err)
    if (err /= 0) rf%failed = .true.
    rf%last_flush = MPI_Wtime()
  end subroutine flush_file

  !> Whether a write failed on any rank since the file was opened (collective): the disk is full or
  !> the file system failed, and the run must stop with what the file holds so far.
  logical function results_failed(rf)
    type(results_file_t), intent(in) :: rf
    logical :: mine
    mine = rf%failed
    call MPI_Allreduce(mine, results_failed, 1, MPI_LOGICAL, MPI_LOR, rf%comm)
  end function results_failed

  !> Rank 0's clock decides, so that every rank makes the same collective call.
  logical function flush_due(rf)
    type(results_file_t), intent(in) :: rf
    flush_due = MPI_Wtime() - rf%last_flush >= flush_interval_s
    call MPI_Bcast(flush_due, 1, MPI_LOGICAL, 0, rf%comm)
  end function flush_due

  !> Writes the history records that wait in the buffer (collective).
  subroutine write_pending(rf)
    type(results_file_t), intent(inout) :: rf
    integer :: k, first, n
    integer(hsize_t) :: nt
    n = rf%pending
    if (n > 0) then
      first = rf%records - n + 1
      nt = int(rf%n_tracked, hsize_t)
      call append_root(rf, '/history/time', rf%pending_values(1, 1:n), [integer(hsize_t) ::], first, n)
      do k = 1, n_history_scalars
        call append_root(rf, '/history/'//trim(history_scalar_names(k)), rf%pending_values(1 + k, 1:n), &
                         [integer(hsize_t) ::], first, n)
      end do
      call write_rows(rf%file, rf%transfer, '/history/tracked_displacement', [3_hsize_t, nt], rf%tracked, &
                      first, real_values=reshape(rf%pending_tracked(1:3, :, 1:n), [3 * rf%n_tracked * n]), &
                      n_frames=n, failed=rf%failed)
      call write_rows(rf%file, rf%transfer, '/history/tracked_velocity', [3_hsize_t, nt], rf%tracked, &
                      first, real_values=reshape(rf%pending_tracked(4:6, :, 1:n), [3 * rf%n_tracked * n]), &
                      n_frames=n, failed=rf%failed)
      call write_pending_parts(rf, first, n)
      rf%pending = 0
    end if
  end subroutine write_pending

  !> The pending per-part histories, contact, wall and reaction forces and the reaction moment (rank 0's values; none when
  !> the model has no part, contact definition or wall).
  subroutine write_pending_parts(rf, first, n)
    type(results_file_t), intent(inout) :: rf
    integer, intent(in) :: first, n
    integer :: k, np, at
    np = rf%n_parts
    do k = 1, size(part_histories)
      if (np > 0) call append_root(rf, '/history/'//trim(part_histories(k)), &
                                   reshape(rf%pending_parts((k - 1) * np + 1:k * np, 1:n), [np * n]), &
                                   [int(np, hsize_t)], first, n)
    end do
    at = size(part_histories) * np
    if (rf%n_contacts > 0) call append_root(rf, '/history/contact_force', &
                                            reshape(rf%pending_parts(at + 1:at + 3 * rf%n_contacts, 1:n), &
                                                    [3 * rf%n_contacts * n]), &
                                            [3_hsize_t, int(rf%n_contacts, hsize_t)], first, n)
    at = at + 3 * rf%n_contacts
    if (rf%n_walls > 0) call append_root(rf, '/history/rigid_wall_force', &
                                         reshape(rf%pending_parts(at + 1:at + 3 * rf%n_walls, 1:n), &
                                                 [3 * rf%n_walls * n]), &
                                         [3_hsize_t, int(rf%n_walls, hsize_t)], first, n)
    at = at + 3 * rf%n_walls
    call append_root(rf, '/history/reaction_force', reshape(rf%pending_parts(at + 1:at + 3, 1:n), [3 * n]), &
                     [3_hsize_t], first, n)
    call append_root(rf, '/history/reaction_moment', reshape(rf%pending_parts(at + 4:at + 6, 1:n), [3 * n]), &
                     [3_hsize_t], first, n)
  end subroutine write_pending_parts

  !> Writes the /run attributes (the same record on every rank), marks the file complete when
  !> asked, and closes it.
  subroutine results_finish(rf, run, complete)
    type(results_file_t), intent(inout) :: rf
    type(run_record_t), intent(in) :: run
    logical, intent(in) :: complete
    integer(hid_t) :: group
    integer :: err
    call results_flush(rf)
    if (results_failed(rf)) then   ! a full disk: keep what was written, add nothing, close
      call phdf5_close(rf%file, rf%transfer)
      return
    end if
    call h5gcreate_f(rf%file, 'run', group, err)
    call write_long_attribute(group, 'cycles', run%cycles)
    call write_int_attribute(group, 'ranks', run%ranks)
    call write_int_attribute(group, 'threads', run%threads)
    call write_int_attribute(group, 'elements', run%elements)
    call write_int_attribute(group, 'nodes', run%nodes)
    call write_real_attribute(group, 'dt_s', run%dt_s)
    call write_real_attribute(group, 'dt_stable_s', run%dt_stable_s)
    call write_real_attribute(group, 'dt_first_s', run%dt_first_s)
    call write_real_attribute(group, 'dt_stable_min_s', run%dt_stable_min_s)
    call write_real_attribute(group, 'dt_stable_max_s', run%dt_stable_max_s)
    call write_real_attribute(group, 'added_mass_kg', run%added_mass_kg)
    call write_real_attribute(group, 'model_mass_kg', run%model_mass_kg)
    call write_real_attribute(group, 'added_mass_fraction', run%added_mass_kg / max(run%model_mass_kg, tiny(1.0_wp)))
    if (allocated(run%part_added_mass_kg)) call write_real_array_attribute(group, 'part_added_mass_kg', &
                                                                           run%part_added_mass_kg)
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
    call write_real_attribute(group, 'peak_memory_per_rank_mb', run%peak_memory_mb)
    call write_real_attribute(group, 'load_imbalance', run%load_imbalance)
    call write_real_attribute(group, 'setup_s', run%setup_s)
    call write_real_attribute(group, 'messages_per_step', run%messages_per_step)
    call write_real_attribute(group, 'bytes_sent_per_step', run%bytes_sent_per_step)
    call write_real_attribute(group, 'bytes_received_per_step', run%bytes_received_per_step)
    if (allocated(run%precision)) call write_string_attribute(group, 'precision', run%precision)
    call write_string_attribute(group, 'effects', effect_list(run%effects, .false.))
    call write_string_attribute(group, 'effects_off', effect_list(run%effects, .true.))
    call h5gclose_f(group, err)
    call write_effect_table(rf%file, run)
    if (complete) call write_int_attribute(rf%file, 'complete', 1)
    call flush_file(rf)   ! a disk that fills now leaves the file open: results_failed says so
    if (results_failed(rf)) return
    call phdf5_close(rf%file, rf%transfer)
  end subroutine results_finish

  !> The group /effects: one subgroup per effect the deck declares, in the order of the step, with
  !> its state ("on", or "off" where the scene switched it off), active and skipped cycles, wall
  !> seconds, and the effect whose seconds include it ("" where timed alone).
  subroutine write_effect_table(file, run)
    integer(hid_t), intent(in) :: file
    type(run_record_t), intent(in) :: run
    integer(hid_t) :: effects, row
    integer :: k, err
    call h5gcreate_f(file, 'effects', effects, err)
    do k = 1, n_effects
      if (.not. run%effects%declared(k)) cycle
      call h5gcreate_f(effects, trim(effect_names(k)), row, err)
      call write_string_attribute(row, 'state', trim(merge('on ', 'off', run%effects%running(k))))
      call write_long_attribute(row, 'active_cycles', run%effects%active(k))
      call write_long_attribute(row, 'skipped_cycles', run%effects%skipped(k))
      call write_real_attribute(row, 'wall_s', run%effects%seconds(k))
      call write_string_attribute(row, 'timed_with', timed_with(run%effects, k))
      call write_long_attribute(row, 'order', int(k, i8))
      if (k == effect_contact .and. allocated(run%pair_parts)) then   ! each pair: its parts and cycles
        call write_long_array_attribute(row, 'pair_parts', run%pair_parts)
        call write_long_array_attribute(row, 'pair_active_cycles', run%pair_active_cycles)
        call write_long_array_attribute(row, 'pair_skipped_cycles', run%pair_skipped_cycles)
      end if
      call h5gclose_f(row, err)
    end do
    call h5gclose_f(effects, err)
  end subroutine write_effect_table

  !> The declared effects whose seconds include effect k's, joined by "+" ("" where timed alone).
  pure function timed_with(table, k) result(owners)
    type(effect_table_t), intent(in) :: table
    integer, intent(in) :: k
    character(len=:), allocatable :: owners
    integer :: owner(2), j
    owners = ''
    owner = [effect_timed_with(k), effect_also_timed_with(k)]
    do j = 1, 2
      if (owner(j) == 0) cycle
      if (.not. table%declared(owner(j))) cycle
      if (len(owners) > 0) owners = owners//'+'
      owners = owners//trim(effect_names(owner(j)))
    end do
  end function timed_with

  ! ---------------------------------------------------------------- plumbing

  !> The rows this rank writes: its owned nodes and its elements; rank 0 the tracked nodes.
  subroutine set_rows(rf, comm, n_nodes, n_elements, node_ids, element_ids, n_tracked, n_parts, n_contacts, n_walls)
    type(results_file_t), intent(inout) :: rf
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_nodes, n_elements, node_ids(:), element_ids(:), n_tracked, n_parts, n_contacts, n_walls
    integer :: rank, k
    call MPI_Comm_rank(comm, rank)
    rf%root = rank == 0
    rf%comm = comm
    rf%last_flush = MPI_Wtime()
    rf%n_nodes = n_nodes
    rf%n_elements = n_elements
    rf%n_tracked = n_tracked
    rf%n_parts = n_parts
    rf%n_contacts = n_contacts
    rf%n_walls = n_walls
    rf%nodes = row_runs(node_ids)
    rf%elements = row_runs(element_ids)
    rf%tracked = row_runs(pack([(k, k = 1, n_tracked)], rf%root))
  end subroutine set_rows

  !> Appends entry `index` of a growing dataset whose whole entry rank 0 writes.
  subroutine append_root(rf, name, values, fixed, index, count)
    type(results_file_t), intent(inout) :: rf
    character(len=*), intent(in) :: name
    real(wp), intent(in) :: values(:)
    integer(hsize_t), intent(in) :: fixed(:)
    integer, intent(in) :: index
    integer, intent(in), optional :: count   !< entries index, index + 1, ... (default 1)
    integer :: n
    n = 1
    if (present(count)) n = count
    ! the entry is the single row of a dataset of shape [fixed, 1]
    call write_rows(rf%file, rf%transfer, name, [fixed, 1_hsize_t], row_runs(pack([1], rf%root)), index, &
                    real_values=values, frame_is_row=.true., n_frames=n, failed=rf%failed)
  end subroutine append_root

end module results_writer
