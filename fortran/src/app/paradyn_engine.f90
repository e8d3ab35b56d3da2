!> paradyn-engine DECK.h5 [RESULTS.h5] [--restart[=CHECKPOINT.h5]] [--check] [--expect-ranks=N] [--await-deck]
!> paradyn-engine --version
!>
!> --check sets the run up (the deck's checks, the initial penetrations, the stable step), prints
!> PARADYN-CHECK and exits without writing anything; --expect-ranks=N refuses to run on another
!> number of MPI ranks than the launcher was asked for (docs/errors.md); --await-deck starts MPI
!> and HDF5, then waits for the line `go` on standard input before it reads the deck: the
!> frontend starts the engine while it still meshes and writes DECK.h5; end of input or another
!> line ends the engine with status 0 without running.
!> Runs one deck under MPI (element partitions across ranks) and OpenMP (groups across threads) and
!> writes the results file, with a checkpoint beside it every /control checkpoint_interval and
!> when stopped by SIGTERM, SIGINT or SIGUSR1. --restart continues a run from its checkpoint.
!> Exit status (paradyn_schema, from schema/results.toml): status_ok, status_bad_input,
!> status_numerical, status_stopped (by a signal, checkpoint written), status_failure otherwise.
program paradyn_engine
  use mpi_f08
  use, intrinsic :: iso_c_binding, only: c_int
  use hdf5, only: h5open_f, h5close_f, h5eset_auto_f, h5get_libversion_f
  use paradyn_kinds, only: wp, ek, i8
  use build_info, only: build_commit, build_type, build_arch
  use paradyn_schema, only: status_ok, status_failure, status_bad_input, status_stopped, contact_gather_all, shell_element_full
  use model_deck, only: deck_t
  use deck_reader, only: read_deck
  use explicit_solver, only: solver_t, solver_setup, solver_run, record_at_stop
  use results_writer, only: results_file_t, results_create, results_reopen, results_finish, results_flush, results_failed, &
                            run_record_t
  use solver_checkpoint, only: checkpoint_write, checkpoint_read, checkpoint_path
  use stop_signals, only: install_stop_handlers
  use singleton_start, only: prefer_light_singleton, remove_session_base
  use process_environment, only: default_environment
  use run_names, only: copy_run_names
  use deck_effects, only: effects_of_deck
  use contact_checks, only: resolve_initial_penetrations
  use contact_global_rows, only: replicated_contact_deck
  use contact_parallel, only: contact_is_local
  use model_deck, only: node_row, element_row
  use, intrinsic :: iso_fortran_env, only: error_unit, input_unit, compiler_version, compiler_options
  use effect_table, only: effect_table_t, effect_list
  use machine_memory, only: node_memory_mb, deck_memory_mb, proc_kib
  use phase_timers, only: wall_clock
  implicit none

  interface
    subroutine c_exit(status) bind(C, name='exit')
      import :: c_int
      integer(c_int), value :: status
    end subroutine c_exit
    !> exit without the atexit handlers (HDF5's would crash on a file it could not close)
    subroutine c_quick_exit(status) bind(C, name='_exit')
      import :: c_int
      integer(c_int), value :: status
    end subroutine c_quick_exit
  end interface

  type(deck_t) :: deck      !< this rank's rows of the deck (model_deck)
  type(deck_t) :: contact   !< with contact: the contact parts in the global layout (contact_global_rows)
  real(wp), allocatable :: moves(:, :)   !< with contact: initial penetrations moved out (3, this rank's node rows)
  type(solver_t) :: solver
  type(results_file_t) :: results
  type(run_record_t) :: run
  type(effect_table_t) :: effects
  character(len=4096) :: deck_path, results_path, restart_path, argument
  character(len=:), allocatable :: checkpoint
  character(len=1024) :: message
  integer :: rank, n_ranks, status, err, n_args, k, n_positional, frames, records
  logical :: restart, check_only, await_deck
  integer :: expect_ranks
  real(wp) :: pause_time
  real(wp) :: engine_start = 0, setup_s = -1   !< the wall clock after MPI start-up; set-up seconds
  type(MPI_Comm) :: comm   !< the engine's own duplicate of MPI_COMM_WORLD, passed everywhere
  integer :: thread_level
  character(len=:), allocatable :: session_base   !< a one-rank run's own MPI session directory

  ! MPI is called from one thread at a time, outside the OpenMP regions: FUNNELED is enough
  call prefer_light_singleton(session_base)
  call MPI_Init_thread(MPI_THREAD_FUNNELED, thread_level)
  engine_start = wall_clock()
  call MPI_Comm_dup(MPI_COMM_WORLD, comm)
  call MPI_Comm_rank(comm, rank)
  call MPI_Comm_size(comm, n_ranks)
  if (thread_level < MPI_THREAD_FUNNELED) &
    call fail(status_failure, 'the MPI library does not support MPI_THREAD_FUNNELED, which the OpenMP threads need; '// &
              'use an MPI built with thread support (Open MPI and MPICH are)')
  ! a file system without locks (some NFS and Lustre mounts) must not stop a one-rank run, whose
  ! POSIX driver takes HDF5's lock where the file system has one
  call default_environment('HDF5_USE_FILE_LOCKING', 'BEST_EFFORT')
  call h5open_f(err)
  call h5eset_auto_f(0, err)   ! HDF5's own error stacks would bury the engine's one-line message

  call install_stop_handlers()
  n_args = command_argument_count()
  n_positional = 0
  restart = .false.
  check_only = .false.
  await_deck = .false.
  expect_ranks = 0
  restart_path = ''
  deck_path = ''
  results_path = ''
  do k = 1, n_args
    call get_command_argument(k, argument)
    if (argument == '-h' .or. argument == '--help') then
      if (rank == 0) write (*, '(a)') 'usage: paradyn-engine DECK.h5 [RESULTS.h5] [--restart[=CHECKPOINT.h5]] '// &
        '[--check] [--expect-ranks=N]', &
        'Runs a ParaDyn deck (docs/formats.md); launch it with mpirun -n RANKS and OMP_NUM_THREADS.', &
        '--restart continues an interrupted run from its checkpoint (default RESULTS.checkpoint.h5).', &
        '--check sets the run up, prints PARADYN-CHECK (the first step, the stable step, the steps) and writes nothing.', &
        '--expect-ranks=N stops with status 2 unless the launcher started N ranks.', &
        '--await-deck waits for the line go on standard input before reading the deck (end of input: exit 0).', &
        '--version names the build: commit, precision, compiler and flags, MPI and HDF5.'
      call finish(status_ok)
    else if (argument == '--restart') then
      restart = .true.
    else if (argument(1:10) == '--restart=') then
      restart = .true.
      restart_path = argument(11:)
    else if (argument == '--version') then
      call print_version()
      call finish(status_ok)
    else if (argument == '--check') then
      check_only = .true.
    else if (argument == '--await-deck') then
      await_deck = .true.
    else if (argument(1:15) == '--expect-ranks=') then
      read (argument(16:), *, iostat=err) expect_ranks
      if (err /= 0 .or. expect_ranks < 1) call fail(status_bad_input, 'bad '//trim(argument)// &
                                                    '; give --expect-ranks=N with N the number of MPI ranks launched')
    else if (argument(1:1) == '-' .or. n_positional == 2) then
      call fail(status_bad_input, 'unexpected argument '//trim(argument)// &
                '; usage: paradyn-engine DECK.h5 [RESULTS.h5] [--restart[=CHECKPOINT.h5]]')
    else
      n_positional = n_positional + 1
      if (n_positional == 1) deck_path = argument
      if (n_positional == 2) results_path = argument
    end if
  end do
  if (n_positional < 1) then
    call fail(status_bad_input, 'usage: paradyn-engine DECK.h5 [RESULTS.h5] [--restart[=CHECKPOINT.h5]] '// &
              '(results default to results.h5 beside the deck)')
  end if
  if (expect_ranks > 0 .and. expect_ranks /= n_ranks) then
    write (message, '(a,i0,a,i0,a)') 'launched on ', n_ranks, ' MPI rank(s) but --expect-ranks=', expect_ranks, &
      ' was asked for: the MPI launcher does not belong to the MPI library this engine was built with, or '// &
      'the job gave it fewer slots; launch with that MPI''s mpirun -n (or srun -n) and the same rank count'
    call fail(status_bad_input, trim(message))
  end if
  if (n_positional < 2) results_path = beside(deck_path, 'results.h5')
  checkpoint = checkpoint_path(trim(results_path))
  if (restart_path == '') restart_path = checkpoint
  if (await_deck) call await_frontend()

  ! every rank reads its rows of the deck and checks them; all reach the same verdict
  call read_deck(trim(deck_path), comm, deck, status, message)
  if (status /= status_ok) call fail(status_bad_input, trim(deck_path)//': '//trim(message))
  call check_memory(deck%n_elements, deck%n_nodes, &
                    3 * maxval(merge(deck%integration_points, 0, deck%shell_element == shell_element_full)))
  call write_deck_line()
  call effects_of_deck(deck, effects)   ! what the deck declares; the scene's switched-off effects go
  if (deck%n_contacts > 0) then   ! checked on each rank's rows
    call resolve_initial_penetrations(deck, comm, rank == 0, error_unit, moves)   ! reported; moves where asked
    ! local contact sets up from each rank's rows; one rank and the replicated scheme read the
    ! contact parts in the global layout (contact_global_rows)
    if (.not. contact_is_local(n_ranks, deck%contact_gather == contact_gather_all, deck%contact_kind)) &
      contact = replicated_contact_deck(deck, comm)
  end if
  call solver_setup(solver, deck, contact, effects, comm, status, message)
  if (status /= status_ok) call fail(status, trim(message))
  if (allocated(moves)) then
    ! initial displacements (a restart restores x)
    solver%nodes%x = solver%nodes%x + moves(:, [(node_row(deck, solver%dom%nodes(k)), k = 1, solver%dom%n_nodes)])
    deallocate (moves)
  end if
  contact = deck_t()
  if (check_only) then   ! paradyn-run --check: everything is set up and checked; nothing is written
    if (rank == 0) write (*, '(a,es23.16,a,es23.16,a,i0,a,es11.4)') 'PARADYN-CHECK dt=', solver%clock%dt, &
      ' dt_stable=', solver%clock%dt_stable, ' steps=', solver%clock%n_steps, ' end_time=', solver%clock%end_time
    flush (6)
    call finish(status_ok)
  end if

  associate (owned => solver%dom%nodes(solver%halo%owned_local), elements => solver%dom%elements)
    if (restart) then
      call checkpoint_read(solver, trim(restart_path), frames, records, status, message)
      if (status /= status_ok) call fail(status, trim(message))
      call results_reopen(trim(results_path), comm, deck%n_nodes, deck%n_elements, owned, elements, &
                          deck%n_tracked, deck%n_parts, deck%n_contacts, deck%n_rigid_walls, frames, records, results, status, &
                          message)
    else
      call results_create(trim(results_path), comm, deck%n_nodes, deck%n_elements, owned, elements, &
                          deck%coordinates(:, [(node_row(deck, owned(k)), k = 1, size(owned))]), &
                          deck%connectivity(:, [(element_row(deck, elements(k)), k = 1, size(elements))]), &
                          deck%element_part([(element_row(deck, elements(k)), k = 1, size(elements))]), &
                          solver%props(deck%element_part([(element_row(deck, elements(k)), k = 1, size(elements))]))%thickness, &
                          deck%n_tracked, deck%n_parts, deck%n_contacts, deck%n_rigid_walls, results, status, message)
      if (status == status_ok) call copy_run_names(trim(deck_path), results%file)
    end if
  end associate
  if (status /= status_ok) call fail(status, trim(message))
  ! the solver holds what the run needs from here on (its run control): release the deck's rows
  deck = deck_t()
  if (rank == 0) then
    write (*, '(a,i0,a,i0,a,i0,a,i0,a,es11.4,a,es11.4,a,es11.4,a)') 'PARADYN-START elements=', &
      solver%control%n_elements, ' nodes=', solver%control%n_nodes, ' ranks=', n_ranks, ' threads=', solver%threads, &
      ' dt=', solver%clock%dt, ' dt_stable=', solver%clock%dt_stable, ' end_time=', solver%clock%end_time, &
      ' effects='//effect_list(solver%effects, .false.)//' partition='//solver%control%partition// &
      ' precision='//solver%control%precision
    if (solver%mass_scaling_step > 0.0_wp) call write_mass_scaling_line()
    if (restart) write (*, '(a,es13.6,a,i0)') 'PARADYN-RESTART time=', solver%clock%time, ' cycle=', &
      solver%clock%cycles
    flush (6)
  end if

  do   ! run to each checkpoint time, write the checkpoint, go on
    pause_time = huge(1.0_wp)
    if (solver%control%checkpoint_interval > 0.0_wp) &
      pause_time = (floor(solver%clock%time / solver%control%checkpoint_interval + 1.0e-9_wp) + 1) &
                   * solver%control%checkpoint_interval
    call solver_run(solver, results, run, status, message, pause_time)
    if (setup_s < 0) setup_s = solver%wall_start - engine_start   ! the first call's start of the loop
    if ((solver%floor_stop .or. solver%energy_stop) .and. solver%control%checkpoint_interval > 0.0_wp) then
      ! the state is finite (the floor: the last good step; the energy limit: the record that
      ! passed it): a run with checkpoints keeps it, to look at or to restart with other settings
      call results_flush(results)
      call checkpoint_write(solver, checkpoint, results%frames, results%records, err, argument)
      if (rank == 0 .and. err == status_ok) write (*, '(a,es13.6,a,i0,a)') 'PARADYN-CHECKPOINT time=', &
        solver%clock%time, ' cycle=', solver%clock%cycles, ' path='//checkpoint
    end if
    if (solver%floor_stop) call record_at_stop(solver, results)
    if (status /= status_ok .or. solver%finished) exit
    call results_flush(results)   ! the checkpoint counts only what the results file holds
    call checkpoint_write(solver, checkpoint, results%frames, results%records, status, message)
    if (status /= status_ok) exit
    if (rank == 0) then
      write (*, '(a,es13.6,a,i0,a)') 'PARADYN-CHECKPOINT time=', solver%clock%time, ' cycle=', solver%clock%cycles, &
        ' path='//checkpoint
      flush (6)
    end if
    if (solver%stop_requested) then
      status = status_stopped
      write (message, '(a,es12.5,a)') 'stopped by a signal at time ', solver%clock%time, ' s; the checkpoint '// &
        checkpoint//' holds the state; continue with: paradyn-engine '//trim(deck_path)//' '// &
        trim(results_path)//' --restart'
      exit
    end if
  end do
  run%peak_memory_mb = largest_peak_memory_mb()
  call MPI_Bcast(setup_s, 1, MPI_DOUBLE_PRECISION, 0, comm)   ! rank 0's: attributes must agree
  run%setup_s = setup_s
  if (results_failed(results)) call stop_on_full_disk()
  call results_finish(results, run, status == status_ok)
  if (results_failed(results)) call stop_on_full_disk()   ! the end's own writes found the disk full
  if (status /= status_ok) call fail(status, trim(message))
  if (rank == 0) then
    write (*, '(a,i0,a,es13.6,a,f0.3,a,es11.4)') 'PARADYN-DONE cycles=', run%cycles, ' time=', solver%clock%time, &
      ' wall_s=', run%wall_s, ' element_cycles_per_s=', run%element_cycles_per_s
    flush (6)
  end if
  call finish(status_ok)

contains

  !> PARADYN-MASS_SCALING: the target step, the elements scaled, the added mass in all, as a
  !> fraction of the model's, and per part (comma separated, kg).
  subroutine write_mass_scaling_line()
    character(len=24) :: value
    character(len=:), allocatable :: parts
    integer :: p
    parts = ''
    do p = 1, size(solver%added_mass_part)
      write (value, '(es11.4)') solver%added_mass_part(p)
      parts = parts//merge(',', ' ', p > 1)//trim(adjustl(value))
    end do
    write (*, '(a,es11.4,a,i0,a,es11.4,a,es11.4,a)') 'PARADYN-MASS_SCALING target_dt=', solver%mass_scaling_step, &
      ' elements=', solver%scaled_elements, ' added_kg=', solver%added_mass, ' fraction=', &
      solver%added_mass / max(solver%model_mass, tiny(1.0_wp)), ' part_added_kg='//trim(adjustl(parts))
  end subroutine write_mass_scaling_line

  !> PARADYN-DECK: the mesh rows each rank read from the deck (its block: elements, nodes) and
  !> holds after the exchange (its elements, the nodes they touch, the sum of its elements' 1-based
  !> ids), rank after rank (comma separated).
  subroutine write_deck_line()
    character(len=*), parameter :: keys(5) = [character(len=17) :: 'element_rows_read', 'node_rows_read', &
                                                 'elements_held', 'nodes_held', 'element_id_sums']
    integer(i8) :: mine(5)
    integer(i8), allocatable :: all(:, :)
    character(len=:), allocatable :: line
    integer :: r, j
    mine = [int(deck%rows_read, i8), int(size(deck%element_ids), i8), int(size(deck%node_ids), i8), &
            sum(int(deck%element_ids, i8))]
    allocate (all(5, n_ranks))
    call MPI_Gather(mine, 5, MPI_INTEGER8, all, 5, MPI_INTEGER8, 0, comm)
    if (rank /= 0) return
    line = 'PARADYN-DECK'
    do j = 1, 5
      line = line//' '//trim(keys(j))//'='
      do r = 1, n_ranks
        write (argument, '(i0)') all(j, r)
        line = line//trim(merge(',', ' ', r > 1))//trim(argument)
      end do
    end do
    write (*, '(a)') line
    flush (6)
  end subroutine write_deck_line

  !> Refuses a model whose memory estimate per rank (its share of the mesh: model_deck's layout),
  !> times the ranks on this node, is beyond the node's memory, naming the estimate.
  subroutine check_memory(n_elements, n_nodes, extra_points)
    integer, intent(in) :: n_elements, n_nodes, extra_points
    type(MPI_Comm) :: node
    integer :: ranks_here
    real(wp) :: need_mb, have_mb
    character(len=256) :: text
    call MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, node)
    call MPI_Comm_size(node, ranks_here)
    call MPI_Comm_free(node)
    need_mb = ranks_here * deck_memory_mb((n_elements + n_ranks - 1) / n_ranks, (n_nodes + n_ranks - 1) / n_ranks, &
                                           extra_points)
    have_mb = node_memory_mb()
    if (have_mb <= 0.0_wp .or. need_mb <= have_mb) return
    write (text, '(a,i0,a,i0,a,i0,a,i0,a)') 'the model (', n_elements, ' elements) on ', ranks_here, &
      ' rank(s) of this node needs about ', nint(need_mb), ' MiB, more than its ', nint(have_mb), &
      ' MiB (PARADYN_MEMORY_MB, else MemTotal)'
    call fail(status_bad_input, trim(text)//'; use fewer ranks per node, more nodes, or a coarser mesh')
  end subroutine check_memory

  !> The largest peak resident set (VmHWM of /proc/self/status) over the ranks, in MiB; 0 where
  !> the system does not report it.
  real(wp) function largest_peak_memory_mb() result(largest)
    real(wp) :: mine
    mine = proc_kib('/proc/self/status', 'VmHWM:') / 1024.0_wp
    call MPI_Allreduce(mine, largest, 1, MPI_DOUBLE_PRECISION, MPI_MAX, comm)
  end function largest_peak_memory_mb

  !> HDF5 cannot close a file it cannot flush, and its clean-up at MPI_Finalize then crashes: the
  !> file holds what was written before (complete = 0), so end here with the failure status.
  subroutine stop_on_full_disk()
    if (rank == 0) write (0, '(a)') 'paradyn-engine: error: cannot write '//trim(results_path)// &
      ': the disk is full or the file system failed; the results file holds at most what was written '// &
      'before (complete = 0; it may not open); free space and rerun (or --restart from the last checkpoint)'
    flush (0)
    flush (6)
    call c_quick_exit(int(status_failure, c_int))
  end subroutine stop_on_full_disk

  !> What this engine is (rank 0 prints it): its commit and precision, the compiler and its
  !> flags, the MPI library and HDF5, one line each.
  subroutine print_version()
    character(len=MPI_MAX_LIBRARY_VERSION_STRING) :: library
    integer :: length, major, minor, release, status, line_end
    call MPI_Get_library_version(library, length)
    call h5get_libversion_f(major, minor, release, status)
    if (rank /= 0) return
    line_end = index(library(1:length), achar(10)) - 1
    if (line_end < 0) line_end = length
    write (*, '(a)') 'paradyn-engine '//build_commit//' ('//trim(merge('double', 'mixed ', ek == wp))// &
      ' precision, '//build_type//' build, arch '//build_arch//')'
    write (*, '(a)') 'compiler: '//compiler_version()
    write (*, '(a)') 'flags: '//compiler_options()
    write (*, '(a)') 'MPI: '//trim(library(1:line_end))
    write (*, '(a,i0,a,i0,a,i0)') 'HDF5: ', major, '.', minor, '.', release
    flush (6)
  end subroutine print_version

  !> Rank 0 reads the frontend's line: `go` runs the deck file it has written. The end of input,
  !> or another line, ends the engine with status 0 without running: the frontend gave up. Every
  !> rank learns the verdict.
  subroutine await_frontend()
    character(len=8) :: line
    integer :: verdict, ios   ! verdict 0: go on; -1: no run
    verdict = -1
    if (rank == 0) then
      read (input_unit, '(a)', iostat=ios) line
      if (ios == 0 .and. line == 'go') verdict = 0
    end if
    call MPI_Bcast(verdict, 1, MPI_INTEGER, 0, comm)
    if (verdict < 0) call finish(status_ok)
  end subroutine await_frontend

  function beside(path, name) result(other)
    character(len=*), intent(in) :: path, name
    character(len=len(path) + len(name)) :: other
    integer :: slash
    slash = index(path, '/', back=.true.)
    other = path(1:slash)//name
  end function beside

  subroutine fail(code, text)
    integer, intent(in) :: code
    character(len=*), intent(in) :: text
    if (rank == 0 .and. code == status_stopped) then   ! a pause with its checkpoint, not an error
      write (0, '(a)') 'paradyn-engine: '//text
    else if (rank == 0) then
      write (0, '(a)') 'paradyn-engine: error: '//text
    end if
    call finish(code)
  end subroutine fail

  subroutine finish(code)
    integer, intent(in) :: code
    call h5close_f(err)
    if (comm /= MPI_COMM_NULL) call MPI_Comm_free(comm)
    call MPI_Finalize()
    call remove_session_base(session_base)
    call c_exit(int(code, c_int))   ! the status alone, without the banner that STOP prints
  end subroutine finish

end program paradyn_engine
