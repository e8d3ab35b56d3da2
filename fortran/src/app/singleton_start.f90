!> Start-up of a rank started without a launcher (`paradyn-engine deck.h5`, the frontend's direct
!> runner): Open MPI would otherwise fork a supporting daemon and probe every network library,
!> 0.3 s of a run whose time loop may take less (docs/performance.md, "Fixed costs"). Before
!> MPI_Init, and only when no launcher set the environment, ask for no daemon (the engine never
!> spawns processes), for the ob1 messaging layer (one process has no network to probe), and
!> for hwloc's topology without its I/O devices (HWLOC_COMPONENTS=-pci,-linuxio: reading every PCI
!> device's configuration took 13 of the 36 ms that MPI_Init and the libraries cost here; the
!> engine binds no network card and places no thread by PCI locality).
!> Without a daemon every such process takes the same job id, so each gets a session directory of
!> its own (two engines sharing one would remove it under each other's feet); it is removed after
!> MPI_Finalize. Settings the user made win; other MPIs ignore these names.
module singleton_start
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_ptr, c_associated
  use process_environment, only: default_environment
  implicit none
  private
  public :: prefer_light_singleton, remove_session_base

  ! what mpirun / srun (PMI, PMIx) set in every rank's environment
  character(len=*), parameter :: launcher_variables(4) = [character(len=20) :: &
    'OMPI_COMM_WORLD_SIZE', 'PMIX_RANK', 'PMI_RANK', 'PMI_SIZE']
  character(len=*), parameter :: hwloc_without_io = '-pci,-linuxio'   !< hwloc's component list

  interface
    function c_mkdtemp(template) bind(C, name='mkdtemp') result(path)
      import :: c_char, c_ptr
      character(kind=c_char), intent(inout) :: template(*)
      type(c_ptr) :: path
    end function c_mkdtemp
    function c_rmdir(path) bind(C, name='rmdir') result(status)
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int) :: status
    end function c_rmdir
  end interface

contains

  !> session_base: the private session directory made here ('' when none was made: a launcher
  !> started this rank, or the user chose the settings).
  subroutine prefer_light_singleton(session_base)
    character(len=:), allocatable, intent(out) :: session_base
    character(kind=c_char, len=:), allocatable :: template
    integer :: k, length
    session_base = ''
    do k = 1, size(launcher_variables)
      call get_environment_variable(trim(launcher_variables(k)), length=length)
      if (length > 0) return
    end do
    call default_environment('OMPI_MCA_pml', 'ob1')
    call default_environment('HWLOC_COMPONENTS', hwloc_without_io)
    call get_environment_variable('OMPI_MCA_ess_singleton_isolated', length=length)
    if (length > 0) return   ! the user's choice, and the user's session directories
    template = temporary_folder()//'/paradyn-mpi.XXXXXX'//c_null_char
    if (.not. c_associated(c_mkdtemp(template))) return   ! no private folder: keep the daemon
    session_base = template(1:len(template) - 1)
    call default_environment('OMPI_MCA_orte_tmpdir_base', session_base)
    call default_environment('OMPI_MCA_ess_singleton_isolated', '1')
  end subroutine prefer_light_singleton

  !> After MPI_Finalize (which removes what it put inside): the private session directory itself.
  subroutine remove_session_base(session_base)
    character(len=*), intent(in) :: session_base
    integer(c_int) :: status
    if (len(session_base) > 0) status = c_rmdir(session_base//c_null_char)
  end subroutine remove_session_base

  function temporary_folder() result(folder)
    character(len=:), allocatable :: folder
    integer :: length
    call get_environment_variable('TMPDIR', length=length)
    if (length == 0) then
      folder = '/tmp'
      return
    end if
    allocate (character(len=length) :: folder)
    call get_environment_variable('TMPDIR', folder)
  end function temporary_folder

end module singleton_start
