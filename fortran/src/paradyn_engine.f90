!> paradyn-engine DECK.h5 [RESULTS.h5]
!>
!> Runs one deck under MPI (element partitions across ranks) and OpenMP (groups across threads) and
!> writes the results file. Exit status: 0 done, 2 bad input, 3 numerical failure, 1 otherwise.
program paradyn_engine
  use mpi_f08
  use hdf5, only: h5open_f, h5close_f
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t, partition_label
  use deck_reader, only: read_deck
  use explicit_solver, only: solver_t, solver_setup, solver_run, solver_effects
  use results_writer, only: results_file_t, results_create, results_finish, run_record_t
  implicit none

  type(deck_t) :: deck
  type(solver_t) :: solver
  type(results_file_t) :: results
  type(run_record_t) :: run
  character(len=4096) :: deck_path, results_path
  character(len=1024) :: message
  integer :: rank, n_ranks, status, err, n_args

  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  call MPI_Comm_size(MPI_COMM_WORLD, n_ranks)
  call h5open_f(err)

  n_args = command_argument_count()
  if (n_args < 1 .or. n_args > 2) then
    call fail(2, 'usage: paradyn-engine DECK.h5 [RESULTS.h5] (results default to results.h5 beside the deck)')
  end if
  call get_command_argument(1, deck_path)
  if (deck_path == '-h' .or. deck_path == '--help') then
    if (rank == 0) write (*, '(a)') 'usage: paradyn-engine DECK.h5 [RESULTS.h5]', &
      'Runs a ParaDyn deck (docs/formats.md); launch it with mpirun -n RANKS and OMP_NUM_THREADS.'
    call finish(0)
  end if
  if (n_args == 2) then
    call get_command_argument(2, results_path)
  else
    results_path = beside(deck_path, 'results.h5')
  end if

  ! every rank reads and checks the deck; all reach the same verdict
  call read_deck(trim(deck_path), deck, status, message)
  if (status /= 0) call fail(2, trim(deck_path)//': '//trim(message))
  call solver_setup(solver, deck, MPI_COMM_WORLD, status, message)
  if (status /= 0) call fail(status, trim(message))

  if (rank == 0) then
    call results_create(trim(results_path), deck%coordinates, deck%connectivity, deck%element_part, &
                        deck%n_tracked, results, status, message)
    write (*, '(a,i0,a,i0,a,i0,a,i0,a,es11.4,a,es11.4,a,es11.4,a)') 'PARADYN-START elements=', &
      deck%n_elements, ' nodes=', deck%n_nodes, ' ranks=', n_ranks, ' threads=', solver%threads, &
      ' dt=', solver%dt, ' dt_stable=', solver%dt_stable, ' end_time=', deck%end_time, &
      ' effects='//solver_effects(deck)//' partition='//partition_label(deck%partition)
    flush (6)
  end if
  call MPI_Bcast(status, 1, MPI_INTEGER, 0, MPI_COMM_WORLD)
  if (status /= 0) call fail(1, trim(message))

  call solver_run(solver, deck, results, run, status, message)
  if (rank == 0) call results_finish(results, run, status == 0)
  if (status /= 0) call fail(status, trim(message))
  if (rank == 0) then
    write (*, '(a,i0,a,es13.6,a,f0.3,a,es11.4)') 'PARADYN-DONE cycles=', run%cycles, ' time=', solver%time, &
      ' wall_s=', run%wall_s, ' element_cycles_per_s=', run%element_cycles_per_s
    flush (6)
  end if
  call finish(0)

contains

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
    if (rank == 0) write (0, '(a)') 'paradyn-engine: error: '//text
    call finish(code)
  end subroutine fail

  subroutine finish(code)
    integer, intent(in) :: code
    call h5close_f(err)
    call MPI_Finalize()
    if (code == 0) stop
    stop code, quiet=.true.
  end subroutine finish

end program paradyn_engine
