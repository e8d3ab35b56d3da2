!> Counters of what one rank sends and receives, for the weak-scaling account of docs/performance.md
!> ("Beyond one machine"). Point-to-point messages are counted as sent. A collective is counted as
!> the point-to-point messages of a plain algorithm, whatever the MPI library does inside: an
!> allgather(v) as one message to every other rank (own bytes to each, everyone else's bytes
!> received); an allreduce as recursive doubling, ceil(log2 p) messages of its bytes each way.
!> The counts are cheap (a few integer additions per call) and change no result.
module traffic_counter
  use paradyn_kinds, only: i8
  implicit none
  private
  public :: traffic_t, count_messages, count_allgather, count_allreduce, reduction_steps

  type :: traffic_t
    integer(i8) :: messages = 0         !< messages sent
    integer(i8) :: bytes_sent = 0
    integer(i8) :: bytes_received = 0
  end type traffic_t

contains

  !> n point-to-point messages carrying `sent` bytes out and `received` bytes in, in all.
  pure subroutine count_messages(t, n, sent, received)
    type(traffic_t), intent(inout) :: t
    integer, intent(in) :: n
    integer(i8), intent(in) :: sent, received
    t%messages = t%messages + n
    t%bytes_sent = t%bytes_sent + sent
    t%bytes_received = t%bytes_received + received
  end subroutine count_messages

  !> An allgather(v) over n_ranks in which this rank gives `own` bytes of `total` bytes gathered.
  pure subroutine count_allgather(t, own, total, n_ranks)
    type(traffic_t), intent(inout) :: t
    integer(i8), intent(in) :: own, total
    integer, intent(in) :: n_ranks
    if (n_ranks < 2) return
    call count_messages(t, n_ranks - 1, own * (n_ranks - 1), total - own)
  end subroutine count_allgather

  !> An allreduce of `bytes` over n_ranks (recursive doubling).
  pure subroutine count_allreduce(t, bytes, n_ranks)
    type(traffic_t), intent(inout) :: t
    integer(i8), intent(in) :: bytes
    integer, intent(in) :: n_ranks
    integer :: steps
    steps = reduction_steps(n_ranks)
    call count_messages(t, steps, bytes * steps, bytes * steps)
  end subroutine count_allreduce

  !> ceil(log2 n_ranks): the rounds of recursive doubling (0 on one rank).
  pure integer function reduction_steps(n_ranks) result(steps)
    integer, intent(in) :: n_ranks
    steps = 0
    do while (2**steps < n_ranks)
      steps = steps + 1
    end do
  end function reduction_steps

end module traffic_counter
