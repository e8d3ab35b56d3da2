!> The automatic contact limit on the step (/control contact_closing_limit; docs/theory.md,
!> "Automatic contact limit"): the step in which a slave near its master surface closes on it by
!> the limit's fraction of the pass's thinner shell wall. The local search (contact_stages) takes
!> the least over its candidates; the step's choice (time_step_control) applies it.
!>
!> Pure: no MPI, no I/O, no module state.
module contact_closing
  use paradyn_kinds, only: wp, ip
  use contact_search, only: segment_candidates
  use segment_projection, only: segment_shape_functions
  use contact_pass, only: contact_pass_t
  use contact_interface, only: contact_t
  implicit none
  private
  public :: closing_limited, touching_step, approach_step, closing_limit_step

contains

  !> Whether the automatic limit applies to the pass: switched on, and a shell on at least one side.
  pure logical function closing_limited(c, pass)
    type(contact_t), intent(in) :: c
    type(contact_pass_t), intent(in) :: pass
    closing_limited = c%closing_limit > 0.0_wp .and. pass%t_wall < huge(1.0_wp)
  end function closing_limited

  !> The automatic step limit (/control contact_closing_limit f) of a slave whose nearest segment
  !> the search found (xc the closest point, normal the normal there): where the slave is within
  !> the reach plus its closing in the present step, the step in which it closes on the segment by
  !> f times the pass's thinner shell wall, at its speed along the normal relative to the point
  !> under it (either way: a pair that rebounds within reach closes again within a step or two);
  !> else huge. A pass the activity check finds idle stays farther than twice the reach plus
  !> twice its sides' speeds times the step (contact_activity, with speeds at most doubled since
  !> the check), beyond this nearness: skipping it changes no step.
  pure real(wp) function touching_step(c, pass, at, segment, xi, eta, xc, normal, reach) result(dt)
    type(contact_t), intent(in) :: c
    type(contact_pass_t), intent(in) :: pass
    integer, intent(in) :: at, segment
    real(wp), intent(in) :: xi, eta, xc(3), normal(3), reach
    real(wp) :: v_point(3), closing, shape(4)
    integer :: m
    shape = segment_shape_functions(xi, eta)
    v_point = 0.0_wp
    do m = 1, 4
      v_point = v_point + shape(m) * c%v(:, pass%segment_at(m, segment))
    end do
    closing = abs(dot_product(c%v(:, at) - v_point, normal))
    dt = huge(1.0_wp)
    if (norm2(c%x(:, at) - xc) - reach <= 2.0_wp * closing * c%time_step) dt = closing_limit_step(c, pass, closing)
  end function touching_step

  !> The automatic step limit of candidate k, a slave at column `at` that the
  !> search found clear of its segments by at least `lower`: where that bound lets it reach them in
  !> the present step at its speed relative to its nearest master node, its nearest segment is
  !> projected and touching_step decides; else huge. One projection, only for slaves about to touch.
  pure real(wp) function approach_step(c, pass, k, at, lower, reach) result(dt)
    type(contact_t), intent(in) :: c
    type(contact_pass_t), intent(in) :: pass
    integer, intent(in) :: k, at
    real(wp), intent(in) :: lower, reach
    integer :: segment
    real(wp) :: xi, eta, xc(3), normal(3), speed
    dt = huge(1.0_wp)
    speed = norm2(c%v(:, at) - c%v(:, pass%master_at(c%candidates(2, k))))
    if (lower > 2.0_wp * speed * c%time_step) return
    if (pass%shares_nodes) then
      call segment_candidates(c%x(:, at), int(c%candidates(2, k), ip), int(size(pass%masters), ip), c%x, &
                              int(size(pass%segments, 2), ip), pass%segment_at, pass%segment_start, &
                              pass%segment_list, segment, xi, eta, xc, normal, skip_node=int(at, ip))
    else
      call segment_candidates(c%x(:, at), int(c%candidates(2, k), ip), int(size(pass%masters), ip), c%x, &
                              int(size(pass%segments, 2), ip), pass%segment_at, pass%segment_start, &
                              pass%segment_list, segment, xi, eta, xc, normal)
    end if
    if (segment == 0) return
    if (norm2(c%x(:, at) - xc) - reach <= 2.0_wp * speed * c%time_step) dt = closing_limit_step(c, pass, speed)
  end function approach_step

  !> The step in which a pair of the pass closing at `closing` closes by the automatic limit's
  !> fraction of the pass's thinner shell wall (huge when it does not close).
  pure real(wp) function closing_limit_step(c, pass, closing) result(dt)
    type(contact_t), intent(in) :: c
    type(contact_pass_t), intent(in) :: pass
    real(wp), intent(in) :: closing
    dt = huge(1.0_wp)
    if (closing > 0.0_wp) dt = c%closing_limit * pass%t_wall / closing
  end function closing_limit_step

end module contact_closing
