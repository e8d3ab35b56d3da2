!> Stop signals: SIGTERM (Slurm at the time limit, `kill`), SIGINT (Ctrl-C) and SIGUSR1 (what
!> `mpirun` forwards to the ranks, since it turns SIGTERM into a kill) only raise a flag; the time
!> loop polls it, and the engine then writes a checkpoint and stops cleanly. The flag is the one
!> piece of module state in the engine: a signal handler has nowhere else to put it.
module stop_signals
  use, intrinsic :: iso_c_binding, only: c_int, c_funptr, c_funloc
  implicit none
  private
  public :: install_stop_handlers, stop_signal_received

  integer(c_int), parameter :: sigint = 2, sigusr1 = 10, sigterm = 15   ! Linux numbering
  integer(c_int), volatile, save :: received = 0

  interface
    function c_signal(signum, handler) bind(C, name='signal') result(previous)
      import :: c_int, c_funptr
      integer(c_int), value :: signum
      type(c_funptr), value :: handler
      type(c_funptr) :: previous
    end function c_signal
  end interface

contains

  subroutine install_stop_handlers()
    type(c_funptr) :: previous
    previous = c_signal(sigterm, c_funloc(on_stop_signal))
    previous = c_signal(sigint, c_funloc(on_stop_signal))
    previous = c_signal(sigusr1, c_funloc(on_stop_signal))
  end subroutine install_stop_handlers

  logical function stop_signal_received()
    stop_signal_received = received /= 0
  end function stop_signal_received

  subroutine on_stop_signal(signum) bind(C)
    integer(c_int), value, intent(in) :: signum
    received = signum
  end subroutine on_stop_signal

end module stop_signals
