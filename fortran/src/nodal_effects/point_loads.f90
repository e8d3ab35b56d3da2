!> Point loads: the forces at a time, and the work they do over a step.
!>
!> Compiled without floating-point contraction (fortran/CMakeLists.txt): the work is summed over
!> the nodes of a rank, and a node must get the same arithmetic whether it falls in the vector body
!> or the scalar remainder of the loop, or the external work would depend on the layout.
module point_loads
  use paradyn_kinds, only: wp
  implicit none
  private
  public :: point_load_forces, point_load_work

contains

  !> Adds the point loads at time t: each grows linearly from 0 to its value over its ramp time.
  !> node holds local node indices (0 for loads on nodes this rank does not hold).
  pure subroutine point_load_forces(n_loads, node, dof, value, ramp_time, time, force_external)
    integer, intent(in) :: n_loads, node(n_loads), dof(n_loads)
    real(wp), intent(in) :: value(n_loads), ramp_time(n_loads), time
    real(wp), intent(inout) :: force_external(:, :)
    integer :: l
    do l = 1, n_loads
      if (node(l) < 1) cycle
      if (ramp_time(l) > 0.0_wp) then
        force_external(dof(l), node(l)) = force_external(dof(l), node(l)) &
                                          + value(l) * min(1.0_wp, time / ramp_time(l))
      else
        force_external(dof(l), node(l)) = force_external(dof(l), node(l)) + value(l)
      end if
    end do
  end subroutine point_load_forces

  !> Work of the external forces over a step dt by the trapezoidal rule, on the nodes of weight 1
  !> (each node is counted by one rank only), added to work.
  pure subroutine point_load_work(n, dt, weight, v, w, force_before, force_after, work)
    integer, intent(in) :: n
    real(wp), intent(in) :: dt, weight(n), v(3, n), w(3, n), force_before(6, n), force_after(6, n)
    real(wp), intent(inout) :: work
    integer :: j
    do j = 1, n
      work = work + weight(j) * 0.5_wp * dt * (dot_product(v(:, j), force_before(1:3, j) + force_after(1:3, j)) &
                                               + dot_product(w(:, j), force_before(4:6, j) + force_after(4:6, j)))
    end do
  end subroutine point_load_work

end module point_loads
