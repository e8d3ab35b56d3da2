!> Slave nodes that start inside the contact thickness of the surface they should meet (issue 15):
!> how deep, where, and the push that takes each out, by the same geometry as the penalty force
!> (contact_penalty's penalty_force with unit stiffness: its force is the depth along the push).
!> Every contact definition is checked before the run and reported; the scene chooses what is
!> done: the nodes are moved onto the surface (the default: initial displacements the solver
!> adds), or their overlap is kept as their gap (contact_pass). Master elements are binned as in
!> surface_overlap, so the check is linear in the nodes. The kernel only: contact_checks runs it
!> on each rank's rows over the ranks; no MPI.
module initial_penetration
  use paradyn_kinds, only: wp
  use contact_penalty, only: penalty_force
  use surface_overlap, only: bin_elements, cell_of, index_of
  implicit none
  private
  public :: slave_penetrations

contains

  !> depth(s): the deepest penetration of node slaves(s) past the thickened surfaces of elements
  !> (4, n) at the positions x, 0 where none; push(:, s) the move that takes it out, from the
  !> first of the elements (in their order) that reach that depth, whatever order the grid's cells
  !> visit them in (so a rank that holds only the elements near its slaves, in the same order,
  !> finds the same push).
  subroutine slave_penetrations(x, slaves, elements, t_slave, t_master, depth, push)
    real(wp), intent(in) :: x(:, :)
    integer, intent(in) :: slaves(:), elements(:, :)
    real(wp), intent(in) :: t_slave, t_master
    real(wp), intent(out) :: depth(:), push(:, :)
    real(wp) :: lower(3), cell, reach, p(3), f_slave(3), f_master(3, 4), penetration
    integer :: dims(3), s, i, j, l, f, e, lo(3), hi(3), best
    integer, allocatable :: start(:), members(:)
    logical :: touching
    depth = 0.0_wp
    push = 0.0_wp
    if (size(slaves) == 0 .or. size(elements, 2) == 0) return
    call bin_elements(x, elements, lower, cell, dims, start, members)
    reach = 0.5_wp * (t_slave + t_master)
    do s = 1, size(slaves)
      p = x(:, slaves(s))
      lo = cell_of(p - reach, lower, cell, dims)
      hi = cell_of(p + reach, lower, cell, dims)
      best = huge(1)
      do l = lo(3), hi(3)
        do j = lo(2), hi(2)
          do i = lo(1), hi(1)
            do f = start(index_of(i, j, l, dims)), start(index_of(i, j, l, dims) + 1) - 1
              e = members(f)
              if (any(elements(:, e) == slaves(s))) cycle   ! a node never contacts its own elements
              call penalty_force(p, t_slave, x(:, elements(:, e)), t_master, 1.0_wp, f_slave, f_master, &
                                 penetration, touching, rounded_edges=.true.)
              if (.not. touching .or. penetration <= 0.0_wp) cycle
              if (penetration > depth(s) .or. (penetration == depth(s) .and. e < best)) then
                depth(s) = penetration
                push(:, s) = f_slave
                best = e
              end if
            end do
          end do
        end do
      end do
    end do
  end subroutine slave_penetrations

end module initial_penetration
