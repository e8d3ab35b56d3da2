!> The state of the nodes of one rank (local numbering): positions, velocities, masses, fixed dofs
!> and forces, and the central-difference update of them, nodes split into one contiguous range
!> per thread.
module nodal_state
  use paradyn_kinds, only: wp
  use model_deck, only: deck_t, node_row
  use domain_decomposition, only: domain_t
  use time_integration, only: update_velocities, update_positions, update_orientations
  implicit none
  private
  public :: nodal_state_t, nodal_state_setup, advance_velocities, advance_positions, keep_velocities

  type :: nodal_state_t
    integer :: n = 0
    real(wp), allocatable :: x0(:, :), x(:, :)          !< initial and current positions (3, n)
    real(wp), allocatable :: v(:, :), w(:, :)           !< velocity, angular velocity at the half step
    real(wp), allocatable :: v_old(:, :), w_old(:, :)   !< the half step before (for output)
    real(wp), allocatable :: mass(:), inertia(:)        !< lumped mass and rotational inertia
    real(wp), allocatable :: q(:, :)                    !< (4, n) orientation from the start, a unit quaternion
    real(wp), allocatable :: weight(:)                  !< 1 where this rank owns the node, else 0
    integer, allocatable :: fixed(:, :)                 !< (6, n), 1 = fixed dof
    real(wp), allocatable :: f_int(:, :), f_ext(:, :), f_ext_old(:, :)   !< (6, n)
    !> asked for by a member that needs it (welds failing by plastic strain), the solver gives
    !> each step the largest effective plastic strain of this rank's shell integration points
    !> around each node (node_plastic_strain); not allocated otherwise
    real(wp), allocatable :: eps_p(:)
  end type nodal_state_t

contains

  !> The deck's initial state of the nodes this rank holds (the deck's rows of them, model_deck's
  !> layout); masses come later (solver_setup).
  subroutine nodal_state_setup(ns, deck, dom)
    type(nodal_state_t), intent(out) :: ns
    type(deck_t), intent(in) :: deck
    type(domain_t), intent(in) :: dom
    integer, allocatable :: rows(:)
    integer :: k
    ns%n = dom%n_nodes
    allocate (rows(dom%n_nodes))
    do k = 1, dom%n_nodes
      rows(k) = node_row(deck, dom%nodes(k))
    end do
    ns%x0 = deck%coordinates(:, rows)
    ns%x = ns%x0
    ns%v = deck%velocity(:, rows)
    ns%w = deck%angular_velocity(:, rows)
    ns%v_old = ns%v
    ns%w_old = ns%w
    allocate (ns%q(4, ns%n), source=0.0_wp)
    ns%q(1, :) = 1.0_wp
    ns%fixed = deck%fixed(:, rows)
    ns%weight = real(dom%node_owned, wp)
    where (ns%fixed(1:3, :) /= 0) ns%v = 0.0_wp
    where (ns%fixed(4:6, :) /= 0) ns%w = 0.0_wp
    allocate (ns%f_int(6, ns%n), ns%f_ext(6, ns%n), ns%f_ext_old(6, ns%n), source=0.0_wp)
  end subroutine nodal_state_setup

  !> The velocities before an update, for output at the whole step (the mean of the two).
  subroutine keep_velocities(ns)
    type(nodal_state_t), intent(inout) :: ns
    ns%v_old = ns%v
    ns%w_old = ns%w
  end subroutine keep_velocities

  !> Central-difference velocity update over a step h; adds the work damping took to damping_work.
  subroutine advance_velocities(ns, h, damping, threads, damping_work)
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: h, damping
    integer, intent(in) :: threads
    real(wp), intent(inout) :: damping_work
    integer :: chunk, j0, j1
    real(wp) :: work
    chunk = max(1, (ns%n + threads - 1) / threads)
    work = 0.0_wp
    !$omp parallel do schedule(static) private(j1) reduction(+:work)
    do j0 = 1, ns%n, chunk
      j1 = min(j0 + chunk - 1, ns%n)
      call update_velocities(j1 - j0 + 1, h, damping, ns%mass(j0:j1), ns%inertia(j0:j1), ns%fixed(:, j0:j1), &
                             ns%f_int(:, j0:j1), ns%f_ext(:, j0:j1), ns%weight(j0:j1), ns%v(:, j0:j1), &
                             ns%w(:, j0:j1), work)
    end do
    !$omp end parallel do
    damping_work = damping_work + work
  end subroutine advance_velocities

  subroutine advance_positions(ns, dt, threads)
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: dt
    integer, intent(in) :: threads
    integer :: chunk, j0, j1
    chunk = max(1, (ns%n + threads - 1) / threads)
    !$omp parallel do schedule(static) private(j1)
    do j0 = 1, ns%n, chunk
      j1 = min(j0 + chunk - 1, ns%n)
      call update_positions(j1 - j0 + 1, dt, ns%v(:, j0:j1), ns%x(:, j0:j1))
      call update_orientations(j1 - j0 + 1, dt, ns%w(:, j0:j1), ns%q(:, j0:j1))
    end do
    !$omp end parallel do
  end subroutine advance_positions

end module nodal_state
