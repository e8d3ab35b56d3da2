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
  !> a stored point beyond those measured: stress, back stress and plastic strain (9 doubles); a
  !> fully integrated part (element/shell_full) stores 3 x integration_points more per element
  real(wp), parameter :: mb_per_point = 9.0_wp * 8.0_wp / 1048576.0_wp

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

  !> The memory one rank needs for a model of this size (MiB); extra_points: the stored points per
  !> element beyond a one-point element's (3 x the most integration_points of a fully integrated
  !> part, counted for every element: an upper bound; 0 without one).
  pure real(wp) function deck_memory_mb(n_elements, n_nodes, extra_points) result(mb)
    integer, intent(in) :: n_elements, n_nodes, extra_points
    mb = mb_base + mb_per_element * real(max(n_elements, n_nodes), wp) &
         + mb_per_point * real(extra_points, wp) * real(n_elements, wp)
  end function deck_memory_mb

end module machine_memory
