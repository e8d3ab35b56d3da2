!> The one reduction of local contact's sums per step (docs/theory.md, "Parallel contact and
!> determinism"): each rank's exact sums (exact_sum accumulators) of the energy's work and the
!> definitions' forces, over the terms of the records and nodes it owns, are added over the ranks,
!> and the deepest penetration is their maximum, in one MPI_Allreduce with an operation of its
!> own over one block of integers (the accumulators, then the penetration's bits: a non-negative
!> double orders as its bits do). Integer sums and a maximum are exact in any order, so every
!> rank gets the same answer for any layout and reduction tree.
module contact_reduction
  use mpi_f08
  use, intrinsic :: iso_c_binding, only: c_ptr, c_f_pointer
  use paradyn_kinds, only: wp, i8
  use exact_sum, only: exact_normalise
  use traffic_counter, only: traffic_t, count_allreduce
  implicit none
  private
  public :: reduce_contact_sums

contains

  !> sums(:, d): this rank's accumulators, then their sum over the ranks; deepest (>= 0): this
  !> rank's deepest penetration, then the deepest of all. Collective.
  subroutine reduce_contact_sums(comm, n_ranks, sums, deepest, traffic)
    type(MPI_Comm), intent(in) :: comm
    integer, intent(in) :: n_ranks
    integer(i8), intent(inout) :: sums(:, :)
    real(wp), intent(inout) :: deepest
    type(traffic_t), intent(inout) :: traffic
    integer(i8) :: buffer(size(sums) + 1)
    type(MPI_Datatype) :: block
    type(MPI_Op) :: op
    integer :: d
    do d = 1, size(sums, 2)
      call exact_normalise(sums(:, d))   ! limbs below 2^32: the ranks' sums cannot overflow
    end do
    buffer(1:size(sums)) = reshape(sums, [size(sums)])
    buffer(size(buffer)) = transfer(max(deepest, 0.0_wp), 0_i8)
    ! one element of the whole block, so that the operation never sees it cut in pieces
    call MPI_Type_contiguous(size(buffer), MPI_INTEGER8, block)
    call MPI_Type_commit(block)
    call MPI_Op_create(add_then_max, .true., op)
    call MPI_Allreduce(MPI_IN_PLACE, buffer, 1, block, op, comm)
    call MPI_Op_free(op)
    call MPI_Type_free(block)
    call count_allreduce(traffic, int(8 * size(buffer), i8), n_ranks)
    sums = reshape(buffer(1:size(sums)), shape(sums))
    deepest = transfer(buffer(size(buffer)), 1.0_wp)
  end subroutine reduce_contact_sums

  !> The reduction: blocks of integers, added but for the last of each block, whose maximum is kept.
  subroutine add_then_max(invec, inoutvec, len, datatype)
    type(c_ptr), value :: invec, inoutvec
    integer :: len
    type(MPI_Datatype) :: datatype
    integer(i8), pointer :: a(:, :), b(:, :)
    integer :: bytes, width
    call MPI_Type_size(datatype, bytes)
    width = bytes / 8
    call c_f_pointer(invec, a, [width, len])
    call c_f_pointer(inoutvec, b, [width, len])
    b(1:width - 1, :) = b(1:width - 1, :) + a(1:width - 1, :)
    b(width, :) = max(b(width, :), a(width, :))
  end subroutine add_then_max

end module contact_reduction
