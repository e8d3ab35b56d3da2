!> How much memory this machine has, and how much a deck needs (issue 17, size guards): a run
!> whose estimate is beyond the machine is refused before the work starts, with the estimate.
module machine_memory
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: proc_kib, node_memory_mb, deck_memory_mb

  !> Per element and node of the model (MiB), and the engine's own start (MiB): measured on the
  !> pipe-whip cases (peak 31.8 MiB at 1024 elements, 68.1 MiB at 25600: about 1.5 kB per element
  !> and node together), rounded up; a rank holds its share of the mesh (model_deck's layout).
  real(wp), parameter :: mb_per_element = 2.0e-3_wp, mb_base = 40.0_wp

contains

  !> A value in kB of a /proc file ('/proc/meminfo', 'MemTotal:'); 0 where the system does not say.
  integer function proc_kib(file, key) result(kib)
    character(len=*), intent(in) :: file, key
    character(len=256) :: line
    integer :: unit, io
    kib = 0
    open (newunit=unit, file=file, action='read', status='old', iostat=io)
    if (io /= 0) return
    do
      read (unit, '(a)', iostat=io) line
      if (io /= 0) exit
      if (line(1:len(key)) == key) then
        read (line(len(key) + 1:), *, iostat=io) kib
        if (io /= 0) kib = 0
        exit
      end if
    end do
    close (unit)
  end function proc_kib

  !> The memory of this node (MiB): PARADYN_MEMORY_MB where set (a batch job's share), else
  !> MemTotal; 0 where unknown.
  real(wp) function node_memory_mb() result(mb)
    character(len=32) :: text
    integer :: length, io
    call get_environment_variable('PARADYN_MEMORY_MB', text, length)
    if (length > 0) then
      read (text, *, iostat=io) mb
      if (io == 0) return
    end if
    mb = proc_kib('/proc/meminfo', 'MemTotal:') / 1024.0_wp
  end function node_memory_mb

  !> The memory one rank needs for a model of this size (MiB).
  pure real(wp) function deck_memory_mb(n_elements, n_nodes) result(mb)
    integer, intent(in) :: n_elements, n_nodes
    mb = mb_base + mb_per_element * real(max(n_elements, n_nodes), wp)
  end function deck_memory_mb

end module machine_memory
