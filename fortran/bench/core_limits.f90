!> paradyn-core-limits
!>
!> The limits of one core that the element kernel's roofline account (docs/performance.md) sets
!> its numbers against, measured with the kernel's own compile options (no FMA contraction,
!> 512-bit vectors preferred): separate adds and multiplies, divisions and square roots on arrays
!> that stay in the L1 cache, and the bandwidth of a triad a = b + s c on arrays far larger than
!> the caches. Prints operations per nanosecond and gigabytes per second; CPU time, 1 thread.
program core_limits
  use paradyn_kinds, only: wp
  implicit none
  integer, parameter :: n_l1 = 512            !< 4 KiB per array: in L1, 64 independent vectors
  integer, parameter :: reps = 200000
  integer, parameter :: n_mem = 32 * 1024 * 1024   !< 256 MiB per array: beyond every cache
  real(wp), allocatable :: x(:), a(:), b(:), c(:)
  real(wp) :: t0, t1, s
  integer :: r, i

  allocate (x(n_l1))
  call random_number(x)
  s = x(1)
  call cpu_time(t0)
  do r = 1, reps
    do i = 1, n_l1
      x(i) = x(i) * 0.999_wp + 1.0e-3_wp    ! one multiply, one add
    end do
  end do
  call cpu_time(t1)
  write (*, '(a,f8.2,a,es10.2,a)') 'add and multiply: ', 2.0_wp * n_l1 * reps / (t1 - t0) / 1.0e9_wp, &
    ' flop per ns (', sum(x), ')'
  call cpu_time(t0)
  do r = 1, reps
    do i = 1, n_l1
      x(i) = 2.0_wp / (x(i) + 1.0_wp)    ! one division (and an add)
    end do
  end do
  call cpu_time(t1)
  write (*, '(a,f8.2,a,es10.2,a)') 'division: ', real(n_l1, wp) * reps / (t1 - t0) / 1.0e9_wp, &
    ' per ns (', sum(x), ')'
  call cpu_time(t0)
  do r = 1, reps
    do i = 1, n_l1
      x(i) = sqrt(x(i) + 1.0_wp)    ! one square root (and an add)
    end do
  end do
  call cpu_time(t1)
  write (*, '(a,f8.2,a,es10.2,a)') 'square root: ', real(n_l1, wp) * reps / (t1 - t0) / 1.0e9_wp, &
    ' per ns (', sum(x), ')'

  allocate (a(n_mem), b(n_mem), c(n_mem))
  a = 0.0_wp
  b = 1.0_wp
  c = 2.0_wp
  call cpu_time(t0)
  do r = 1, 10
    s = 1.0_wp / r
    do i = 1, n_mem
      a(i) = b(i) + s * c(i)
    end do
  end do
  call cpu_time(t1)
  ! three arrays of 8-byte reals per pass (a written: its line is read first, not counted)
  write (*, '(a,f8.2,a,es10.2,a)') 'memory (triad): ', 24.0_wp * n_mem * 10 / (t1 - t0) / 1.0e9_wp, &
    ' GB per s (', a(n_mem), ')'
end program core_limits
