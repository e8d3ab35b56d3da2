!> Rigid bodies as a member of the nodal effect family (docs/architecture.md): after each velocity
!> update, the force and torque on each body are summed over its nodes, its Newton-Euler update
!> runs (rigid_body_motion), and its nodes get the velocities that carry them with it. The sums are
!> exact (core/exact_sum) and reduced over the ranks, so every rank moves every body the same way
!> and the positions are bitwise the same on any layout. Each rank carries the nodes it holds; a
!> body costs time in proportion to its nodes, and a model without bodies never builds this member.
!> A weld (a body with a failure force or time, weld_failure) lets its nodes go for the rest of the
!> run when it fails: from that step on they move as free nodes; the failed state is checkpointed.
module rigid_body_effect
  use mpi_f08
  use paradyn_kinds, only: wp, i8
  use paradyn_schema, only: effect_rigid_bodies
  use exact_sum, only: exact_width, exact_add, exact_normalise, exact_value
  use vector_algebra, only: cross
  use nodal_state, only: nodal_state_t
  use load_curves, only: load_curves_t, curve_value
  use nodal_effect, only: nodal_effect_t, stage_constraints
  use rigid_body_motion, only: rigid_body_t, body_from_sums, body_advance, body_omega, &
                               carry_nodes, n_mass_sums, body_with_given_mass, inertia_is_positive
  use weld_failure, only: weld_t, weld_has_force_criterion, weld_criterion, weld_has_strain_criterion, &
                          weld_strain_failed
  implicit none
  private
  public :: rigid_body_effect_t, rigid_body_effect_make

  !> centre, rotation, velocity, momentum, omega, failed (1.0 or 0.0) and the failure time
  integer, parameter :: state_per_body = 23

  type, extends(nodal_effect_t) :: rigid_body_effect_t
    type(MPI_Comm) :: comm
    type(rigid_body_t), allocatable :: bodies(:)
    integer, allocatable :: first(:)          !< entries of body b: first(b) .. first(b + 1) - 1
    integer, allocatable :: node(:)           !< local node of each entry (every node held)
    real(wp), allocatable :: offset(:, :)     !< x at t = 0 less the body's centre at t = 0
    integer(i8), allocatable :: sums(:, :, :) !< workspace: exact accumulators (width, 6, bodies)
    integer, allocatable :: prescribed(:, :)  !< (6, bodies) 1: the dof's velocity follows velocity x curve
    real(wp), allocatable :: velocity(:, :)   !< (6, bodies) m/s, rad/s
    integer, allocatable :: curve(:)          !< per body, 1-based, 0: the factor 1
    type(load_curves_t) :: curves
    integer :: rank = 0                       !< the constraint work is counted once, on rank 0
    type(weld_t), allocatable :: welds(:)     !< per body: its failure forces, exponents, time, normal
    integer, allocatable :: failure_entry(:)  !< per body: the entry of its weld node if this rank owns it, else 0
    logical :: force_criteria = .false.       !< some body can fail by its force
    logical :: strain_criteria = .false.      !< some body can fail by the plastic strain of its shells
    integer, allocatable :: failed(:)         !< per body: 1 once it has let its nodes go
    real(wp), allocatable :: failed_at(:)     !< per body: the time it let go (s), -1 while it holds
    real(wp), allocatable :: v_free(:, :)     !< (6, entries) workspace: the nodes' velocities before the constraint
  contains
    procedure :: acts_at
    procedure :: constrain
    procedure :: state_words
    procedure :: restore_state
    procedure :: carried_mass
    procedure :: failures
  end type rigid_body_effect_t

contains

  !> The member for the bodies of the deck: body(j) is local node j's body (1-based, 0 for none),
  !> fixed(:, b) the held dofs of body b, prescribed(:, b) those whose velocity is velocity(:, b) x
  !> curve(b) of curves (0: the factor 1). Collective over comm. Mass, centre and inertia come from
  !> the nodes' masses (ns%mass, ns%inertia, set before); the initial velocity and angular momentum
  !> from the nodes' initial velocities, which are then made those of the rigid motion. welds(b):
  !> body b's failure (weld_failure), failure_node(b) the local node whose constraint force is its
  !> weld's (0 for none or not held here). given_mass(b) > 0: body b's mass, centre (3, b) and
  !> inertia (6, b: xx, yy, zz, xy, yz, zx) are given_* instead (its nodes give its initial velocity).
  function rigid_body_effect_make(body, fixed, prescribed, velocity, curve, curves, welds, failure_node, &
                                  given_mass, given_centre, given_inertia, ns, comm) result(e)
    integer, intent(in) :: body(:), fixed(:, :), prescribed(:, :), curve(:), failure_node(:)
    real(wp), intent(in) :: velocity(:, :), given_mass(:), given_centre(:, :), given_inertia(:, :)
    type(load_curves_t), intent(in) :: curves
    type(weld_t), intent(in) :: welds(:)
    type(nodal_state_t), intent(inout) :: ns
    type(MPI_Comm), intent(in) :: comm
    type(rigid_body_effect_t) :: e
    integer :: nb, b, k
    real(wp), allocatable :: terms(:, :), totals(:, :), origin(:, :)
    e%id = effect_rigid_bodies
    e%comm = comm
    call MPI_Comm_rank(comm, e%rank)
    nb = size(fixed, 2)
    e%prescribed = prescribed
    e%velocity = velocity
    e%curve = curve
    e%curves = curves
    call sort_entries(body, nb, e%first, e%node)
    e%welds = welds
    allocate (e%failure_entry(nb), e%failed(nb), e%failed_at(nb))
    e%failure_entry = 0
    e%failed = 0
    e%failed_at = -1.0_wp
    do b = 1, nb   ! every rank checks the welds (collective), whether it holds their nodes or not
      if (.not. weld_has_force_criterion(welds(b))) cycle
      e%force_criteria = .true.
      if (failure_node(b) == 0) cycle
      do k = e%first(b), e%first(b + 1) - 1
        if (e%node(k) == failure_node(b) .and. ns%weight(failure_node(b)) /= 0.0_wp) e%failure_entry(b) = k
      end do
    end do
    call check_failure_nodes(e, failure_node, comm)
    if (e%force_criteria) allocate (e%v_free(6, size(e%node)))
    e%strain_criteria = any([(weld_has_strain_criterion(welds(b)), b = 1, nb)])
    if (e%strain_criteria .and. .not. allocated(ns%eps_p)) allocate (ns%eps_p(ns%n), source=0.0_wp)
    allocate (e%bodies(nb), origin(3, nb), totals(n_mass_sums, nb))
    allocate (e%sums(exact_width, n_mass_sums, nb))
    origin = 0.0_wp
    ! pass 1: mass and first moment about the world's origin give a centre to take moments about
    allocate (terms(n_mass_sums, size(e%node)), source=0.0_wp)
    call mass_terms(e, ns, origin, terms)
    call reduce(e, terms(1:4, :), totals(1:4, :))
    do b = 1, nb
      if (.not. totals(1, b) > 0.0_wp) error stop 'paradyn-engine: a rigid body has no mass; give every row of '// &
        '/rigid_bodies nodes with mass in /nodes/rigid_body (the frontend checks this: paradyn.deck.validate_model)'
      origin(:, b) = totals(2:4, b) / totals(1, b)
    end do
    call mass_terms(e, ns, origin, terms)
    call reduce(e, terms, totals)
    do b = 1, nb
      e%bodies(b) = body_from_sums(totals(:, b), origin(:, b), merge(1, 0, fixed(:, b) /= 0 .or. prescribed(:, b) /= 0))
    end do
    ! the momenta of the nodes' initial velocities: translation, then rotation about the centre
    allocate (e%offset(3, size(e%node)))
    do b = 1, nb
      do k = e%first(b), e%first(b + 1) - 1
        e%offset(:, k) = ns%x(:, e%node(k)) - e%bodies(b)%centre
      end do
    end do
    call momentum_terms(e, ns, terms(1:6, :))
    call reduce(e, terms(1:6, :), totals(1:6, :))
    do b = 1, nb
      e%bodies(b)%target = merge(velocity(:, b) * start_factor(e, b), 0.0_wp, prescribed(:, b) /= 0)
      e%bodies(b)%velocity = merge(e%bodies(b)%target(1:3), totals(1:3, b) / e%bodies(b)%mass, &
                                   e%bodies(b)%given(1:3) /= 0)
      e%bodies(b)%momentum = totals(4:6, b)
      call body_omega(e%bodies(b), e%bodies(b)%rotation)
      do k = e%first(b), e%first(b + 1) - 1
        ns%v(:, e%node(k)) = e%bodies(b)%velocity + cross(e%bodies(b)%omega, e%offset(:, k))
        ns%w(:, e%node(k)) = e%bodies(b)%omega
      end do
      if (.not. given_mass(b) > 0.0_wp) cycle   ! LS-DYNA *PART_INERTIA: the same motion, the given body
      if (.not. inertia_is_positive(given_inertia(:, b))) error stop 'paradyn-engine: a /rigid_bodies/given_inertia '// &
        'is not positive definite; give the inertia tensor about the centre (the frontend checks this)'
      call body_with_given_mass(e%bodies(b), given_mass(b), given_centre(:, b), given_inertia(:, b))
      call body_omega(e%bodies(b), e%bodies(b)%rotation)
      do k = e%first(b), e%first(b + 1) - 1
        e%offset(:, k) = ns%x(:, e%node(k)) - e%bodies(b)%centre
      end do
    end do
    e%sums = 0
  end function rigid_body_effect_make

  !> Stops the run when a body's failure node (given here where held) is on no rank one of its own.
  subroutine check_failure_nodes(e, failure_node, comm)
    type(rigid_body_effect_t), intent(in) :: e
    integer, intent(in) :: failure_node(:)
    type(MPI_Comm), intent(in) :: comm
    integer :: given(size(failure_node)), found(size(failure_node)), k
    given = merge(1, 0, failure_node > 0)
    found = merge(1, 0, e%failure_entry > 0)
    call MPI_Allreduce(MPI_IN_PLACE, given, size(given), MPI_INTEGER, MPI_MAX, comm)
    call MPI_Allreduce(MPI_IN_PLACE, found, size(found), MPI_INTEGER, MPI_MAX, comm)
    if (any(given > 0 .and. found == 0 .and. [(weld_has_force_criterion(e%welds(k)), k = 1, size(e%welds))])) &
      error stop 'paradyn-engine: a /rigid_bodies/failure_node is not a node of its own body (/nodes/rigid_body); '// &
        'give the weld''s N1, or -1 (the frontend checks this: paradyn.deck.validate_model)'
  end subroutine check_failure_nodes

  !> The factor of body b's prescribed velocities at time 0.
  pure real(wp) function start_factor(e, b) result(factor)
    type(rigid_body_effect_t), intent(in) :: e
    integer, intent(in) :: b
    factor = 1.0_wp
    if (e%curve(b) > 0) factor = curve_value(e%curves, e%curve(b), 0.0_wp)
  end function start_factor

  !> The local nodes of each body in ascending order: first (nb + 1) and node.
  pure subroutine sort_entries(body, nb, first, node)
    integer, intent(in) :: body(:), nb
    integer, allocatable, intent(out) :: first(:), node(:)
    integer :: b, j, k
    allocate (first(nb + 1), node(count(body > 0)))
    k = 0
    do b = 1, nb
      first(b) = k + 1
      do j = 1, size(body)
        if (body(j) /= b) cycle
        k = k + 1
        node(k) = j
      end do
    end do
    first(nb + 1) = k + 1
  end subroutine sort_entries

  !> Per entry of an owned node: m, m d (3), m d d^T (xx, yy, zz, xy, yz, zx) and the rotary
  !> inertia, d = x - origin of its body; 0 for a node another rank owns.
  pure subroutine mass_terms(e, ns, origin, terms)
    type(rigid_body_effect_t), intent(in) :: e
    type(nodal_state_t), intent(in) :: ns
    real(wp), intent(in) :: origin(:, :)
    real(wp), intent(out) :: terms(:, :)
    integer :: b, k, j
    real(wp) :: d(3), m
    terms = 0.0_wp
    do b = 1, size(e%bodies)
      do k = e%first(b), e%first(b + 1) - 1
        j = e%node(k)
        if (ns%weight(j) == 0.0_wp) cycle
        m = ns%mass(j)
        d = ns%x(:, j) - origin(:, b)
        terms(:, k) = [m, m * d, m * d * d, m * d(1) * d(2), m * d(2) * d(3), m * d(3) * d(1), ns%inertia(j)]
      end do
    end do
  end subroutine mass_terms

  !> Per entry of an owned node: its momentum m v and its angular momentum about the body's
  !> centre, offset x m v + I w.
  pure subroutine momentum_terms(e, ns, terms)
    type(rigid_body_effect_t), intent(in) :: e
    type(nodal_state_t), intent(in) :: ns
    real(wp), intent(out) :: terms(:, :)
    integer :: k, j
    terms = 0.0_wp
    do k = 1, size(e%node)
      j = e%node(k)
      if (ns%weight(j) == 0.0_wp) cycle
      terms(1:3, k) = ns%mass(j) * ns%v(:, j)
      terms(4:6, k) = cross(e%offset(:, k), ns%mass(j) * ns%v(:, j)) + ns%inertia(j) * ns%w(:, j)
    end do
  end subroutine momentum_terms

  !> totals(q, b) = the sum of terms(q, k) over the entries of body b on every rank, exactly.
  subroutine reduce(e, terms, totals)
    type(rigid_body_effect_t), intent(inout) :: e
    real(wp), intent(in) :: terms(:, :)
    real(wp), intent(out) :: totals(:, :)
    integer :: b, k, q, nq, n_ranks
    nq = size(terms, 1)
    e%sums(:, 1:nq, :) = 0
    do b = 1, size(e%bodies)
      do k = e%first(b), e%first(b + 1) - 1
        do q = 1, nq
          call exact_add(e%sums(:, q, b), terms(q, k))
        end do
      end do
      do q = 1, nq
        call exact_normalise(e%sums(:, q, b))
      end do
    end do
    call MPI_Comm_size(e%comm, n_ranks)
    if (n_ranks > 1) call MPI_Allreduce(MPI_IN_PLACE, e%sums(:, 1:nq, :), exact_width * nq * size(e%bodies), &
                                        MPI_INTEGER8, MPI_SUM, e%comm)
    do b = 1, size(e%bodies)
      do q = 1, nq
        totals(q, b) = exact_value(e%sums(:, q, b))
      end do
    end do
  end subroutine reduce

  !> Force and torque from the nodes' forces at the step's start, each body's update, and the
  !> half-step velocities of its nodes.
  subroutine constrain(e, ns, time, dt, dt_previous)
    class(rigid_body_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time, dt, dt_previous
    real(wp) :: terms(6, size(e%node)), totals(6, size(e%bodies)), f(6), centre(3), rotation(3, 3), factor, work
    integer :: b, k, j
    terms = 0.0_wp
    do b = 1, size(e%bodies)
      if (e%failed(b) == 0 .and. time >= e%welds(b)%time) then   ! its failure time: free from this step
        e%failed(b) = 1
        e%failed_at(b) = time
      end if
      if (e%failed(b) /= 0) cycle
      do k = e%first(b), e%first(b + 1) - 1
        j = e%node(k)
        if (ns%weight(j) == 0.0_wp) cycle
        f = ns%f_ext(:, j) - ns%f_int(:, j)
        terms(1:3, k) = f(1:3)
        terms(4:6, k) = cross(ns%x(:, j) - e%bodies(b)%centre, f(1:3)) + f(4:6)
      end do
    end do
    call reduce(e, terms, totals)
    if (e%force_criteria) then
      e%v_free(1:3, :) = ns%v(:, e%node)
      e%v_free(4:6, :) = ns%w(:, e%node)
    end if
    do b = 1, size(e%bodies)
      if (e%failed(b) /= 0) cycle
      centre = e%bodies(b)%centre
      rotation = e%bodies(b)%rotation
      factor = 1.0_wp
      if (e%curve(b) > 0) factor = curve_value(e%curves, e%curve(b), time + 0.5_wp * dt)
      e%bodies(b)%target = merge(e%velocity(:, b) * factor, 0.0_wp, e%prescribed(:, b) /= 0)
      call body_advance(e%bodies(b), totals(1:3, b), totals(4:6, b), 0.5_wp * (dt_previous + dt), dt, work)
      if (e%rank == 0) e%work = e%work + work
      call carry_nodes(e%bodies(b), centre, rotation, e%offset(:, e%first(b):e%first(b + 1) - 1), &
                       e%node(e%first(b):e%first(b + 1) - 1), dt, ns%v, ns%w)
    end do
    if (e%force_criteria) call check_welds(e, ns, time, 0.5_wp * (dt_previous + dt))
    if (e%strain_criteria) call check_weld_strains(e, ns, time)
  end subroutine constrain

  !> The welds whose shells' plastic strain reached their failure plastic strain let their nodes
  !> go from the next step: the largest of ns%eps_p (each rank's shells around each node it holds)
  !> over the weld's nodes and over the ranks (a maximum: exact), so every rank decides alike.
  subroutine check_weld_strains(e, ns, time)
    type(rigid_body_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(in) :: ns
    real(wp), intent(in) :: time
    real(wp) :: most(size(e%bodies))
    integer :: b, n_ranks
    most = 0.0_wp
    do b = 1, size(e%bodies)
      if (e%failed(b) /= 0 .or. e%first(b + 1) == e%first(b)) cycle
      most(b) = maxval(ns%eps_p(e%node(e%first(b):e%first(b + 1) - 1)))
    end do
    call MPI_Comm_size(e%comm, n_ranks)
    if (n_ranks > 1) call MPI_Allreduce(MPI_IN_PLACE, most, size(most), MPI_DOUBLE_PRECISION, MPI_MAX, e%comm)
    do b = 1, size(e%bodies)
      if (e%failed(b) /= 0 .or. .not. weld_strain_failed(e%welds(b), most(b))) cycle
      e%failed(b) = 1
      e%failed_at(b) = time
    end do
  end subroutine check_weld_strains

  !> The welds whose force reached their failure surface in this step let their nodes go: the
  !> force is the one the constraint applied to the weld's node, m (v - v_free) / h, summed exactly
  !> over the ranks (its owner alone gives it), so every rank decides alike. A weld that fails
  !> gives its nodes back their free velocities of this step: they move freely from this step on.
  subroutine check_welds(e, ns, time, h)
    type(rigid_body_effect_t), intent(inout) :: e
    type(nodal_state_t), intent(inout) :: ns
    real(wp), intent(in) :: time, h
    real(wp) :: terms(3, size(e%node)), totals(3, size(e%bodies))
    integer :: b, k, j
    terms = 0.0_wp
    do b = 1, size(e%bodies)
      k = e%failure_entry(b)
      if (k == 0 .or. e%failed(b) /= 0) cycle
      j = e%node(k)
      terms(:, k) = ns%mass(j) * (ns%v(:, j) - e%v_free(1:3, k)) / h
    end do
    call reduce(e, terms, totals)
    do b = 1, size(e%bodies)
      if (e%failed(b) /= 0 .or. .not. weld_has_force_criterion(e%welds(b))) cycle
      if (weld_criterion(e%welds(b), totals(:, b), e%bodies(b)%rotation) < 1.0_wp) cycle
      e%failed(b) = 1
      e%failed_at(b) = time
      do k = e%first(b), e%first(b + 1) - 1
        ns%v(:, e%node(k)) = e%v_free(1:3, k)
        ns%w(:, e%node(k)) = e%v_free(4:6, k)
      end do
    end do
  end subroutine check_welds

  !> How many bodies have let their nodes go (the same on every rank).
  pure integer function failures(e) result(n)
    class(rigid_body_effect_t), intent(in) :: e
    n = count(e%failed /= 0)
  end function failures

  !> The bodies' motion, the same on every rank, for a checkpoint.
  function state_words(e) result(words)
    class(rigid_body_effect_t), intent(in) :: e
    real(wp), allocatable :: words(:)
    integer :: b
    allocate (words(0))
    do b = 1, size(e%bodies)
      associate (x => e%bodies(b))
        words = [words, x%centre, reshape(x%rotation, [9]), x%velocity, x%momentum, x%omega, &
                 real(e%failed(b), wp), e%failed_at(b)]
      end associate
    end do
  end function state_words

  !> The bodies' motion from a checkpoint's words (state_words).
  subroutine restore_state(e, words)
    class(rigid_body_effect_t), intent(inout) :: e
    real(wp), intent(in) :: words(:)
    integer :: b, o
    do b = 1, size(e%bodies)
      o = (b - 1) * state_per_body
      e%bodies(b)%centre = words(o + 1:o + 3)
      e%bodies(b)%rotation = reshape(words(o + 4:o + 12), [3, 3])
      e%bodies(b)%velocity = words(o + 13:o + 15)
      e%bodies(b)%momentum = words(o + 16:o + 18)
      e%bodies(b)%omega = words(o + 19:o + 21)
      e%failed(b) = nint(words(o + 22))
      e%failed_at(b) = words(o + 23)
    end do
  end subroutine restore_state

  pure logical function acts_at(e, stage)
    class(rigid_body_effect_t), intent(in) :: e
    integer, intent(in) :: stage
    acts_at = stage == stage_constraints
  end function acts_at

  !> A body's node moves with the whole body: its mass for the contact's stability cap is the
  !> body's (a node's own lumped share would cap the penalty of a heavy body's contact far below
  !> what stops it, and let it sink into what it hits when the step is set by other elements).
  pure subroutine carried_mass(e, mass)
    class(rigid_body_effect_t), intent(in) :: e
    real(wp), intent(inout) :: mass(:)
    integer :: b, k
    do b = 1, size(e%bodies)
      if (e%failed(b) /= 0) cycle
      do k = e%first(b), e%first(b + 1) - 1
        mass(e%node(k)) = max(mass(e%node(k)), e%bodies(b)%mass)
      end do
    end do
  end subroutine carried_mass

end module rigid_body_effect
