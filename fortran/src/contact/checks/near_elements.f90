!> The elements of one part near what a rank must test against them (issue 19, item 5): the
!> contact set-up checks run on each rank's own rows, so a rank needs, besides its own elements,
!> those of the other ranks that can reach its slaves or its element sides. Each rank names one
!> box (the bounds of what it tests; empty when it tests nothing), the boxes are all-gathered (6
!> numbers per rank), and every rank sends each element of the part it holds, with its corners'
!> positions, to each rank whose box the element's bounds come within `margin` of (one
!> MPI_Alltoallv). What a rank receives is ordered by element id, so a search over it meets the
!> elements in the order one rank holding them all would. Memory: the elements near the box, no
!> array sized by the global mesh.
module near_elements
  use mpi_f08
  use paradyn_kinds, only: wp
  use integer_sort, only: distinct_ascending, sorted_position
  use rank_exchange, only: exchange_int, exchange_real
  implicit none
  private
  public :: near_set_t, gather_near, empty_box, box_of

  !> The elements near this rank's box, ids ascending, with a node table of their nodes (and of
  !> the extra nodes the caller adds): connectivity indexes node_ids and x.
  type :: near_set_t
    integer, allocatable :: element_ids(:)
    integer, allocatable :: connectivity(:, :)   !< (4, n) places in node_ids
    integer, allocatable :: node_ids(:)          !< global ids, ascending
    real(wp), allocatable :: x(:, :)             !< (3, size(node_ids))
  end type near_set_t

contains

  !> The box (lower, upper) that holds nothing.
  pure function empty_box() result(box)
    real(wp) :: box(3, 2)
    box(:, 1) = huge(1.0_wp)
    box(:, 2) = -huge(1.0_wp)
  end function empty_box

  !> The bounds of the points x(3, n) (empty_box when n = 0).
  pure function box_of(x) result(box)
    real(wp), intent(in) :: x(:, :)
    real(wp) :: box(3, 2)
    box = empty_box()
    if (size(x, 2) == 0) return
    box(:, 1) = minval(x, dim=2)
    box(:, 2) = maxval(x, dim=2)
  end function box_of

  !> near: every element of every rank's `ids` (global ids, this rank's ascending, corner node ids
  !> `nodes` (4, n) and corner positions `corners` (3, 4, n)) whose bounds come within margin of
  !> this rank's `box`, ids ascending; its node table also holds extra_ids (global ids) at
  !> extra_x (3, n), the nodes the caller tests. Collective.
  subroutine gather_near(comm, box, margin, ids, nodes, corners, extra_ids, extra_x, near)
    type(MPI_Comm), intent(in) :: comm
    real(wp), intent(in) :: box(3, 2), margin, corners(:, :, :), extra_x(:, :)
    integer, intent(in) :: ids(:), nodes(:, :), extra_ids(:)
    type(near_set_t), intent(out) :: near
    real(wp), allocatable :: boxes(:, :, :), send_x(:), recv_x(:)
    integer, allocatable :: first(:), send(:), recv(:), recv_counts(:), fill(:)
    real(wp) :: lo(3), hi(3), slack
    integer :: n_ranks, r, e, m, k, at, pass
    call MPI_Comm_size(comm, n_ranks)
    allocate (boxes(3, 2, n_ranks))
    call MPI_Allgather(box, 6, MPI_DOUBLE_PRECISION, boxes, 6, MPI_DOUBLE_PRECISION, comm)
    allocate (first(n_ranks), fill(n_ranks))
    do pass = 1, 2   ! count, then place (ids and corner nodes: 5 integers; corners: 12 numbers)
      fill = 0
      do e = 1, size(ids)
        lo = minval(corners(:, :, e), dim=2)
        hi = maxval(corners(:, :, e), dim=2)
        do r = 1, n_ranks
          if (boxes(1, 1, r) > boxes(1, 2, r)) cycle   ! an empty box
          ! a relative slack against round-off in the bounds: an element too many costs nothing
          slack = margin + 1.0e-9_wp * (margin + maxval(abs(boxes(:, :, r))))
          if (any(lo > boxes(:, 2, r) + slack) .or. any(hi < boxes(:, 1, r) - slack)) cycle
          if (pass == 2) then
            at = first(r) + fill(r)
            send(5 * at + 1:5 * at + 5) = [ids(e), nodes(:, e)]
            send_x(12 * at + 1:12 * at + 12) = reshape(corners(:, :, e), [12])
          end if
          fill(r) = fill(r) + 1
        end do
      end do
      if (pass == 1) then
        allocate (send(5 * sum(fill)), send_x(12 * sum(fill)))
        first = [(sum(fill(1:r - 1)), r = 1, n_ranks)]
      end if
    end do
    call exchange_int(comm, send, 5 * fill, recv, recv_counts)
    call exchange_real(comm, send_x, 12 * fill, recv_x)
    m = size(recv) / 5
    near%element_ids = distinct_ascending(recv(1:5 * m:5))   ! each element is held by one rank
    near%node_ids = distinct_ascending([([recv(5 * k - 3:5 * k)], k = 1, m), extra_ids])
    allocate (near%connectivity(4, m), near%x(3, size(near%node_ids)))
    do k = 1, size(extra_ids)
      near%x(:, sorted_position(near%node_ids, extra_ids(k))) = extra_x(:, k)
    end do
    do k = 1, m
      e = sorted_position(near%element_ids, recv(5 * k - 4))
      do r = 1, 4
        at = sorted_position(near%node_ids, recv(5 * k - 4 + r))
        near%connectivity(r, e) = at
        near%x(:, at) = recv_x(12 * (k - 1) + 3 * r - 2:12 * (k - 1) + 3 * r)
      end do
    end do
  end subroutine gather_near

end module near_elements
