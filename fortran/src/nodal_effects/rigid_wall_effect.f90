!> Rigid walls as a member of the nodal effect family: at the start of a step, each wall's force on
!> its nodes inside it goes into the nodes' external forces (kernel: rigid_wall), so its work, the
!> springs' stored energy, friction and a moving wall's work, counts as external work. Each wall
!> keeps the exact sum of its forces on the nodes this rank owns, which the history reduces over
!> the ranks (history_sums: LS-DYNA's RWFORC, the same bits on any layout). A wall acts while
!> birth <= t <= death (LS-DYNA BIRTH, DEATH), t the time of the step's forces; outside it no node
!> meets it.
module rigid_wall_effect
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: effect_rigid_wall
  use exact_sum, only: exact_width
  use nodal_state, only: nodal_state_t
  use nodal_effect, only: nodal_effect_t, stage_loads
  use rigid_wall, only: wall_t, wall_make, rigid_wall_forces
  implicit none
  private
  public :: rigid_wall_effect_t, rigid_wall_effect_make

  type, extends(nodal_effect_t) :: rigid_wall_effect_t
    type(wall_t), allocatable :: walls(:)
    integer, allocatable :: first(:)          !< nodes of wall w: node(first(w) : first(w + 1) - 1)
    integer, allocatable :: node(:)           !< local nodes, ascending per wall
    integer(i8), allocatable :: sums(:, :, :) !< (exact_width, 3, walls): this step's forces on owned nodes
    real(wp), allocatable :: birth(:), death(:)  !< each wall acts while birth <= t <= death
  contains
    procedure :: acts_at
    procedure :: add_forces
    procedure :: history_sums
  end type rigid_wall_effect_t

contains

  !> The member from the deck's walls ((3, n_walls) and (n_walls)) for a run of first step dt.
  !> listed(k) is the wall (1-based) of the k-th row of /rigid_wall_nodes and local(k) its node in
  !> this rank's numbering (0 where the rank does not hold it); a wall without rows acts on all n nodes.
  function rigid_wall_effect_make(shape, point, normal, edge, sides, radius, length, velocity, penalty_scale, &
                                  friction, birth, death, listed, local, n, dt) result(e)
    integer, intent(in) :: shape(:), listed(:), local(:), n
    real(wp), intent(in) :: point(:, :), normal(:, :), edge(:, :), sides(:, :), radius(:), length(:)
    real(wp), intent(in) :: velocity(:, :), penalty_scale(:), friction(:), birth(:), death(:), dt
    type(rigid_wall_effect_t) :: e
    integer :: w, j, k, nw
    logical, allocatable :: mine(:)
    e%id = effect_rigid_wall
    nw = size(point, 2)
    allocate (e%walls(nw), e%first(nw + 1), e%node(0), mine(n))
    do w = 1, nw
      e%walls(w) = wall_make(shape(w), point(:, w), normal(:, w), edge(:, w), sides(:, w), radius(w), length(w), &
                             velocity(:, w), penalty_scale(w), friction(w), dt)
      e%first(w) = size(e%node) + 1
      if (any(listed == w)) then
        mine = .false.
        do k = 1, size(listed)
          if (listed(k) == w .and. local(k) > 0) mine(local(k)) = .true.
        end do
        e%node = [e%node, pack([(j, j = 1, n)], mine)]
      else
        e%node = [e%node, [(j, j = 1, n)]]
      end if
    end do
    e%first(nw + 1) = size(e%node) + 1
    e%birth = birth
    e%death = death
    allocate (e%sums(exact_width, 3, nw), source=0_i8)
  end function rigid_wall_effect_make

  pure logical function acts_at(e, stage)
    class(rigid_wall_effect_t), intent(in) :: e
    integer, intent(in) :: stage
    acts_at = stage == stage_loads
  end function acts_at

  subroutine add_forces(e, ns, time)
    class(rigid_wall_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time
    integer :: w
    e%sums = 0
    do w = 1, size(e%walls)
      if (time < e%birth(w) .or. time > e%death(w)) cycle   ! not born yet, or dead
      call rigid_wall_forces(e%walls(w), e%node(e%first(w):e%first(w + 1) - 1), ns%x, ns%v, ns%mass, ns%weight, &
                             time, ns%f_ext, e%sums(:, :, w))
    end do
  end subroutine add_forces

  !> The exact sums of each wall's force on this rank's owned nodes in the last step.
  function history_sums(e) result(sums)
    class(rigid_wall_effect_t), intent(in) :: e
    integer(i8), allocatable :: sums(:, :, :)
    sums = e%sums
  end function history_sums

end module rigid_wall_effect
