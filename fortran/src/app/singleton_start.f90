!> Start-up of a rank started without a launcher (`paradyn-engine deck.h5`, the frontend's direct
!> runner): Open MPI would otherwise fork a supporting daemon and probe every network library,
!> 0.3 s of a run whose time loop may take less (docs/performance.md, "Fixed costs"). Before
!> MPI_Init, and only when no launcher set the environment, ask for no daemon (the engine never
!> spawns processes) and for the ob1 messaging layer (one process has no network to probe).
!> Settings the user made win; other MPIs ignore these names.
module singleton_start
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
  implicit none
  private
  public :: prefer_light_singleton

  ! what mpirun / srun (PMI, PMIx) set in every rank's environment
  character(len=*), parameter :: launcher_variables(4) = [character(len=20) :: &
    'OMPI_COMM_WORLD_SIZE', 'PMIX_RANK', 'PMI_RANK', 'PMI_SIZE']

  interface
    function c_setenv(name, value, overwrite) bind(C, name='setenv') result(status)
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: name(*), value(*)
      integer(c_int), value :: overwrite
      integer(c_int) :: status
    end function c_setenv
  end interface

contains

  subroutine prefer_light_singleton()
    integer :: k, length
    integer(c_int) :: status
    do k = 1, size(launcher_variables)
      call get_environment_variable(trim(launcher_variables(k)), length=length)
      if (length > 0) return
    end do
    status = c_setenv('OMPI_MCA_ess_singleton_isolated'//c_null_char, '1'//c_null_char, 0_c_int)
    status = c_setenv('OMPI_MCA_pml'//c_null_char, 'ob1'//c_null_char, 0_c_int)
  end subroutine prefer_light_singleton

end module singleton_start
